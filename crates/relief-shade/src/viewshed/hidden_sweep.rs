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

use relief_core::{DVec3, HeightField, Surface};

/// Direction bins of the sweep.
pub const BINS: usize = 1 << 15;

/// How much a unit's interval of pseudo-angles (0 to 4 round the circle) is shrunk at each
/// end: far more than their rounding, far less than a bin.
const ANGLE_MARGIN: f64 = 1e-9;

/// The pseudo-angle of direction (`x`, `y`) in [0, 4): 0 east, 1 north, 2 west, 3 south,
/// growing counterclockwise with the angle.
#[inline]
fn diamond_angle(x: f64, y: f64) -> f64 {
    if y >= 0.0 {
        if x >= 0.0 {
            y / (x + y)
        } else {
            1.0 - x / (y - x)
        }
    } else if x < 0.0 {
        2.0 - y / (-x - y)
    } else {
        3.0 + x / (x - y)
    }
}

/// The bin of pseudo-angle `a`.
#[inline]
fn bin_of(a: f64) -> usize {
    ((a * (BINS as f64 / 4.0)) as usize).min(BINS - 1)
}

/// One sweep's inputs: the field, its surface, the eye, the margin.
struct Sweep<'a> {
    field: &'a HeightField,
    surface: Surface,
    eye: DVec3,
    margin: f64,
}

/// Per sample (row-major), whether the segment from `eye` to the sample's target point is
/// proven to pass inside the solid of `surface` of `field` (see the module's documentation).
/// `target(col, row)` is the target point, `None` for a sample not asked about (a void, or
/// out of the radius).
pub fn proven_hidden<T: Fn(usize, usize) -> Option<DVec3> + Sync>(
    field: &HeightField,
    surface: Surface,
    eye: DVec3,
    target: &T,
) -> Vec<bool> {
    let g = field.geometry();
    let lo = f64::from(field.min_sample()) * g.z_scale;
    let hi = f64::from(field.max_sample()) * g.z_scale;
    let margin = 1e-6 * (lo.abs().max(hi.abs()).max(eye.z.abs()) + (hi - lo));
    let sweep = Sweep { field, surface, eye, margin };
    // The directions north of the eye (pseudo-angles 0 to 2) and south of it (2 to 4) share
    // no bin: two sweeps side by side, each over its half of the grid.
    let (mut north, south) =
        rayon::join(|| sweep.half(0..BINS / 2, target), || sweep.half(BINS / 2..BINS, target));
    for (a, b) in north.iter_mut().zip(south) {
        *a |= b;
    }
    north
}

