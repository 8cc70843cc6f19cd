//! The horizons of [`LANES`] neighbouring samples of a frame column at once: their lines are
//! the same line translated by whole rows, so they cross the surface at the same points of a
//! [`Stencil`], each lane reading its own samples side by side (one vector load for all). The
//! lanes walk the stencil together, each skipping by its own bound what cannot raise its
//! horizon: long stretches by the [`BandPyramid`] (the lanes' lines lie in consecutive bands,
//! so their bounds are one vector), eight steps and single steps by the frame's footprints;
//! the rest they test point by point, exactly.

use super::band_pyramid::BandPyramid;
use super::lane_frame::{LaneFrame, LANES, OUTSIDE};
use super::lane_vector::{LaneVector, Portable};
use super::march::Corners;
use super::stencil::{Coefficients, RadiusEnd, Stencil, Step, F32_ERROR};

/// The values of the lanes.
type Lanes = [f32; LANES];

/// Slopes below this come from the padding: no surface lies ahead.
const NO_SURFACE: f64 = -1e18;

/// A bound on the relative rounding of a ceiling computed in f32 (four roundings of half an
/// f32 epsilon each, twice that for safety).
const CEILING_ROUNDING: f32 = 4.0 * f32::EPSILON;

/// Steps tested against the footprints at once (as a power of two).
const BLOCK_LEVEL: u32 = 3;

/// One direction of a lanes engine: its line's stencil and the bounds of its line family.
pub(crate) struct LaneDirection {
    /// Whether the direction's frame columns are the height field's rows (lines along y).
    pub transposed: bool,
    pub stencil: Stencil,
    pub pyramid: std::sync::Arc<BandPyramid>,
}

/// What the lanes of one group start from.
pub(crate) struct LaneGroup<'a> {
    pub frame: &'a LaneFrame,
    pub direction: &'a LaneDirection,
    /// The frame column of the lanes' samples, and lane 0's row (lane `i` is in row `v + i`).
    pub u: usize,
    pub v: usize,
    /// Which lanes hold a sample whose horizon is wanted.
    pub wanted: [bool; LANES],
    /// Split along (0,0)-(1,1) where `z00 + z11 <= z10 + z01` of the unsigned samples: with
    /// the samples upside down, where `>=`.
    pub upside_down: bool,
    pub z_scale: f32,
    pub observer_height: f32,
    /// The lowest slope wanted (0 for horizons above the horizontal only), or -infinity.
    pub lowest: f32,
    /// Steps where the horizons of the group one column before lie (0 for none), counted
    /// from this group's column: the lanes' horizons are likely near, so these steps are
    /// tested first. They change how fast the answer is found, never the answer.
    pub hints: [u32; LANES],
}

/// The horizons' slopes of a group's lanes, and the steps that set them (0 where none did).
pub(crate) struct LaneSlopes {
    pub slopes: [f64; LANES],
    pub steps: [u32; LANES],
}

#[inline(always)]
fn offset(base: usize, by: isize) -> usize {
    base.wrapping_add_signed(by)
}

/// The slopes of the points `a + w (b - a)` from the lanes' samples `z0` in f32, and a bound
/// on how far each may lie above the exact slope.
#[inline(always)]
fn edge_slopes<V: LaneVector>(a: V, b: V, w: f32, z0: V, c: Coefficients) -> (V, V) {
    let (da, db) = (a.sub(z0), b.sub(z0));
    let slope = da.add(V::splat(w).mul(db.sub(da))).mul(V::splat(c.scale)).sub(V::splat(c.lift));
    let error = slope.abs().mul(V::splat(F32_ERROR)).add(V::splat(c.error));
    (slope, error)
}

/// The lanes' `z00, z10, z01, z11` corners of the cell whose corner (0, 0) is `corner`
/// from `base` (the next column `stride` on, the next row 1).
#[inline(always)]
fn cell<V: LaneVector>(z: &[f32], base: usize, stride: usize, corner: isize) -> [V; 4] {
    let at = offset(base, corner);
    [V::load(z, at), V::load(z, at + stride), V::load(z, at + 1), V::load(z, at + stride + 1)]
}

