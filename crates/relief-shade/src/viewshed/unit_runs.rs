//! The sweep's units and targets a run of one row at a time: the same quantities as one by
//! one ([`super::hidden_sweep`] says what they are), in loops over the run that the compiler
//! turns into vector code, with each corner's direction found once for the units on either
//! side of it. The divisions and square roots that dominate the sweep run eight at a time in
//! AVX-512 registers where the processor has them (chosen at run time; the same IEEE
//! operations either way, so the same bits).

use super::hidden_sweep::{Sweep, ANGLE_MARGIN, BINS};
use super::target_points::TargetPoints;
use relief_core::Surface;

/// The pseudo-angle of direction (`x`, `y`) in [0, 4): 0 east, 1 north, 2 west, 3 south,
/// growing counterclockwise with the angle ("diamond angle", no trigonometry). Without
/// branches: the quadrant's base plus the share of `|x| + |y|` turned past it.
#[inline(always)]
pub(crate) fn diamond_angle(x: f64, y: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let (base, turned) = match (y >= 0.0, x >= 0.0) {
        (true, true) => (0.0, ay),
        (true, false) => (1.0, ax),
        (false, false) => (2.0, ay),
        (false, true) => (3.0, ax),
    };
    base + turned / (ax + ay)
}

/// The bin of pseudo-angle `a`.
#[inline(always)]
pub(crate) fn bin_of(a: f64) -> usize {
    ((a * (BINS as f64 / 4.0)) as usize).min(BINS - 1)
}

/// What a unit adds to the sweep: its bound on the slope of lines of sight, and the bins it
/// covers whole, `first..last`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct UnitEntry {
    pub bound: f64,
    pub first: u32,
    pub last: u32,
}

/// A target of the sweep: its sample's index, its bin, and the slope of its line of sight.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TargetEntry {
    pub index: usize,
    pub bin: usize,
    pub slope: f64,
}

/// Scratch space of the runs, reused from run to run.
#[derive(Default)]
pub(crate) struct Runs {
    /// Per corner of the run, its direction from the eye at the run's lower and upper edge.
    lower: Vec<f64>,
    upper: Vec<f64>,
    /// Per corner, its x from the eye.
    corner_x: Vec<f64>,
    /// Per unit, its lowest height (NaN where it has none).
    lowest: Vec<f64>,
    /// Per unit, its bound, its first and last bin, and whether it enters the bins.
    bound: Vec<f64>,
    first: Vec<u32>,
    last: Vec<u32>,
    kept: Vec<bool>,
    /// The units of the last run that cover a bin.
    pub units: Vec<UnitEntry>,
    /// The targets of the last run.
    pub targets: Vec<TargetEntry>,
    target_x: Vec<f64>,
    target_y: Vec<f64>,
    target_z: Vec<f64>,
    /// The sample index of the run's first target (the others follow it).
    target_first: usize,
    /// Per target, its line of sight's slope (NaN where it has no direction) and its bin.
    target_slope: Vec<f64>,
    target_bin: Vec<u32>,
}

impl Runs {
    /// Fills [`Runs::units`] with the units of row `r` whose south-west sample (texel, for
    /// `boxes`) lies in `cols` and that cover a bin whole.
    #[allow(unsafe_code)]
    pub(crate) fn units(&mut self, g: &Sweep, r: usize, cols: std::ops::Range<usize>) {
        #[cfg(target_arch = "x86_64")]
        if wide() {
            // SAFETY: the processor has AVX-512 F and VL (checked just above).
            return unsafe { self.units_wide(g, r, cols) };
        }
        self.units_body(g, r, cols)
    }

    /// Fills [`Runs::targets`] with the targets of row `r` in `cols` that `points` gives.
    #[allow(unsafe_code)]
    pub(crate) fn targets(
        &mut self,
        g: &Sweep,
        r: usize,
        cols: std::ops::Range<usize>,
        points: &TargetPoints,
    ) {
        for v in [&mut self.target_x, &mut self.target_y, &mut self.target_z] {
            v.clear();
        }
        self.target_first = cols.start + r * g.field.width();
        #[cfg(target_arch = "x86_64")]
        if wide() {
            // SAFETY: the processor has AVX-512 F and VL (checked just above).
            return unsafe { self.targets_wide(g, r, cols, points) };
        }
        self.targets_body(g, r, cols, points)
    }