impl Sweep<'_> {
    /// [`proven_hidden`] for the targets whose direction's bin lies in `bins` (half of them),
    /// from the units over those bins.
    fn half<T: Fn(usize, usize) -> Option<DVec3> + Sync>(
        &self,
        bins: std::ops::Range<usize>,
        target: &T,
    ) -> Vec<bool> {
        let (field, eye) = (self.field, self.eye);
        let g = field.geometry();
        let (w, h) = (field.width(), field.height());
        // The eye's texel; rings of texels around it.
        let ce = (((eye.x - g.origin.x) / g.dx).max(0.0) as usize).min(w - 1);
        let re = (((eye.y - g.origin.y) / g.dy).max(0.0) as usize).min(h - 1);
        let rings = ce.max(w - 1 - ce).max(re).max(h - 1 - re) + 1;
        // The rows whose units and targets can lie in the half (with a margin of rows).
        let rows = if bins.start == 0 { re.saturating_sub(2)..h } else { 0..(re + 3).min(h) };

        let mut bounds = vec![f64::NEG_INFINITY; BINS];
        let mut hidden = vec![false; w * h];
        // Rings of units already in the bins.
        let mut units_in = 0;
        let chunk = (rings / 64).clamp(1, RING_CHUNK);
        for first_ring in (0..rings).step_by(chunk) {
            // Every unit at least RING_LAG rings nearer than the chunk's first targets.
            let units_to = first_ring.saturating_sub(RING_LAG - 1);
            let annulus = Annulus { ce, re, w, h, rows: rows.clone() };
            annulus.visit(units_in..units_to, |c, r| {
                if let Some(unit) = self.unit(c, r) {
                    let (first, last) = (unit.first.max(bins.start), unit.last.min(bins.end));
                    for bound in bounds.get_mut(first..last).unwrap_or_default() {
                        *bound = bound.max(unit.bound);
                    }
                }
            });
            units_in = units_in.max(units_to);
            let targets = first_ring..(first_ring + chunk).min(rings);
            annulus.visit(targets, |c, r| {
                let Some(t) = target(c, r) else { return };
                let (dx, dy) = (t.x - eye.x, t.y - eye.y);
                let d = (dx * dx + dy * dy).sqrt();
                let bin = bin_of(diamond_angle(dx, dy));
                if d > 0.0 && bins.contains(&bin) {
                    let slope = (t.z - eye.z) / d;
                    hidden[c + r * w] = slope < bounds[bin];
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
    /// Calls `visit(col, row)` for every texel whose ring lies in `rings`, row by row from the
    /// south, west to east.
    #[inline]
    fn visit(&self, rings: std::ops::Range<usize>, mut visit: impl FnMut(usize, usize)) {
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
                cols(ce.saturating_sub(outer), ce + outer).for_each(|c| visit(c, r));
            } else {
                if let Some(inner) = ce.checked_sub(rings.start) {
                    cols(ce.saturating_sub(outer), inner).for_each(|c| visit(c, r));
                }
                cols(ce + rings.start, ce + outer).for_each(|c| visit(c, r));
            }
        }
    }
}

/// What a unit adds to the sweep.
struct UnitEntry {
    /// Its bound `l` on the slope of lines of sight.
    bound: f64,
    /// The bins it covers whole, `first..last`.
    first: usize,
    last: usize,
}

impl Sweep<'_> {
    /// The unit whose south-west sample is (`c`, `r`) (texel (`c`, `r`) for `boxes`), or
    /// `None` for one that does not exist, touches a hole or the eye, lies across the cut of
    /// the pseudo-angles (east of the eye) or covers no bin whole.
    fn unit(&self, c: usize, r: usize) -> Option<UnitEntry> {
        let field = self.field;
        let g = field.geometry();
        let (w, h) = (field.width(), field.height());
        let z = |c: usize, r: usize| f64::from(field.sample(c, r)) * g.z_scale;
        let (x0, y0, zmin) = match self.surface {
            Surface::Triangles => {
                if c + 1 >= w || r + 1 >= h {
                    return None;
                }
                let corners = [(c, r), (c + 1, r), (c, r + 1), (c + 1, r + 1)];
                if corners.iter().any(|&(c, r)| field.is_hole(c, r)) {
                    return None;
                }
                let zmin = corners.iter().map(|&(c, r)| z(c, r)).fold(f64::INFINITY, f64::min);
                (c as f64 + 0.5, r as f64 + 0.5, zmin)
            }
            Surface::Boxes => {
                if field.is_hole(c, r) {
                    return None;
                }
                (c as f64, r as f64, z(c, r))
            }
        };
        let (x0, y0) = (g.origin.x + x0 * g.dx - self.eye.x, g.origin.y + y0 * g.dy - self.eye.y);
        let (x1, y1) = (x0 + g.dx, y0 + g.dy);
        let (near_x, near_y) = (x0.max(0.0).max(-x1), y0.max(0.0).max(-y1));
        let dmin = (near_x * near_x + near_y * near_y).sqrt();
        // The cut of the pseudo-angles runs east of the eye.
        if dmin <= 0.0 || (x1 > 0.0 && y0 <= 0.0 && y1 >= 0.0) {
            return None;
        }
        let (far_x, far_y) = (x0.abs().max(x1.abs()), y0.abs().max(y1.abs()));
        let dmax = (far_x * far_x + far_y * far_y).sqrt();
        // The directions the unit covers run from one corner to the opposite one; which two,
        // by the quadrant it lies in (all four where it straddles an axis).
        let (lo, hi) = if x0 >= 0.0 && y0 >= 0.0 {
            (diamond_angle(x1, y0), diamond_angle(x0, y1))
        } else if x1 <= 0.0 && y0 >= 0.0 {
            (diamond_angle(x1, y1), diamond_angle(x0, y0))
        } else if x1 <= 0.0 && y1 <= 0.0 {
            (diamond_angle(x0, y1), diamond_angle(x1, y0))
        } else if x0 >= 0.0 && y1 <= 0.0 {
            (diamond_angle(x0, y0), diamond_angle(x1, y1))
        } else {
            let angles = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| diamond_angle(x, y));
            let lo = angles.iter().copied().fold(f64::INFINITY, f64::min);
            (lo, angles.iter().copied().fold(f64::NEG_INFINITY, f64::max))
        };
        let (lo, hi) = (lo + ANGLE_MARGIN, hi - ANGLE_MARGIN);
        let scale = BINS as f64 / 4.0;
        // Both are >= 0: `as` truncates, the floor.
        let lo_bins = (lo * scale).max(0.0);
        let first = lo_bins as usize + usize::from(lo_bins.fract() > 0.0);
        let last = ((hi * scale).max(0.0) as usize).min(BINS);
        if first >= last {
            return None;
        }
        let rise = zmin - self.margin - self.eye.z;
        let bound = if rise >= 0.0 { rise / dmax } else { rise / dmin };
        Some(UnitEntry { bound, first, last })
    }
}