/// Per lane, `main` where the cell of corners `c` is split along (0,0)-(1,1), else `other`.
#[inline(always)]
fn by_split<V: LaneVector>(c: &[V; 4], upside_down: bool, main: V, other: V) -> V {
    let [z00, z10, z01, z11] = *c;
    let (sum_main, sum_anti) = (z00.add(z11), z10.add(z01));
    if upside_down {
        V::select_le(sum_anti, sum_main, main, other)
    } else {
        V::select_le(sum_main, sum_anti, main, other)
    }
}

/// Bit `i` set where lane `i`'s cell of corners `c` is split along (0,0)-(1,1).
#[inline(always)]
fn main_mask<V: LaneVector>(c: &[V; 4], upside_down: bool) -> u16 {
    let [z00, z10, z01, z11] = *c;
    let (sum_main, sum_anti) = (z00.add(z11), z10.add(z01));
    if upside_down {
        V::le_mask(sum_anti, sum_main)
    } else {
        V::le_mask(sum_main, sum_anti)
    }
}

/// Whether the cell of corners `z00, z10, z01, z11` is split along (0,0)-(1,1), as
/// [`by_split`] decides it.
#[inline(always)]
pub(crate) fn main_split(z00: f32, z10: f32, z01: f32, z11: f32, upside_down: bool) -> bool {
    let (sum_main, sum_anti) = (z00 + z11, z10 + z01);
    if upside_down {
        sum_anti <= sum_main
    } else {
        sum_main <= sum_anti
    }
}

/// The lanes' best slopes: exact (f64, as the definition computes them) and, for the
/// skipping, each rounded down to f32.
pub(crate) struct Best<V> {
    pub exact: [f64; LANES],
    low: V,
    /// The step whose point set each lane's best (0 for none).
    pub steps: [u32; LANES],
}

impl<V: LaneVector> Best<V> {
    /// The best slopes `exact` (NaN in a lane that nothing may raise).
    #[inline(always)]
    pub(crate) fn new(exact: [f64; LANES]) -> Best<V> {
        Best { exact, low: V::round_down(&exact), steps: [0; LANES] }
    }

    /// The best slopes rounded down to f32.
    #[inline(always)]
    pub(crate) fn low(&self) -> V {
        self.low
    }

    /// Raises each lane to its slope of a point of step `step` where that is larger.
    #[inline(always)]
    fn raise(&mut self, slopes: [f64; LANES], step: u32) {
        if V::raise_exact(&mut self.exact, &mut self.steps, &slopes, step) {
            self.low = V::round_down(&self.exact);
        }
    }
}

/// The exact slopes (f64) of the points `a + w (b - a)`, `a` and `b` read from `z` at
/// `at_a` and `at_b` for lane 0.
#[inline(always)]
fn exact_edge<V: LaneVector>(
    z: &[f32],
    at_a: usize,
    at_b: usize,
    w: f64,
    c: &Coefficients,
    z0: &[f64; LANES],
) -> [f64; LANES] {
    V::exact_slopes(z, at_a, at_b, [w, c.scale64, c.lift64], z0)
}

/// Raises the lanes' `best` slopes to the steepest over the points of `step`: each point in
/// f32 first, and exactly where it may raise a lane.
#[inline(always)]
pub(crate) fn test_step<V: LaneVector>(grid: &Grid<V>, step: &Step, j: u32, best: &mut Best<V>) {
    let Grid { z, base, stride, upside_down, z0, ref z0_exact } = *grid;
    for e in &step.edges {
        let (at_a, at_b) = (offset(base, e.a), offset(base, e.b));
        let (slope, error) =
            edge_slopes(V::load(z, at_a), V::load(z, at_b), e.w, z0, e.coefficients);
        if V::any_greater(slope.add(error), best.low) {
            best.raise(exact_edge::<V>(z, at_a, at_b, e.w64, &e.coefficients, z0_exact), j);
        }
    }
    for d in &step.diagonals {
        let c = cell::<V>(z, base, stride, d.corner);
        let [z00, z10, z01, z11] = c;
        let (main, main_error) = edge_slopes(z00, z11, d.main as f32, z0, d.main_coefficients);
        let (anti, anti_error) = edge_slopes(z01, z10, d.anti as f32, z0, d.anti_coefficients);
        let slope = by_split(&c, upside_down, main.add(main_error), anti.add(anti_error));
        if V::any_greater(slope, best.low) {
            let at = offset(base, d.corner);
            let on_main =
                exact_edge::<V>(z, at, at + stride + 1, d.main, &d.main_coefficients, z0_exact);
            let on_anti =
                exact_edge::<V>(z, at + 1, at + stride, d.anti, &d.anti_coefficients, z0_exact);
            best.raise(V::select_exact(main_mask(&c, upside_down), &on_main, &on_anti), j);
        }
    }
}

