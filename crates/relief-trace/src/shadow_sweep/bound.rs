//! The sweep along the sun's azimuth: each block's bound on the height of the terrain's shadow.

use super::*;

impl<T: Tracer> SunShadows<T> {
    /// The swept bound `U` of the block holding cell (cx, cy).
    #[inline]
    pub(super) fn bound_at(&self, cx: usize, cy: usize) -> f32 {
        self.bound[self.bound_index(cx, cy)]
    }

    /// Where [`SunShadows::bound_at`] of cell (cx, cy) is stored.
    #[inline]
    pub(super) fn bound_index(&self, cx: usize, cy: usize) -> usize {
        let (bx, by) = match self.block_shift {
            Some(shift) => (cx >> shift, cy >> shift),
            None => (cx / self.block, cy / self.block),
        };
        bx * self.stride_x + by * self.stride_y
    }

    /// `D` of every block (see the module documentation), laid out as the bound: read from
    /// the wrapped tracer's max mipmap where that holds them (blocks of `2^l` cells over a
    /// `triangles` surface without holes, whose `D` is not widened: level `l`'s nodes), else
    /// computed from the samples.
    pub(super) fn block_maxima(&self) -> Vec<f32> {
        let level = self.block_shift.unwrap_or(0) as usize;
        let mipmap = self.inner.max_mipmap().filter(|m| {
            self.fast_triangles
                && level >= 1
                && level <= m.top_level()
                && m.nodes(0) == (self.grid.cells_x(), self.grid.cells_y())
                && m.nodes(level) == (self.blocks_x, self.blocks_y)
        });
        if let Some(mipmap) = mipmap {
            // The sweep's rows, each along the minor axis.
            let (rows, row_len) = if self.major_is_x {
                (self.blocks_x, self.blocks_y)
            } else {
                (self.blocks_y, self.blocks_x)
            };
            let mut maxima = vec![f32::NEG_INFINITY; rows * row_len];
            maxima.par_chunks_mut(row_len).enumerate().for_each(|(r, row)| {
                for (k, d) in row.iter_mut().enumerate() {
                    let (bx, by) = if self.major_is_x { (r, k) } else { (k, r) };
                    *d = mipmap.node(level, bx, by);
                }
            });
            return maxima;
        }
        let widened = self.widened_block_maxima();
        if self.stride_x == 1 {
            return widened;
        }
        let mut maxima = vec![f32::NEG_INFINITY; widened.len()];
        maxima.par_chunks_mut(self.blocks_y).enumerate().for_each(|(bx, column)| {
            for (by, d) in column.iter_mut().enumerate() {
                *d = widened[bx + by * self.blocks_x];
            }
        });
        maxima
    }

    /// `D` of every block, row by row along x (block `(bx, by)` at `bx + by * blocks_x`): the
    /// highest sample any cell of the block, widened by one cell on every side, reads.
    pub(super) fn widened_block_maxima(&self) -> Vec<f32> {
        let (b, w) = (self.block, self.field.width());
        let reach = match self.grid.surface() {
            Surface::Boxes => 0,
            Surface::Triangles => 1,
        };
        // The samples read by the cells of block `k` widened by one cell, along one axis; not
        // widened over a continuous surface (see the module documentation).
        let widen = !self.fast_triangles as usize;
        let samples_of = |k: usize, cells: usize| {
            let first = (k * b).saturating_sub(widen);
            let last = ((k + 1) * b + widen - 1).min(cells - 1) + reach;
            first..=last
        };
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (blocks_x, blocks_y) = (self.blocks_x, self.blocks_y);
        let samples = self.field.samples();
        // Row by row of blocks: down the sample rows first (whole rows at a time), then along
        // the row.
        let mut widened = vec![f32::NEG_INFINITY; blocks_x * blocks_y];
        widened.par_chunks_mut(blocks_x).enumerate().for_each_init(
            || vec![f32::NEG_INFINITY; w],
            |column_max, (by, out)| {
                column_max.fill(f32::NEG_INFINITY);
                for r in samples_of(by, cells_y) {
                    for (m, &v) in column_max.iter_mut().zip(&samples[r * w..(r + 1) * w]) {
                        *m = m.max(v);
                    }
                }
                for (bx, m) in column_max
                    .chunks(b)
                    .map(|c| c.iter().fold(f32::NEG_INFINITY, |a, &v| a.max(v)))
                    .enumerate()
                    .take(blocks_x)
                {
                    let range = samples_of(bx, cells_x);
                    let (first, last) = (*range.start(), *range.end());
                    // The block's own samples, and those just outside it that its widened cells read.
                    let mut d = m;
                    for c in (first..bx * b).chain((bx + 1) * b..=last) {
                        d = d.max(column_max[c]);
                    }
                    out[bx] = d;
                }
            },
        );
        widened
    }

