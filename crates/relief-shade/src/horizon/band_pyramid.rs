//! Per family of parallel lines, the highest sample each band of lines can read over each
//! stretch of columns: what lets every lane of a group skip, at once and each by its own
//! bound, the stretches of its line that cannot raise its horizon.

use super::lane_frame::{LaneFrame, BAND_WINDOW_ROWS, LANES, OUTSIDE, PAD_U, PAD_V};

/// Columns of the finest node (as a power of two), at least.
pub(crate) const BASE_LEVEL: u32 = 5;

/// For the lines `v = c + slope * u` of a frame, grouped by `floor(c)` into bands (one row of
/// offsets wide): per node of `2^level` columns and per band, the highest sample a line of
/// the band reads between two columns of the node. The lanes of a group are the samples of
/// [`LANES`] consecutive rows of one column, so their lines lie in consecutive bands: their
/// bounds over a node are one vector of the node's row.
pub(crate) struct BandPyramid {
    slope: f64,
    /// Columns of the finest node (as a power of two): [`BASE_LEVEL`], or more where the
    /// memory allowed needs it.
    base_level: u32,
    /// The band of entry 0 of a node's row.
    first_band: i64,
    /// Entries a node's row: every band a group's lanes can lie in, and a vector past the last.
    row_len: usize,
    /// Per level from [`BASE_LEVEL`]: the node rows one after the other.
    levels: Vec<Vec<f32>>,
}

impl BandPyramid {
    /// The pyramid of `frame`'s lines rising `slope` rows a column (at most 1 in magnitude),
    /// from the frame's [`LaneFrame::band_windows`], in at most `bytes_per_sample` bytes per
    /// sample of the frame.
    pub(crate) fn new(
        frame: &LaneFrame,
        windows: &[f32],
        slope: f64,
        bytes_per_sample: f64,
    ) -> BandPyramid {
        let (width, height, stride) = (frame.width, frame.height, frame.stride);
        let reach = slope * width.saturating_sub(1) as f64;
        let low = (-reach).min(0.0).floor() as i64 - 2;
        let high = (height + LANES) as f64 + (-reach).max(0.0);
        let first_band = low;
        let row_len = (high.ceil() as i64 + 2 - low) as usize + LANES;
        let cells = width.saturating_sub(1).max(1);
        // The levels together hold about twice the finest: 8 bytes a band and finest node.
        let finest_columns = 8.0 * row_len as f64 / (bytes_per_sample * height.max(1) as f64);
        let base_level = BASE_LEVEL.max(finest_columns.log2().ceil().max(0.0) as u32);
        let nodes = cells.div_ceil(1 << base_level);
        let mut base = vec![OUTSIDE; nodes * row_len];
        let below = BAND_WINDOW_ROWS as i64 / 2 - 1;
        for (n, row) in base.chunks_exact_mut(row_len).enumerate() {
            let first = n << base_level;
            for u in first..(first + (1 << base_level)).min(cells) {
                let column = &windows[(u + PAD_U) * stride..][..stride];
                // Entry j (band first_band + j) reads the window from padded row j + shift.
                let shift = first_band + (slope * u as f64).floor() as i64 - below + PAD_V as i64;
                let from = (-shift).max(0) as usize;
                let to = ((stride as i64 - shift).max(0) as usize).min(row_len);
                for j in from..to {
                    let v = column[(j as i64 + shift) as usize];
                    row[j] = if v > row[j] { v } else { row[j] };
                }
            }
        }
        let mut levels = vec![base];
        let mut n = nodes;
        while n > 1 {
            let below = levels.last().expect("the base level");
            let up = n.div_ceil(2);
            let mut above = vec![OUTSIDE; up * row_len];
            for (j, row) in below.chunks_exact(row_len).enumerate() {
                for (a, &b) in above[(j / 2) * row_len..][..row_len].iter_mut().zip(row) {
                    *a = if b > *a { b } else { *a };
                }
            }
            levels.push(above);
            n = up;
        }
        BandPyramid { slope, base_level, first_band, row_len, levels }
    }

    /// The entry of the band of the line through frame sample (`u`, `v`): the first lane's of
    /// a group whose lanes are samples `v..v + LANES` of column `u`.
    pub(crate) fn band(&self, u: usize, v: usize) -> usize {
        let c = v as f64 - self.slope * u as f64;
        (c.floor() as i64 - self.first_band) as usize
    }

    /// The finest level.
    pub(crate) fn base_level(&self) -> u32 {
        self.base_level
    }

    /// The highest level: its node covers every column.
    pub(crate) fn top_level(&self) -> u32 {
        self.base_level + self.levels.len() as u32 - 1
    }

    /// Per lane from the band entry `band`, the highest sample its line reads between two
    /// columns of the node of `2^level` columns (`level` from
    /// [`BandPyramid::base_level`] to [`BandPyramid::top_level`]) that holds column `u`.
    #[inline(always)]
    pub(crate) fn bounds(&self, level: u32, u: usize, band: usize) -> &[f32] {
        let nodes = &self.levels[(level - self.base_level) as usize];
        &nodes[(u >> level) * self.row_len + band..][..LANES]
    }
}
