//! The height field as the horizon lanes read it: padded, signed, and turned so that every
//! line advances at least as many columns as rows; and the maxima that let a group of lanes skip
//! the stretches of their lines that cannot raise their horizons.

/// Samples whose horizons are found together, side by side in a row of the frame.
pub(crate) const LANES: usize = 16;

/// The height of the padding around the samples: below any surface, so that no point made
/// from it can set a horizon.
pub(crate) const OUTSIDE: f32 = -1e30;

/// Padding columns on each side: a group of lanes reads up to `LANES + 1` columns past its
/// last sample's line.
const PAD_X: usize = LANES + 2;

/// Padding rows below and above: a line is followed up to two rows past the data.
const PAD_Y: usize = 3;

/// Bands of lines (one row of offsets wide) per group of [`BandMaxima`].
const GROUP_BANDS: usize = 16;

/// Rows below a group's first band that its window starts at, and rows the window spans: the
/// lines of a group of lanes lie in two consecutive groups' bands and read one row beyond
/// their cells on each side, and a margin covers the rounding of where a band starts.
const WINDOW_BELOW: isize = 2;
const WINDOW_ROWS: usize = 2 * GROUP_BANDS + 6;

/// Columns of the finest node of [`BandMaxima`] (as a power of two).
pub(crate) const FIRST_LEVEL: u32 = 3;

/// The samples times a sign, padded with [`OUTSIDE`], in rows of the frame (the height field's
/// rows, or its columns if `transposed`).
pub(crate) struct LaneFrame {
    /// Padded samples, row-major.
    pub z: Vec<f32>,
    /// Padded samples a row.
    pub stride: usize,
    /// Samples a row and rows, without padding.
    pub width: usize,
    pub height: usize,
    /// Per padded sample, the highest sample of the [`FOOTPRINT_ROWS`] x [`FOOTPRINT_COLS`]
    /// block whose lower left corner it is: all that a group of lanes reads in one step.
    pub footprints: Vec<f32>,
    /// Per padded sample, the highest sample of the [`FOOTPRINT_ROWS`] x 2 block whose lower
    /// left corner it is: all that one lane reads in one step.
    pub lane_footprints: Vec<f32>,
}

/// Rows and columns of a footprint: a step reads up to three rows, and the lanes read
/// `LANES + 1` columns.
const FOOTPRINT_ROWS: usize = 3;
const FOOTPRINT_COLS: usize = LANES + 1;

impl LaneFrame {
    /// The frame of `samples` (`width` x `height`, row-major) times `sign`, rows and columns
    /// swapped if `transposed`.
    pub(crate) fn new(
        samples: &[f32],
        width: usize,
        height: usize,
        sign: f32,
        transposed: bool,
    ) -> LaneFrame {
        let (fw, fh) = if transposed { (height, width) } else { (width, height) };
        let stride = fw + 2 * PAD_X;
        let rows = fh + 2 * PAD_Y;
        let mut z = vec![OUTSIDE; stride * rows];
        for row in 0..fh {
            let line = &mut z[(row + PAD_Y) * stride + PAD_X..][..fw];
            if transposed {
                for (col, v) in line.iter_mut().enumerate() {
                    *v = sign * samples[row + col * width];
                }
            } else {
                for (v, &s) in line.iter_mut().zip(&samples[row * width..][..fw]) {
                    *v = sign * s;
                }
            }
        }
        let lane_footprints = footprints(&z, stride, rows, 2);
        let footprints = footprints(&z, stride, rows, FOOTPRINT_COLS);
        LaneFrame { z, stride, width: fw, height: fh, footprints, lane_footprints }
    }

    /// Where sample (`col`, `row`) of the frame is in [`LaneFrame::z`].
    pub(crate) fn index(&self, col: usize, row: usize) -> usize {
        (row + PAD_Y) * self.stride + col + PAD_X
    }

    fn padded_rows(&self) -> usize {
        self.height + 2 * PAD_Y
    }

    /// Per padded sample, the highest of it and the `WINDOW_ROWS - 1` samples above it: what
    /// [`BandMaxima::new`] reads.
    pub(crate) fn windows(&self) -> Vec<f32> {
        let (stride, rows) = (self.stride, self.padded_rows());
        let mut windows = self.z.clone();
        let mut raise = |span: usize| {
            for r in 0..rows.saturating_sub(span) {
                let (low, high) = windows.split_at_mut((r + span) * stride);
                for (a, &b) in low[r * stride..].iter_mut().zip(&high[..stride]) {
                    *a = if b > *a { b } else { *a };
                }
            }
        };
        // Windows of 2, 4, ..., 32 rows by doubling, then WINDOW_ROWS.
        for span in [1, 2, 4, 8, 16, WINDOW_ROWS - 32] {
            raise(span);
        }
        windows
    }
}