    #[inline(always)]
    fn units_body(&mut self, g: &Sweep, r: usize, cols: std::ops::Range<usize>) {
        self.units.clear();
        let field = g.field;
        let geometry = field.geometry();
        let (w, h) = (field.width(), field.height());
        let (offset, cols) = match g.surface {
            Surface::Triangles if r + 1 < h => (0.5, cols.start..cols.end.min(w - 1)),
            Surface::Triangles => return,
            Surface::Boxes => (0.0, cols),
        };
        if cols.is_empty() {
            return;
        }
        prefetch_run(field.samples(), w, r + 1 + ROWS_AHEAD, cols.start..cols.end + 1);
        let n = cols.len();
        // The lowest height of each unit.
        self.lowest.clear();
        let zs = geometry.z_scale;
        match g.surface {
            Surface::Triangles => {
                let row = |r: usize| &field.samples()[r * w + cols.start..][..=n];
                let (below, above) = (row(r), row(r + 1));
                self.lowest.resize(n, 0.0);
                for (i, low) in self.lowest.iter_mut().enumerate() {
                    let z = |v: f32| f64::from(v) * zs;
                    let (a, b) = (z(below[i]), z(below[i + 1]));
                    let (c, d) = (z(above[i]), z(above[i + 1]));
                    *low = f64::INFINITY.min(a).min(b).min(c).min(d);
                }
                if field.holes().is_some() {
                    for (low, c) in self.lowest.iter_mut().zip(cols.clone()) {
                        let corners = [(c, r), (c + 1, r), (c, r + 1), (c + 1, r + 1)];
                        if corners.iter().any(|&(c, r)| field.is_hole(c, r)) {
                            *low = f64::NAN;
                        }
                    }
                }
            }
            Surface::Boxes => {
                for c in cols.clone() {
                    let z = f64::from(field.sample(c, r)) * zs;
                    self.lowest.push(if field.is_hole(c, r) { f64::NAN } else { z });
                }
            }
        }
        // The corners' directions, each found once for the units on either side.
        let y0 = geometry.origin.y + (r as f64 + offset) * geometry.dy - g.eye.y;
        let y1 = y0 + geometry.dy;
        self.corner_x.clear();
        self.corner_x.extend((0..=n).map(|j| {
            geometry.origin.x + ((cols.start + j) as f64 + offset) * geometry.dx - g.eye.x
        }));
        self.lower.clear();
        self.lower.extend(self.corner_x.iter().map(|&x| diamond_angle(x, y0)));
        self.upper.clear();
        self.upper.extend(self.corner_x.iter().map(|&x| diamond_angle(x, y1)));
        let near_y = y0.max(0.0).max(-y1);
        let far_y = y0.abs().max(y1.abs());
        let crosses_cut_row = y0 <= 0.0 && y1 >= 0.0;
        let scale = BINS as f64 / 4.0;
        // Every unit's numbers first (a loop without branches, in vectors), then the units
        // that count.
        self.bound.clear();
        self.bound.resize(n, 0.0);
        for v in [&mut self.first, &mut self.last] {
            v.clear();
            v.resize(n, 0);
        }
        self.kept.clear();
        self.kept.resize(n, false);
        let (x, lower, upper) = (&self.corner_x[..=n], &self.lower[..=n], &self.upper[..=n]);
        let (lowest, bound) = (&self.lowest[..n], &mut self.bound[..n]);
        let (first, last, kept) = (&mut self.first[..n], &mut self.last[..n], &mut self.kept[..n]);
        for i in 0..n {
            let (x0, x1) = (x[i], x[i + 1]);
            let near_x = x0.max(0.0).max(-x1);
            let dmin = (near_x * near_x + near_y * near_y).sqrt();
            let far_x = x0.abs().max(x1.abs());
            let dmax = (far_x * far_x + far_y * far_y).sqrt();
            // The directions the unit covers run between its corners' extremes (it does not
            // lie across the cut east of the eye, which is checked below).
            let (a, b, c, d) = (lower[i], lower[i + 1], upper[i], upper[i + 1]);
            let lo = a.min(b).min(c.min(d)) + ANGLE_MARGIN;
            let hi = a.max(b).max(c.max(d)) - ANGLE_MARGIN;
            let lo_bins = (lo * scale).max(0.0);
            let from = lo_bins as u32 + u32::from(lo_bins.fract() > 0.0);
            let to = ((hi * scale).max(0.0) as u32).min(BINS as u32);
            let rise = lowest[i] - g.margin - g.eye.z;
            bound[i] = rise / if rise >= 0.0 { dmax } else { dmin };
            (first[i], last[i]) = (from, to);
            kept[i] = dmin > 0.0 && !(x1 > 0.0 && crosses_cut_row) && !rise.is_nan() && from < to;
        }
        for i in 0..n {
            if kept[i] {
                self.units.push(UnitEntry { bound: bound[i], first: first[i], last: last[i] });
            }
        }
    }

