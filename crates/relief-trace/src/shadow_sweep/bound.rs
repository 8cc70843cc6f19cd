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
        bx + by * self.blocks_x
    }

    /// The blocks' values of `swept` (in sweep order: row `I` along the dominant axis,
    /// mirrored, holds the blocks `J` along the other, mirrored) row by row along x.
    pub(super) fn unmirrored(&self, swept: &[f32]) -> Vec<f32> {
        let (blocks_x, blocks_y) = (self.blocks_x, self.blocks_y);
        let mut bound = vec![0.0; swept.len()];
        bound.par_chunks_mut(blocks_x).enumerate().for_each(|(by, row)| {
            let my = if self.flip_y { blocks_y - 1 - by } else { by };
            for (bx, out) in row.iter_mut().enumerate() {
                let mx = if self.flip_x { blocks_x - 1 - bx } else { bx };
                let (i, j) = if self.major_is_x { (mx, my) } else { (my, mx) };
                *out = swept[i * self.minor_len + j];
            }
        });
        bound
    }

    /// `D` of every block in sweep order: the highest sample any cell of the block, widened
    /// by one cell on every side, reads.
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
        // Rows of blocks, mirrored along both axes as the sweep has them: down the sample
        // rows first (whole rows at a time), then along the row.
        let mut widened = vec![f32::NEG_INFINITY; blocks_x * blocks_y];
        widened.par_chunks_mut(blocks_x).enumerate().for_each_init(
            || vec![f32::NEG_INFINITY; w],
            |column_max, (my, out)| {
                let by = if self.flip_y { blocks_y - 1 - my } else { my };
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
                    let mx = if self.flip_x { blocks_x - 1 - bx } else { bx };
                    out[mx] = d;
                }
            },
        );
        if !self.major_is_x {
            return widened;
        }
        // Rows of the sweep run along y: transpose, in tiles that stay in cache.
        const TILE: usize = 32;
        let mut transposed = vec![f32::NEG_INFINITY; blocks_x * blocks_y];
        transposed.par_chunks_mut(TILE * blocks_y).enumerate().for_each(|(ti, band)| {
            let rows = band.len() / blocks_y;
            for j0 in (0..blocks_y).step_by(TILE) {
                for j in j0..(j0 + TILE).min(blocks_y) {
                    let source =
                        &widened[j * blocks_x + ti * TILE..j * blocks_x + ti * TILE + rows];
                    for (r, &v) in source.iter().enumerate() {
                        band[r * blocks_y + j] = v;
                    }
                }
            }
        });
        transposed
    }

    /// The sweep, in place over the blocks' `widened` maxima in sweep order: `U` of every
    /// block, with the ray rising `rise` per block along the dominant axis.
    pub(super) fn sweep(&self, mut bound: Vec<f32>, major_len: usize, rise: f64) -> Vec<f32> {
        let n = self.minor_len;
        // From the sun's side: U(I, J) = max(S(I, J), max(U(I+1, J), U(I+1, J+1)) - rise) with
        // S the largest D over {I, I+1} x {J, J+1}. In f64, with a finite stand-in for minus
        // infinity (past the last J, and before the first row) so that the stored value can
        // be rounded up without branches: raised by a relative 2^-22, more than the f32
        // rounding takes off.
        const NOTHING: f64 = -1e300;
        let mut next = vec![NOTHING; n + 1];
        let mut current = vec![NOTHING; n + 1];
        // D of the row on the sun's side (before the sweep overwrote it), and of this one.
        let mut there = vec![f32::NEG_INFINITY; n + 1];
        let mut here = vec![f32::NEG_INFINITY; n + 1];
        for i in (0..major_len).rev() {
            let out = &mut bound[i * n..(i + 1) * n];
            here[..n].copy_from_slice(out);
            for j in 0..n {
                let s = here[j].max(here[j + 1]).max(there[j]).max(there[j + 1]) as f64;
                let u = s.max(NOTHING).max(next[j].max(next[j + 1]) - rise);
                current[j] = u;
                out[j] = (u + u.abs() * (1.0 / 4194304.0) + 1e-44) as f32;
            }
            std::mem::swap(&mut next, &mut current);
            std::mem::swap(&mut there, &mut here);
        }
        bound
    }
}
