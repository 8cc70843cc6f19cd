//! Samples proven hidden from one eye without tracing: a sweep outward from the eye that keeps,
//! per narrow bin of compass directions, a lower bound of the elevation angle of the terrain
//! crossed so far.
//!
//! # The bound
//!
//! Work in horizontal distance `s` from the eye `E` and the slope `g = (T.z - E.z) / D` of the
//! line of sight to a target `T` at horizontal distance `D`: the segment is at height
//! `E.z + s g` over the point at distance `s` on its way.
//!
//! A *unit* is a piece of the footprint over which the surface is at least a known height
//! `zmin`: for `triangles`, the square between four neighbouring samples (each triangle's
//! heights are averages of its corners', so at least their minimum); for `boxes`, a texel's
//! footprint (its top, or higher on its edges where a taller neighbour stands). A unit touching
//! a hole has no such bound and is left out. Seen from `E`, a unit whose footprint does not
//! contain `E` covers a closed interval of directions; a line of sight whose direction lies in
//! it crosses the unit at some distance `s` in `[dmin, dmax]`, the unit's nearest and farthest
//! horizontal distances. When every point of the unit is nearer the eye than the target in the
//! norm `max(|x| / dx, |y| / dy)` (which grows along a line of sight), that crossing lies on
//! the segment, and the segment is below the surface there by more than a margin `m` whenever
//! `g < l`, with
//! `l = (zmin - m - E.z) / dmax` if the numerator is at least 0, else over `dmin`.
//!
//! The directions are split into [`BINS`] bins, equal steps of a pseudo-angle that grows with
//! the angle (the "diamond angle", no trigonometry). A unit raises the bound `L[b]` of every
//! bin `b` it covers whole (its interval shrunk by a hair for rounding) to at
//! least its `l`. Targets are visited by rings of texels around the eye's texel, a few rings
//! at a time (`RING_CHUNK`), and a unit enters the bins at least `RING_LAG` rings before
//! the targets that use it, when every point of it is nearer than they are in that norm. A target whose slope is below `L` of its
//! direction's bin is then hidden: its segment passes more than `m`
//! inside the solid at a point of some unit, which every exact tracer finds. The margin (a
//! millionth of the heights' magnitude and range) is far above the rounding of any tracer.
//! Every other target is left to the tracer.

use super::target_points::TargetPoints;
use super::unit_runs::Runs;
use relief_core::{DVec3, HeightField, Surface};

/// Direction bins of the sweep.
pub const BINS: usize = 1 << 15;

/// How much a unit's interval of pseudo-angles (0 to 4 round the circle) is shrunk at each
/// end: far more than their rounding, far less than a bin.
pub(crate) const ANGLE_MARGIN: f64 = 1e-9;

/// One sweep's inputs: the field, its surface, the eye, the margin.
pub(crate) struct Sweep<'a> {
    pub field: &'a HeightField,
    pub surface: Surface,
    pub eye: DVec3,
    pub margin: f64,
}

/// Per sample (row-major), whether the segment from `eye` to the sample's target point is
/// proven to pass inside the solid of `surface` of `field` (see the module's documentation).
/// `targets` are the target points (none for a sample not asked about: a void, or out of the
/// radius).
pub(crate) fn proven_hidden(
    field: &HeightField,
    surface: Surface,
    eye: DVec3,
    targets: &TargetPoints,
) -> Vec<bool> {
    let g = field.geometry();
    let lo = f64::from(field.min_sample()) * g.z_scale;
    let hi = f64::from(field.max_sample()) * g.z_scale;
    let margin = 1e-6 * (lo.abs().max(hi.abs()).max(eye.z.abs()) + (hi - lo));
    let sweep = Sweep { field, surface, eye, margin };
    // The directions north of the eye (pseudo-angles 0 to 2) and south of it (2 to 4) share
    // no bin: two sweeps side by side, each over its half of the grid.
    let (mut north, south) =
        rayon::join(|| sweep.half(0..BINS / 2, targets), || sweep.half(BINS / 2..BINS, targets));
    for (a, b) in north.iter_mut().zip(south) {
        *a |= b;
    }
    north
}