/// Raises the lanes' `best` slopes to the exact slope of the line's end at a radius.
#[inline(always)]
fn test_end<V: LaneVector>(
    z: &[f32],
    base: usize,
    stride: usize,
    end: &RadiusEnd,
    z0_exact: &[f64; LANES],
    upside_down: bool,
    best: &mut Best<V>,
) {
    let at = offset(base, end.corner);
    let (s, q) = (end.s, end.q);
    let slopes = std::array::from_fn(|i| {
        let (z00, z10) = (z[at + i], z[at + stride + i]);
        let (z01, z11) = (z[at + 1 + i], z[at + stride + 1 + i]);
        let [d00, d10, d01, d11] = [z00, z10, z01, z11].map(|v| f64::from(v) - z0_exact[i]);
        let main_diagonal = main_split(z00, z10, z01, z11, upside_down);
        let rise =
            Corners { z00: d00, z10: d10, z01: d01, z11: d11, main_diagonal }.height_at(s, q);
        rise * end.coefficients.scale64 - end.coefficients.lift64
    });
    best.raise(slopes, end.step as u32);
}

/// Where a group of lanes reads its samples, and the lanes' own samples.
pub(crate) struct Grid<'a, V> {
    pub z: &'a [f32],
    /// Lane 0's sample in `z` (wrapping: it may lie outside `z`, whose points a stencil's
    /// offsets from it reach), and samples a column.
    pub base: usize,
    pub stride: usize,
    pub upside_down: bool,
    /// The lanes' own signed samples, in f32 and f64.
    pub z0: V,
    pub z0_exact: [f64; LANES],
}

impl<V: LaneVector> Grid<'_, V> {
    /// Raises `best` to the steepest slope over the points of step `j` of `steps`.
    #[inline(always)]
    fn test(&self, steps: &[Step], j: usize, best: &mut Best<V>) {
        test_step(self, &steps[j], j as u32, best);
    }
}

