//! The lowest and highest sample of every block of a raster, at every power-of-two scale: what
//! the far field of a window reads to skip the stretches of a line that cannot raise a
//! horizon, without reading their samples.

use std::ops::Range;

/// Samples along a side of the finest block of [`CoarseBounds`].
pub const BOUND_CELL: usize = 16;

/// Per block of `BOUND_CELL x BOUND_CELL` samples (and of 2, 4, ... times that), the lowest and
/// the highest sample of a raster: a few bytes per thousand samples.
#[derive(Debug, Clone, PartialEq)]
pub struct CoarseBounds {
    width: usize,
    height: usize,
    /// Per level from the finest: blocks a row, and per block (row-major) its lowest and
    /// highest sample.
    levels: Vec<(usize, Vec<[f32; 2]>)>,
}

impl CoarseBounds {
    /// Bounds of a `width x height` raster whose finest blocks are given by `block`: for the
    /// block at (`block_col`, `block_row`) (samples `BOUND_CELL` times that on), the lowest and
    /// highest of its samples (voids left out; `[inf, -inf]` for none).
    pub fn new(
        width: usize,
        height: usize,
        block: impl Fn(usize, usize) -> [f32; 2] + Sync,
    ) -> CoarseBounds {
        use rayon::prelude::*;
        let (cols, rows) = (width.div_ceil(BOUND_CELL).max(1), height.div_ceil(BOUND_CELL).max(1));
        let finest: Vec<[f32; 2]> =
            (0..cols * rows).into_par_iter().map(|k| block(k % cols, k / cols)).collect();
        let mut levels = vec![(cols, finest)];
        loop {
            let (cols, below) = levels.last().expect("one level at least");
            let rows = below.len() / cols;
            if *cols == 1 && rows == 1 {
                break;
            }
            let (up_cols, up_rows) = (cols.div_ceil(2), rows.div_ceil(2));
            let mut above = vec![[f32::INFINITY, f32::NEG_INFINITY]; up_cols * up_rows];
            for (k, &[low, high]) in below.iter().enumerate() {
                let node = &mut above[(k % cols) / 2 + (k / cols) / 2 * up_cols];
                node[0] = node[0].min(low);
                node[1] = node[1].max(high);
            }
            levels.push((up_cols, above));
        }
        CoarseBounds { width, height, levels }
    }

    /// The bounds of the samples of a row-major `width x height` grid (NaN a void).
    pub fn of_samples(samples: &[f32], width: usize, height: usize) -> CoarseBounds {
        CoarseBounds::new(width, height, |bc, br| {
            let cols = bc * BOUND_CELL..((bc + 1) * BOUND_CELL).min(width);
            let rows = br * BOUND_CELL..((br + 1) * BOUND_CELL).min(height);
            block_bounds(rows.flat_map(|r| &samples[r * width + cols.start..r * width + cols.end]))
        })
    }

    /// Samples a row and rows of the raster.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// At most the lowest and at least the highest sample of columns `cols` and rows `rows`
    /// (both within the raster, not empty).
    #[inline]
    pub fn span(&self, cols: Range<usize>, rows: Range<usize>) -> [f32; 2] {
        let (c0, c1) = (cols.start / BOUND_CELL, (cols.end - 1) / BOUND_CELL);
        let (r0, r1) = (rows.start / BOUND_CELL, (rows.end - 1) / BOUND_CELL);
        // The level at which the rectangle spans at most 3 blocks each way.
        let mut level = 0;
        while level + 1 < self.levels.len()
            && ((c1 >> level) - (c0 >> level) > 2 || (r1 >> level) - (r0 >> level) > 2)
        {
            level += 1;
        }
        let (n, blocks) = &self.levels[level];
        let mut span = [f32::INFINITY, f32::NEG_INFINITY];
        for r in r0 >> level..=r1 >> level {
            for &[low, high] in &blocks[r * n + (c0 >> level)..=r * n + (c1 >> level)] {
                span[0] = span[0].min(low);
                span[1] = span[1].max(high);
            }
        }
        span
    }

    /// Bytes the bounds hold.
    pub fn bytes(&self) -> u64 {
        self.levels.iter().map(|(_, b)| b.len() as u64 * 8).sum()
    }
}

/// The lowest and highest of `samples`, voids (NaN) left out.
pub fn block_bounds<'a>(samples: impl Iterator<Item = &'a f32>) -> [f32; 2] {
    samples.fold([f32::INFINITY, f32::NEG_INFINITY], |[low, high], &v| {
        if v.is_nan() {
            [low, high]
        } else {
            [low.min(v), high.max(v)]
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_span_holds_every_sample_of_its_rectangle() {
        let (w, h) = (301, 170);
        let samples: Vec<f32> =
            (0..w * h).map(|k| ((k * 7919) % 1009) as f32 - ((k / w) as f32).sqrt()).collect();
        let bounds = CoarseBounds::of_samples(&samples, w, h);
        for (cols, rows) in [(0..w, 0..h), (5..6, 7..8), (31..33, 0..64), (100..290, 40..169)] {
            let [low, high] = bounds.span(cols.clone(), rows.clone());
            let samples = &samples;
            let values = rows.flat_map(|r| cols.clone().map(move |c| samples[c + r * w]));
            let (lo, hi) =
                values.fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
            assert!(low <= lo && high >= hi);
        }
        assert_eq!(
            bounds.span(0..w, 0..h),
            [
                samples.iter().copied().fold(f32::INFINITY, f32::min),
                samples.iter().copied().fold(f32::NEG_INFINITY, f32::max)
            ]
        );
    }
}