    /// The sweep, in place over the blocks' maxima `D` (as [`SunShadows::block_maxima`] lays
    /// them out): `U` of every block, with the ray rising `rise` per block along the dominant
    /// axis.
    pub(super) fn sweep(&self, mut bound: Vec<f32>, rise: f64) -> Vec<f32> {
        // Rows of the sweep (along the dominant axis), blocks in a row, and whether each index
        // is mirrored. Row `I` of the sweep (`I` along the dominant axis, `J` along the other,
        // both mirrored so that the sun lies towards growing `I` and `J`) is stored row `I`
        // (or `rows - 1 - I`) of `bound`, block `J` at `J` (or `n - 1 - J`) in it.
        let (rows, n, flip_i, flip_j) = if self.major_is_x {
            (self.blocks_x, self.blocks_y, self.flip_x, self.flip_y)
        } else {
            (self.blocks_y, self.blocks_x, self.flip_y, self.flip_x)
        };
        debug_assert_eq!(self.stride_x.min(self.stride_y), 1, "the sweep's rows are contiguous");
        // From the sun's side: U(I, J) = max(S(I, J), max(U(I+1, J), U(I+1, J+1)) - rise) with
        // S the largest D over {I, I+1} x {J, J+1}. In f64, with a finite stand-in for minus
        // infinity (past the last J, and before the first row) so that the stored value can
        // be rounded up without branches: raised by a relative 2^-22, more than the f32
        // rounding takes off.
        const NOTHING: f64 = -1e300;
        let mut next = vec![NOTHING; n + 1];
        let mut current = vec![NOTHING; n + 1];
        // D of the row on the sun's side (before the sweep overwrote it), and of this one, in
        // the order of J.
        let mut there = vec![f32::NEG_INFINITY; n + 1];
        let mut here = vec![f32::NEG_INFINITY; n + 1];
        let mut stored = vec![0.0f32; n];
        for i in (0..rows).rev() {
            let r = if flip_i { rows - 1 - i } else { i };
            let row = &mut bound[r * n..(r + 1) * n];
            if flip_j {
                here[..n].iter_mut().zip(row.iter().rev()).for_each(|(d, &v)| *d = v);
            } else {
                here[..n].copy_from_slice(row);
            }
            for j in 0..n {
                let s = here[j].max(here[j + 1]).max(there[j]).max(there[j + 1]) as f64;
                let u = s.max(NOTHING).max(next[j].max(next[j + 1]) - rise);
                current[j] = u;
                stored[j] = (u + u.abs() * (1.0 / 4194304.0) + 1e-44) as f32;
            }
            if flip_j {
                row.iter_mut().rev().zip(&stored).for_each(|(d, &v)| *d = v);
            } else {
                row.copy_from_slice(&stored);
            }
            std::mem::swap(&mut next, &mut current);
            std::mem::swap(&mut there, &mut here);
        }
        bound
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MipmapTracer, NaiveTracer};
    use relief_core::GridGeometry;

    #[test]
    fn maxima_read_from_the_mipmap_sweep_as_those_from_the_samples() {
        // Sizes that are and are not multiples of the block, suns along every axis and
        // diagonal (both layouts, every mirroring).
        for (w, h) in [(23, 17), (33, 33), (9, 40)] {
            let samples = (0..w * h).map(|k| ((k * 7919) % 101) as f32 * 0.37).collect();
            let field = Arc::new(HeightField::new(w, h, samples, GridGeometry::unit()).unwrap());
            let mipmap = MipmapTracer::new(field.clone(), Surface::Triangles);
            let naive = NaiveTracer::new(field.clone(), Surface::Triangles);
            for (x, y) in [(1.0, 0.2), (-1.0, 0.5), (0.3, 1.0), (-0.4, -1.0), (1.0, -1.0)] {
                let sun = DVec3::new(x, y, 0.7);
                for block in [2, 4, 8] {
                    let read = SunShadows::with_block(&mipmap, field.clone(), sun, block).unwrap();
                    let computed =
                        SunShadows::with_block(&naive, field.clone(), sun, block).unwrap();
                    assert!(read.inner.max_mipmap().is_some() && naive.max_mipmap().is_none());
                    assert_eq!(read.block_maxima(), computed.block_maxima(), "{w}x{h} {sun}");
                    assert_eq!(read.bound, computed.bound, "{w}x{h} {sun} block {block}");
                }
            }
        }
    }
}