    #[inline(always)]
    fn targets_body(
        &mut self,
        g: &Sweep,
        r: usize,
        cols: std::ops::Range<usize>,
        points: &TargetPoints,
    ) {
        points.run(r, cols, g.eye, [&mut self.target_x, &mut self.target_y, &mut self.target_z]);
        self.targets.clear();
        let n = self.target_x.len();
        self.target_slope.clear();
        self.target_slope.resize(n, 0.0);
        self.target_bin.clear();
        self.target_bin.resize(n, 0);
        let (x, y, z) = (&self.target_x[..n], &self.target_y[..n], &self.target_z[..n]);
        let (slopes, bins) = (&mut self.target_slope[..n], &mut self.target_bin[..n]);
        for i in 0..n {
            let (dx, dy) = (x[i], y[i]);
            let d = (dx * dx + dy * dy).sqrt();
            bins[i] = bin_of(diamond_angle(dx, dy)) as u32;
            slopes[i] = if d > 0.0 { z[i] / d } else { f64::NAN };
        }
        for i in 0..n {
            if !slopes[i].is_nan() {
                let (index, bin, slope) = (self.target_first + i, bins[i] as usize, slopes[i]);
                self.targets.push(TargetEntry { index, bin, slope });
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx2")]
    fn units_wide(&mut self, g: &Sweep, r: usize, cols: std::ops::Range<usize>) {
        self.units_body(g, r, cols);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx2")]
    fn targets_wide(
        &mut self,
        g: &Sweep,
        r: usize,
        cols: std::ops::Range<usize>,
        points: &TargetPoints,
    ) {
        self.targets_body(g, r, cols, points);
    }
}

/// Rows ahead of the one being visited whose samples a run asks the processor to fetch: the
/// sweep visits the rows in order, a short run of each, too scattered for the hardware to
/// guess.
pub(crate) const ROWS_AHEAD: usize = 2;

/// A hint that the samples `cols` of row `row` of `samples` (`width` a row; any row, in
/// bounds or not) will be read soon.
#[inline(always)]
#[allow(unsafe_code)]
pub(crate) fn prefetch_run(
    samples: &[f32],
    width: usize,
    row: usize,
    cols: std::ops::Range<usize>,
) {
    #[cfg(target_arch = "x86_64")]
    {
        let base = samples.as_ptr().wrapping_add(row.wrapping_mul(width));
        // One hint a cache line of 16 samples, and the run's last.
        for c in cols.clone().step_by(16).chain(cols.end.checked_sub(1)) {
            // SAFETY: prefetching is a hint that never faults and reads nothing into the
            // program; SSE is part of x86-64.
            unsafe {
                use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
                _mm_prefetch::<_MM_HINT_T0>(base.wrapping_add(c) as *const i8);
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (samples, width, row, cols);
}

/// Whether the processor has the AVX-512 the wide runs are compiled for.
#[cfg(target_arch = "x86_64")]
fn wide() -> bool {
    std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("avx512vl")
}
