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

    /// `D` of every block, row by row along x as [`SunShadows::bound_at`] reads them: the
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

    /// The sweep, in place over the blocks' `widened` maxima (as
    /// [`SunShadows::widened_block_maxima`] lays them out): `U` of every block, with the ray
    /// rising `rise` per block along the dominant axis.
    pub(super) fn sweep(&self, mut bound: Vec<f32>, rise: f64) -> Vec<f32> {
        // Rows of the sweep, and blocks in a row.
        let (major_len, n) = if self.major_is_x {
            (self.blocks_x, self.blocks_y)
        } else {
            (self.blocks_y, self.blocks_x)
        };
        // Block `J` of row `I` of the sweep (`I` along the dominant axis, `J` along the other,
        // both mirrored) is `bound[origin + I * i_step + J * j_step]`: the sweep's rows are
        // rows of `bound`, or its columns when x is the dominant axis.
        let (blocks_x, blocks_y) = (self.blocks_x as isize, self.blocks_y as isize);
        let (x_first, x_step) = if self.flip_x { (blocks_x - 1, -1) } else { (0, 1) };
        let (y_first, y_step) =
            if self.flip_y { ((blocks_y - 1) * blocks_x, -blocks_x) } else { (0, blocks_x) };
        let (i_step, j_step) = if self.major_is_x { (x_step, y_step) } else { (y_step, x_step) };
        let origin = x_first + y_first;
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
            let first = origin + i as isize * i_step;
            let at = |j: usize| (first + j as isize * j_step) as usize;
            for (j, d) in here[..n].iter_mut().enumerate() {
                *d = bound[at(j)];
            }
            for j in 0..n {
                let s = here[j].max(here[j + 1]).max(there[j]).max(there[j + 1]) as f64;
                let u = s.max(NOTHING).max(next[j].max(next[j + 1]) - rise);
                current[j] = u;
                bound[at(j)] = (u + u.abs() * (1.0 / 4194304.0) + 1e-44) as f32;
            }
            std::mem::swap(&mut next, &mut current);
            std::mem::swap(&mut there, &mut here);
        }
        bound
    }
}