impl LaneGroup<'_> {
    /// The steepest slope from each wanted lane's observer to its line's points, at least
    /// `lowest` (`NaN` in lanes not wanted; below [`NO_SURFACE`] where no surface lies ahead).
    #[inline(always)]
    fn slopes<V: LaneVector>(&self) -> LaneSlopes {
        let frame = self.frame;
        let stencil = &self.direction.stencil;
        let pyramid = &*self.direction.pyramid;
        let (z, stride) = (&frame.z[..], frame.stride);
        let base = frame.index(self.u, self.v);
        let z0 = V::load(z, base);
        // Lanes not wanted take the largest slope (nothing raises it) and an infinite
        // ceiling.
        let wanted = self.wanted;
        let start: Lanes = std::array::from_fn(|i| if wanted[i] { self.lowest } else { f32::MAX });
        let mut best =
            Best { exact: start.map(f64::from), low: V::from_array(start), steps: [0; LANES] };
        let unwanted: Lanes = std::array::from_fn(|i| if wanted[i] { 0.0 } else { f32::INFINITY });
        let unwanted = V::from_array(unwanted);
        let last_over_frame = self.last_step();
        let last = last_over_frame.min(stencil.len());
        let steps = &stencil.steps[..];
        let footprints = &frame.footprints[..];
        let z0_exact = std::array::from_fn(|i| f64::from(z[base + i]));
        let grid = Grid { z, base, stride, upside_down: self.upside_down, z0, z0_exact };
        // First the steps where the hints say the horizons are (three of them at most).
        let mut tried = [0; 3];
        for (slot, hint) in [0, LANES / 2, LANES - 1].into_iter().enumerate() {
            let j = self.hints[hint] as usize;
            if j >= 1 && j <= last && !tried.contains(&j) {
                tried[slot] = j;
                grid.test(steps, j, &mut best);
            }
        }
        // The column pair (its first column) that step `k`'s points lie between.
        let (u0, forward) = (self.u, stencil.step_x > 0);
        let column = |k: usize| if forward { u0 + k - 1 } else { u0 - k };
        let band = pyramid.band(u0, self.v);
        let (base_level, top) = (pyramid.base_level(), pyramid.top_level());
        let mut level = (base_level + 1).min(top);
        let (mut k, mut fine_end) = (1, 0);
        while k <= last {
            if k > fine_end {
                // The rest of the node of `2^level` columns that step k is in, against each
                // lane's bound over it.
                let u = column(k);
                let first = (u >> level) << level;
                let to = if forward { k + first + (1 << level) - 1 - u } else { k + u - first };
                let to = to.min(last);
                let bounds = V::load(pyramid.bounds(level, u, band), 0);
                if !V::any_greater(bounds, self.ceiling(z0, unwanted, k, to, best.low)) {
                    k = to + 1;
                    level = (level + 1).min(top);
                } else if level > base_level {
                    level -= 1;
                } else {
                    fine_end = to;
                }
                continue;
            }
            // Eight steps against each lane's footprints of their points, then each step.
            let to = (k + (1 << BLOCK_LEVEL) - 1).min(fine_end);
            let block = &steps[k..=to];
            let footprint = |step: &Step| V::load(footprints, offset(base, step.footprint));
            let highest = block.iter().fold(V::splat(OUTSIDE), |m, s| footprint(s).max(m));
            if V::any_greater(highest, self.ceiling(z0, unwanted, k, to, best.low)) {
                for (j, step) in (k..=to).zip(block) {
                    // A hinted step was tested already: testing it again raises nothing.
                    if V::any_greater(footprint(step), self.ceiling(z0, unwanted, j, j, best.low))
                        && !tried.contains(&j)
                    {
                        grid.test(steps, j, &mut best);
                    }
                }
            }
            k = to + 1;
        }
        if let Some(end) = stencil.end.as_ref().filter(|e| e.step <= last_over_frame) {
            test_end(z, base, stride, end, &grid.z0_exact, self.upside_down, &mut best);
        }
        let mut slopes = best.exact;
        for (b, wanted) in slopes.iter_mut().zip(self.wanted) {
            if !wanted {
                *b = f64::NAN;
            }
        }
        LaneSlopes { slopes, steps: best.steps }
    }

    /// See [`ceiling`].
    #[inline(always)]
    fn ceiling<V: LaneVector>(&self, z0: V, unwanted: V, from: usize, to: usize, best: V) -> V {
        let steps = &self.direction.stencil.steps;
        ceiling(steps, [self.observer_height, self.z_scale], z0, unwanted, from..=to, best)
    }

    /// The last step at which any wanted lane's line is still over the frame.
    fn last_step(&self) -> usize {
        let (frame, stencil) = (self.frame, &self.direction.stencil);
        let across =
            if stencil.step_x > 0 { frame.width.saturating_sub(1 + self.u) } else { self.u };
        let m = stencil.rows_per_step;
        let highest = self.v + (LANES - 1).min(frame.height.saturating_sub(1 + self.v));
        let rows = if m > 0.0 {
            ((frame.height - 1 - self.v) as f64 / m).floor() as usize + 1
        } else if m < 0.0 {
            (highest as f64 / -m).floor() as usize + 1
        } else {
            usize::MAX
        };
        across.min(rows)
    }

    /// The steepest slopes of the lanes' lines (`NaN` where not wanted), and the steps that
    /// set them.
    pub(crate) fn exact_slopes(&self) -> LaneSlopes {
        dispatch(self)
    }
}