/// Per sample of `z` (`stride` a row, `rows` rows), the highest of the block of
/// [`FOOTPRINT_ROWS`] x `cols` samples from it up and to the right (cut at the edges).
fn footprints(z: &[f32], stride: usize, rows: usize, cols: usize) -> Vec<f32> {
    let max = |a: f32, b: f32| if b > a { b } else { a };
    let mut out = z.to_vec();
    // Along the rows: windows of 2, 4, ... columns by doubling, then the rest.
    for row in out.chunks_exact_mut(stride) {
        let mut span = 1;
        while 2 * span <= cols {
            for x in 0..stride.saturating_sub(span) {
                row[x] = max(row[x], row[x + span]);
            }
            span *= 2;
        }
        let extra = cols - span;
        for x in 0..stride.saturating_sub(extra) {
            row[x] = max(row[x], row[x + extra]);
        }
    }
    // Across the rows.
    for r in 0..rows {
        for dr in 1..FOOTPRINT_ROWS.min(rows - r) {
            let (low, high) = out.split_at_mut((r + dr) * stride);
            for (a, &b) in low[r * stride..][..stride].iter_mut().zip(&high[..stride]) {
                *a = max(*a, b);
            }
        }
    }
    out
}

/// For one direction, maxima over the samples that the lines of a group of lanes can read:
/// lines `y = c + slope * x` are grouped by `floor(c)` into bands, bands into groups of
/// [`GROUP_BANDS`]; per group and node of `2^level` columns, the highest sample any line of
/// the group or the next reads there.
pub(crate) struct BandMaxima {
    slope: f64,
    /// Added to `floor(c)` so that every band's index is >= 0.
    offset: i64,
    /// Per level from [`FIRST_LEVEL`]: nodes a group, and the maxima group by group.
    levels: Vec<(usize, Vec<f32>)>,
}

impl BandMaxima {
    /// The maxima of `frame` for lines rising `slope` rows a column.
    pub(crate) fn new(frame: &LaneFrame, windows: &[f32], slope: f64) -> BandMaxima {
        let reach = frame.width + PAD_X + LANES;
        let offset = (slope.abs() * reach as f64).ceil() as i64 + 4;
        let groups = (frame.height + 2 * offset as usize) / GROUP_BANDS + 3;
        let stride = frame.stride;
        let rows = frame.padded_rows() as i64;
        let nodes = stride.div_ceil(1 << FIRST_LEVEL);
        let mut first = vec![OUTSIDE; groups * nodes];
        for (g, maxima) in first.chunks_exact_mut(nodes).enumerate() {
            let band = (g * GROUP_BANDS) as i64 - offset;
            for (x, column) in (0..stride).enumerate() {
                let c = x as f64 - PAD_X as f64;
                let start =
                    (band as f64 + slope * c).floor() as i64 - WINDOW_BELOW as i64 + PAD_Y as i64;
                let top = start + WINDOW_ROWS as i64 - 1;
                if top < 0 || start >= rows {
                    continue;
                }
                let v = windows[start.max(0) as usize * stride + column];
                let node = &mut maxima[x >> FIRST_LEVEL];
                *node = if v > *node { v } else { *node };
            }
        }
        let mut levels = vec![(nodes, first)];
        while let Some((n, below)) = levels.last().filter(|(n, _)| *n > 1) {
            let (n, up) = (*n, n.div_ceil(2));
            let mut above = vec![OUTSIDE; groups * up];
            for g in 0..groups {
                for j in 0..n {
                    let (v, node) = (below[g * n + j], &mut above[g * up + j / 2]);
                    *node = if v > *node { v } else { *node };
                }
            }
            levels.push((up, above));
        }
        BandMaxima { slope, offset, levels }
    }

    /// The group of the lines from samples `first_col..first_col + LANES` of row `row`.
    pub(crate) fn group(&self, first_col: usize, row: usize) -> usize {
        let c = |col: usize| row as f64 - self.slope * col as f64;
        let lowest = c(first_col).min(c(first_col + LANES - 1));
        (lowest.floor() as i64 + self.offset) as usize / GROUP_BANDS
    }

    /// The highest sample that lines of `group` read in frame columns `from..=to` (which may
    /// reach into the padding).
    pub(crate) fn highest(&self, group: usize, from: isize, to: isize) -> f32 {
        let (a, b) = ((from + PAD_X as isize) as usize, (to + PAD_X as isize) as usize);
        let span = (b - a + 1) as u32;
        let level = (span.ilog2().max(FIRST_LEVEL) - FIRST_LEVEL) as usize;
        let level = level.min(self.levels.len() - 1);
        let (n, values) = &self.levels[level];
        let shift = level as u32 + FIRST_LEVEL;
        let row = &values[group * n..][..*n];
        let (lo, hi) = (a >> shift, (b >> shift).min(n - 1));
        row[lo..=hi].iter().fold(OUTSIDE, |m, &v| if v > m { v } else { m })
    }
}
