//! The height field as the horizon lanes read it: padded, signed, and turned so that every
//! line advances at least as many columns as rows, stored column by column (a frame column's
//! samples side by side), so that [`LANES`] neighbouring samples of a column are one vector;
//! and the footprints that let a lane skip a step that cannot raise its horizon.

/// Samples whose horizons are found together, side by side in a column of the frame.
pub(crate) const LANES: usize = 16;

/// The height of the padding around the samples: below any surface, so that no point made
/// from it can set a horizon.
pub(crate) const OUTSIDE: f32 = -1e30;

/// Padding columns on each side: a line is followed while over the samples, and a step reads
/// the column past it.
pub(crate) const PAD_U: usize = 2;

/// Padding rows below and above: a group's last lane lies up to `LANES - 1` rows past the
/// data, and a line is followed until its first lane leaves, reading two rows past its cell.
pub(crate) const PAD_V: usize = LANES + 4;

/// Rows of a lane's footprint: a step's points lie in two cells of a column pair, at most
/// three rows.
const FOOTPRINT_ROWS: usize = 3;

/// Rows of a band window, from two rows below where a band's lines enter a column pair (its
/// lines read rows `floor(c + m u) - 1 ..= floor(c + m u) + 3`, one row of margin below for
/// the rounding of where a band starts).
pub(crate) const BAND_WINDOW_ROWS: usize = 6;

/// The samples times a sign, padded with [`OUTSIDE`], the frame's columns one after the other
/// (the height field's columns if the frame's columns run along x, its rows if `transposed`).
pub(crate) struct LaneFrame {
    /// Padded samples, column after column.
    pub z: Vec<f32>,
    /// Padded samples a column.
    pub stride: usize,
    /// Frame columns and rows, without padding.
    pub width: usize,
    pub height: usize,
    /// Per padded sample, the highest sample of the two columns from it and [`FOOTPRINT_ROWS`]
    /// rows from it up: all that one lane reads in one step.
    pub footprints: Vec<f32>,
}

impl LaneFrame {
    /// The frame of `samples` (`width` x `height`, row-major) times `sign`; its columns are the
    /// height field's columns (lines along x), or its rows if `transposed` (lines along y).
    pub(crate) fn new(
        samples: &[f32],
        width: usize,
        height: usize,
        sign: f32,
        transposed: bool,
    ) -> LaneFrame {
        let (fw, fh) = if transposed { (height, width) } else { (width, height) };
        let stride = fh + 2 * PAD_V;
        let columns = fw + 2 * PAD_U;
        let mut z = vec![OUTSIDE; stride * columns];
        for u in 0..fw {
            let column = &mut z[(u + PAD_U) * stride + PAD_V..][..fh];
            if transposed {
                for (v, &s) in column.iter_mut().zip(&samples[u * width..][..fh]) {
                    *v = sign * s;
                }
            } else {
                for (v_index, v) in column.iter_mut().enumerate() {
                    *v = sign * samples[u + v_index * width];
                }
            }
        }
        let footprints = windows(&z, stride, FOOTPRINT_ROWS);
        LaneFrame { z, stride, width: fw, height: fh, footprints }
    }

    /// Where sample (`u`, `v`) of the frame (column, row) is in [`LaneFrame::z`].
    pub(crate) fn index(&self, u: usize, v: usize) -> usize {
        (u + PAD_U) * self.stride + v + PAD_V
    }

    /// Per padded sample, the highest sample of the two columns from it and
    /// [`BAND_WINDOW_ROWS`] rows from it up: what [`super::band_pyramid::BandPyramid::new`]
    /// reads.
    pub(crate) fn band_windows(&self) -> Vec<f32> {
        windows(&self.z, self.stride, BAND_WINDOW_ROWS)
    }
}

/// Per sample of `z` (`stride` a column), the highest of the block of two columns and `rows`
/// rows from it up and to the right (cut at the edges).
fn windows(z: &[f32], stride: usize, rows: usize) -> Vec<f32> {
    let max = |a: f32, b: f32| if b > a { b } else { a };
    let mut out = z.to_vec();
    // Up each column: windows of 2, 4, ... rows by doubling, then the rest.
    for column in out.chunks_exact_mut(stride) {
        let mut span = 1;
        while 2 * span <= rows {
            for v in 0..stride.saturating_sub(span) {
                column[v] = max(column[v], column[v + span]);
            }
            span *= 2;
        }
        let extra = rows - span;
        if extra > 0 {
            for v in 0..stride.saturating_sub(extra) {
                column[v] = max(column[v], column[v + extra]);
            }
        }
    }
    // With the next column.
    let columns = out.len() / stride;
    for u in 0..columns.saturating_sub(1) {
        let (this, next) = out.split_at_mut((u + 1) * stride);
        for (a, &b) in this[u * stride..].iter_mut().zip(&next[..stride]) {
            *a = max(*a, b);
        }
    }
    out
}