/// Per lane, a height at most the highest a point of the steps `stretch` of `steps` may lie
/// without raising the horizon of a lane whose sample is `z0` and best slope so far `best`
/// (`unwanted` is 0 in the lanes wanted, infinite in the others), for an observer
/// `observer_height` over the sample and heights times `z_scale`. A lane's bound is its
/// best line at the stretch's start, or at its end where the line descends.
#[inline(always)]
pub(crate) fn ceiling<V: LaneVector>(
    steps: &[Step],
    [observer_height, z_scale]: [f32; 2],
    z0: V,
    unwanted: V,
    stretch: std::ops::RangeInclusive<usize>,
    best: V,
) -> V {
    let (near, far) = (steps[stretch.start() - 1].distance, steps[*stretch.end()].distance);
    let t = V::select_negative(best, V::splat(far), V::splat(near));
    let rise = best.mul(t).add(V::splat(observer_height));
    let lift = rise.mul(V::splat(1.0 / z_scale));
    // Lowered by more than the rounding of the f32 operations above, so that a point is
    // skipped only where it lies below the exact ceiling: how many points are tested then
    // does not depend on how the stretches fall, and a window's horizons are the whole
    // raster's bit for bit.
    let rounding = z0.abs().add(lift.abs()).mul(V::splat(CEILING_ROUNDING));
    z0.add(lift).sub(rounding).add(unwanted)
}

/// Per lane, the highest of the 2 x 3 samples from `at` in `z` (column-major, `stride`
/// samples a column) that lane's points of a step read: its footprint.
#[inline(always)]
pub(crate) fn footprint<V: LaneVector>(z: &[f32], at: usize, stride: usize) -> V {
    // No closure: one would not inherit the caller's target features.
    let left = V::load(z, at).max(V::load(z, at + 1)).max(V::load(z, at + 2));
    let next = at + stride;
    let right = V::load(z, next).max(V::load(z, next + 1)).max(V::load(z, next + 2));
    left.max(right)
}

/// The horizon angle (radians) of a line's steepest slope: 0 where no surface lies ahead.
#[inline]
pub(crate) fn angle_of(slope: f64) -> f32 {
    if slope < NO_SURFACE {
        0.0
    } else {
        atan(slope as f32)
    }
}

/// The arc tangent of `x` in radians (NaN for NaN), within 2e-7 of it relative (Cephes'
/// `atanf`: a reduction to |x| <= tan(pi/8), then a polynomial); much faster than the
/// library's in f64, and as exact as an `f32` angle is.
#[inline]
fn atan(x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};
    let a = x.abs();
    let (base, y) = if a > 2.414_213_6 {
        (FRAC_PI_2, -1.0 / a)
    } else if a > 0.414_213_57 {
        (FRAC_PI_4, (a - 1.0) / (a + 1.0))
    } else {
        (0.0, a)
    };
    let z = y * y;
    let p = (((8.053_744_5e-2 * z - 1.387_768_6e-1) * z + 1.997_771_1e-1) * z - 3.333_295e-1) * z;
    (base + (p * y + y)).copysign(x)
}

/// [`LaneGroup::slopes`] compiled for the widest vectors the processor has (the same
/// operations in each, no fused multiply-add: the same bits).
#[allow(unsafe_code)]
fn dispatch(group: &LaneGroup) -> LaneSlopes {
    #[cfg(test)]
    if tests::PORTABLE_ONLY.get() {
        return group.slopes::<Portable>();
    }
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor has AVX-512 F (checked just above).
            return unsafe { slopes_avx512(group) };
        }
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above).
            return unsafe { slopes_avx2(group) };
        }
    }
    group.slopes::<Portable>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx2")]
fn slopes_avx512(group: &LaneGroup) -> LaneSlopes {
    group.slopes::<super::lane_vector::Avx512>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn slopes_avx2(group: &LaneGroup) -> LaneSlopes {
    group.slopes::<Portable>()
}

const _: () = assert!((OUTSIDE as f64) < NO_SURFACE);

#[cfg(test)]
pub(crate) mod tests {
    thread_local! {
        /// Whether the lanes run on plain arrays whatever the processor has.
        pub(crate) static PORTABLE_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    }

    #[test]
    fn atan_is_the_library_s_to_2e_7_relative() {
        // From -1e6 to 1e6, densest near 0.
        for i in -15_000..=15_000 {
            let x = ((i as f64) / 1000.0).sinh() as f32;
            let (got, want) = (super::atan(x) as f64, (x as f64).atan());
            assert!((got - want).abs() <= 2e-7 * want.abs(), "atan({x}): {got}, not {want}");
        }
        assert!(super::atan(f32::NAN).is_nan());
        assert_eq!(super::atan(f32::INFINITY), std::f32::consts::FRAC_PI_2);
    }
}