impl Sweep<'_> {
    /// [`proven_hidden`] for the targets whose direction's bin lies in `bins` (half of them),
    /// from the units over those bins.
    fn half(&self, bins: std::ops::Range<usize>, targets: &TargetPoints) -> Vec<bool> {
        let (field, eye) = (self.field, self.eye);
        let g = field.geometry();
        let (w, h) = (field.width(), field.height());
        // The eye's texel; rings of texels around it.
        let ce = (((eye.x - g.origin.x) / g.dx).max(0.0) as usize).min(w - 1);
        let re = (((eye.y - g.origin.y) / g.dy).max(0.0) as usize).min(h - 1);
        let rings = ce.max(w - 1 - ce).max(re).max(h - 1 - re) + 1;
        // The rows whose units and targets can lie in the half (with a margin of rows).
        let rows = if bins.start == 0 { re.saturating_sub(2)..h } else { 0..(re + 3).min(h) };

        let mut runs = Runs::default();
        let mut bounds = vec![f64::NEG_INFINITY; BINS];
        let mut hidden = vec![false; w * h];
        // Rings of units already in the bins.
        let mut units_in = 0;
        let chunk = (rings / 64).clamp(1, RING_CHUNK);
        for first_ring in (0..rings).step_by(chunk) {
            // Every unit at least RING_LAG rings nearer than the chunk's first targets.
            let units_to = first_ring.saturating_sub(RING_LAG - 1);
            let annulus = Annulus { ce, re, w, h, rows: rows.clone() };
            annulus.visit(units_in..units_to, |r, cols| {
                runs.units(self, r, cols);
                for unit in &runs.units {
                    let first = (unit.first as usize).max(bins.start);
                    let last = (unit.last as usize).min(bins.end);
                    for bound in bounds.get_mut(first..last).unwrap_or_default() {
                        *bound = bound.max(unit.bound);
                    }
                }
            });
            units_in = units_in.max(units_to);
            let rings_decided = first_ring..(first_ring + chunk).min(rings);
            annulus.visit(rings_decided, |r, cols| {
                runs.targets(self, r, cols, targets);
                for t in &runs.targets {
                    if bins.contains(&t.bin) {
                        hidden[t.index] = t.slope < bounds[t.bin];
                    }
                }
            });
        }
        hidden
    }
}

/// How many rings of texels a unit waits, at least, before it enters the bins: the unit
/// whose south-west sample is `j` rings from the eye's texel reaches at most `j + 1.5` texels
/// from the eye along either axis, and a sample `k` rings away lies at least `k - 0.5` away,
/// so with `k >= j + 3` every point of the unit is nearer in that norm. The norm grows along
/// a line of sight, so the unit's crossing with it lies before the target.
const RING_LAG: usize = 3;

/// Rings of targets decided together, visited row by row (so that the memory is read in
/// order); their units enter the bins before the chunk's first ring is decided.
const RING_CHUNK: usize = 32;

/// The texels of a `w` x `h` grid in rings around texel (`ce`, `re`) (a texel's ring is the
/// larger of its column's and row's distance), within `rows`.
struct Annulus {
    ce: usize,
    re: usize,
    w: usize,
    h: usize,
    rows: std::ops::Range<usize>,
}

impl Annulus {
    /// Calls `visit(row, cols)` for every run of texels whose ring lies in `rings`, row by row
    /// from the south, west to east.
    #[inline]
    fn visit(
        &self,
        rings: std::ops::Range<usize>,
        mut visit: impl FnMut(usize, std::ops::Range<usize>),
    ) {
        if rings.is_empty() {
            return;
        }
        let Annulus { ce, re, w, h, .. } = *self;
        let outer = rings.end - 1;
        let cols = |from: usize, to: usize| from..(to + 1).min(w);
        let first = re.saturating_sub(outer).max(self.rows.start);
        for r in first..(re + outer + 1).min(h).min(self.rows.end) {
            let dr = r.abs_diff(re);
            if dr >= rings.start {
                visit(r, cols(ce.saturating_sub(outer), ce + outer));
            } else {
                if let Some(inner) = ce.checked_sub(rings.start) {
                    visit(r, cols(ce.saturating_sub(outer), inner));
                }
                visit(r, cols(ce + rings.start, ce + outer));
            }
        }
    }
}
