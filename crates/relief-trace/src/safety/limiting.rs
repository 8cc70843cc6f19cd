//! Limiting triangles (Baboud et al., 6.1 and 6.2): the triangles that bound a texel's safety
//! shape, for all rays or for exterior rays, with or without a viewing-angle bound.
//!
//! Everything is in a class's local frame, for rays of class `x+`. Texel `tau = (i, j)` owns the
//! segment `s_tau` of the x-centerline `i` with `|y - j| <= 1/2`. A triangle `T` is limiting
//! when some ray of the admitted set lies in `T`'s plane, passes strictly above the surface over
//! `s_tau` and reaches `T` (a *limit ray*): tilted, it would hit `T`'s back face.

use super::dual::{HalfPlane, LineSet};
use super::frame::LocalField;
use rayon::prelude::*;
use relief_core::DVec3;
use std::sync::OnceLock;

/// Rows per band of the blocker search's bounds.
const BAND: usize = 16;

/// The plane `z = c + gx x + gy y` of a triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    c: f64,
    gx: f64,
    gy: f64,
}

impl Plane {
    /// The plane through a triangle's three vertices.
    pub fn of(tri: &[DVec3; 3]) -> Plane {
        let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
        let n = e1.cross(e2);
        let (gx, gy) = (-n.x / n.z, -n.y / n.z);
        Plane { c: tri[0].z - gx * tri[0].x - gy * tri[0].y, gx, gy }
    }

    /// Height of the plane at (x, y).
    #[inline]
    pub fn at(&self, x: f64, y: f64) -> f64 {
        self.c + self.gx * x + self.gy * y
    }
}

/// The viewing-angle bound in a local frame: a line of local direction `(1, w)` is admitted
/// when its slope angle is at most `phi_max`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlopeBound {
    /// `tan(phi_max)`.
    pub max_slope: f64,
    /// World length of one local x unit.
    pub step_x: f64,
    /// World length of one local y unit.
    pub step_y: f64,
    /// World height of one sample unit.
    pub z_scale: f64,
}

impl SlopeBound {
    /// The intervals of local slopes `w` in `[-1, 1]` along which a line lying in `plane`
    /// descends steeply enough (widened slightly, so the result only errs on the large side).
    pub fn admitted_slopes(&self, plane: &Plane) -> Vec<(f64, f64)> {
        // f(w) = zs (gx + gy w) - t sqrt(sx^2 + w^2 sy^2) <= 0
        let (t, sx, sy, zs) = (self.max_slope, self.step_x, self.step_y, self.z_scale);
        let f = |w: f64| zs * (plane.gx + plane.gy * w) - t * (sx * sx + w * w * sy * sy).sqrt();
        // Candidate breakpoints: roots of f^2 balance and the zero of the linear part.
        let (a, b) = (zs * plane.gx, zs * plane.gy);
        let (q2, q1, q0) = (b * b - t * t * sy * sy, 2.0 * a * b, a * a - t * t * sx * sx);
        let mut cuts = vec![-1.0, 1.0];
        if b != 0.0 {
            cuts.push(-a / b);
        }
        if q2.abs() > 1e-300 {
            let disc = q1 * q1 - 4.0 * q2 * q0;
            if disc >= 0.0 {
                let r = disc.sqrt();
                cuts.push((-q1 - r) / (2.0 * q2));
                cuts.push((-q1 + r) / (2.0 * q2));
            }
        } else if q1 != 0.0 {
            cuts.push(-q0 / q1);
        }
        cuts.retain(|w| w.is_finite() && (-1.0..=1.0).contains(w));
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let mut intervals: Vec<(f64, f64)> = Vec::new();
        for pair in cuts.windows(2) {
            let (w0, w1) = (pair[0], pair[1]);
            let scale = zs * (plane.gx.abs() + plane.gy.abs()) + t.abs() * (sx + sy);
            let ok = |w: f64| f(w) <= 1e-9 * scale;
            if ok(0.5 * (w0 + w1)) || ok(w0) && ok(w1) {
                match intervals.last_mut() {
                    Some(last) if last.1 >= w0 => last.1 = w1,
                    _ => intervals.push((w0, w1)),
                }
            }
        }
        const WIDEN: f64 = 1e-7;
        intervals.iter().map(|&(a, b)| (a - WIDEN, b + WIDEN)).collect()
    }
}

/// How blocking the terrain is for one triangle's limit rays: computed once per triangle.
#[derive(Debug)]
struct TriangleLines {
    /// The triangle's plane.
    plane: Plane,
    /// Its limit-ray candidates (lines in its plane, class `x+`, crossing it, admitted by the
    /// slope bound, not blocked by the terrain in earlier columns); empty: never limiting.
    lines: LineSet,
}

/// The limiting-triangle test for one ray class.
pub struct LimitingTest<'a> {
    field: LocalField<'a>,
    exterior: bool,
    slope: Option<SlopeBound>,
    /// Per band of `BAND` rows (and the row after), the highest sample in local columns
    /// `0..=x`: `band * width + x`.
    band_prefix_max: Vec<f64>,
    /// A height difference this small is treated as no difference when blocking.
    z_eps: f64,
    /// Per triangle (`2 * (i + j * (width - 1)) + k`), its line set, built on first use
    /// (exterior rays).
    cache: Vec<OnceLock<TriangleLines>>,
    /// Per triangle, the slopes `dy/dx` within `[-1, 1]` along which its plane is admitted by
    /// the viewing-angle bound (all rays with `phi_max`; an empty interval has start > end).
    admitted: Vec<[(f64, f64); 2]>,
}

impl<'a> LimitingTest<'a> {
    /// The test for `field` (a class's local view), for exterior rays or all rays, with an
    /// optional viewing-angle bound.
    pub fn new(field: LocalField<'a>, exterior: bool, slope: Option<SlopeBound>) -> Self {
        let (w, h) = (field.width(), field.height());
        let bands = h.div_ceil(BAND);
        let mut band_prefix_max = vec![f64::NEG_INFINITY; bands * w];
        let mut magnitude = 0.0f64;
        for b in 0..bands {
            let mut top = f64::NEG_INFINITY;
            for i in 0..w {
                for j in b * BAND..((b + 1) * BAND + 1).min(h) {
                    top = top.max(field.h(i, j));
                    magnitude = magnitude.max(field.h(i, j).abs());
                }
                band_prefix_max[b * w + i] = top;
            }
        }
        let triangles = if w > 1 && h > 1 { 2 * (w - 1) * (h - 1) } else { 0 };
        let admitted = match &slope {
            Some(bound) if !exterior => (0..triangles)
                .into_par_iter()
                .map(|t| {
                    let (cell, k) = (t / 2, t % 2);
                    let tri = field.cell_triangles(cell % (w - 1), cell / (w - 1))[k];
                    let mut intervals = bound.admitted_slopes(&Plane::of(&tri));
                    if intervals.len() > 2 {
                        // Never expected; one covering interval only errs on the large side.
                        intervals = vec![(intervals[0].0, intervals[intervals.len() - 1].1)];
                    }
                    let mut out = [(1.0, -1.0); 2];
                    for (o, (w0, w1)) in out.iter_mut().zip(intervals) {
                        *o = (w0.max(-1.0), w1.min(1.0));
                    }
                    out
                })
                .collect(),
            _ => Vec::new(),
        };
        let triangles = if exterior { triangles } else { 0 };
        let cache = (0..triangles).map(|_| OnceLock::new()).collect();
        let z_eps = 1e-9 * (1.0 + magnitude);
        LimitingTest { field, exterior, slope, band_prefix_max, z_eps, cache, admitted }
    }

    /// The local field.
    pub fn field(&self) -> &LocalField<'a> {
        &self.field
    }

    /// Whether triangle `k` (0 or 1) of local cell `(ci, cj)` is limiting for texel `(i, j)`.
    pub fn is_limiting(&self, i: usize, j: usize, ci: usize, cj: usize, k: usize) -> bool {
        let index = 2 * (ci + cj * (self.field.width() - 1)) + k;
        // All rays with a viewing-angle bound: a triangle whose plane no admitted direction lies
        // in cannot be limiting.
        let admitted = self.admitted.get(index);
        if admitted.is_some_and(|intervals| intervals.iter().all(|s| s.0 > s.1)) {
            return false;
        }
        let tri = self.field.cell_triangles(ci, cj)[k];
        let plane = Plane::of(&tri);
        if !self.reachable_above(i, j, &tri, &plane, (-1.0, 1.0)) {
            return false;
        }
        if !self.exterior {
            // All rays: only the viewing-angle bound can narrow the directions that reach T.
            return admitted.is_none_or(|intervals| {
                intervals.iter().any(|&slopes| {
                    slopes.0 <= slopes.1 && self.reachable_above(i, j, &tri, &plane, slopes)
                })
            });
        }
        let lines = self.cache[index].get_or_init(|| self.triangle_lines(ci, &tri, plane));
        self.limit_ray_exists(i, j, lines)
    }

    /// Section 6.1's test: some point of `s_tau` from which `x+` rays reach `T` lies strictly
    /// below `T`'s plane and strictly above the surface. Checking the ends of that part of
    /// `s_tau` and its middle sample suffices: the surface bends only there.
    /// `slopes` bounds the rays' direction `dy/dx`: `(-1, 1)` is the whole class.
    fn reachable_above(
        &self,
        i: usize,
        j: usize,
        tri: &[DVec3; 3],
        plane: &Plane,
        slopes: (f64, f64),
    ) -> bool {
        let x = i as f64;
        let top = (self.field.height() - 1) as f64;
        let mut lo = (j as f64 - 0.5).max(0.0);
        let mut hi = (j as f64 + 0.5).min(top);
        // From y, direction (1, w) meets vertex v when y = v.y - w (v.x - x), v.x >= x.
        let (w0, w1) = slopes;
        let reach_lo = tri.iter().map(|v| v.y - w1 * (v.x - x)).fold(f64::INFINITY, f64::min);
        let reach_hi = tri.iter().map(|v| v.y - w0 * (v.x - x)).fold(f64::NEG_INFINITY, f64::max);
        lo = lo.max(reach_lo);
        hi = hi.min(reach_hi);
        if lo > hi {
            return false;
        }
        let above = |y: f64| plane.at(x, y) - self.field.centerline_height(i, y) > 0.0;
        above(lo) || above(hi) || (lo < j as f64 && (j as f64) < hi && above(j as f64))
    }

    /// The candidate limit rays of a triangle in local column `ci` (section 6.2.1): lines in
    /// its plane crossing it, of class `x+`, within the slope bound, and (for exterior rays)
    /// not passing under the terrain in any earlier column (the blocker traversal, 6.2.3; done
    /// once per triangle, 6.2.6).
    fn triangle_lines(&self, ci: usize, tri: &[DVec3; 3], plane: Plane) -> TriangleLines {
        let x_ref = ci as f64;
        let y_lo = tri.iter().map(|v| v.y).fold(f64::INFINITY, f64::min) - 2.0;
        let y_hi = tri.iter().map(|v| v.y).fold(f64::NEG_INFINITY, f64::max) + 2.0;
        let base = LineSet::rectangle(x_ref, (y_lo, y_hi), (y_lo, y_hi));
        let class = [base.slope_at_least(-1.0), base.slope_at_most(1.0)];
        // Lines crossing the triangle cross its edge (0, 1) or its edge (0, 2).
        let (p0, p1, p2) = (tri[0], tri[1], tri[2]);
        let above = |p: DVec3| base.below_point(p.x, p.y);
        let crossing = |a: DVec3, b: DVec3| -> [[HalfPlane; 4]; 2] {
            [
                [class[0], class[1], above(a), above(b).flipped()],
                [class[0], class[1], above(a).flipped(), above(b)],
            ]
        };
        let (e01, e02) = (crossing(p0, p1), crossing(p0, p2));
        let mut lines = base.split(&[&e01[0], &e01[1], &e02[0], &e02[1]]);
        if let Some(bound) = &self.slope {
            let intervals = bound.admitted_slopes(&plane);
            let alternatives: Vec<[HalfPlane; 2]> = intervals
                .iter()
                .map(|&(w0, w1)| [lines.slope_at_least(w0), lines.slope_at_most(w1)])
                .collect();
            let refs: Vec<&[HalfPlane]> = alternatives.iter().map(|a| &a[..]).collect();
            lines = lines.split(&refs);
        }
        if self.exterior {
            self.remove_blocked(&mut lines, ci, &plane);
        }
        TriangleLines { plane, lines }
    }

    /// Removes the lines that pass under the terrain (where the surface is above the plane)
    /// in local columns before `ci`, scanning columns by decreasing x within the shaft of
    /// remaining lines (6.2.3).
    fn remove_blocked(&self, lines: &mut LineSet, ci: usize, plane: &Plane) {
        let rows = self.field.height() - 1;
        for col in (0..ci).rev() {
            if lines.is_empty() {
                return;
            }
            let (x0, x1) = (col as f64, col as f64 + 1.0);
            // Where the lines stay above every sample of the columns left, nothing can block
            // them any more.
            let lowest = lines
                .vertices()
                .flat_map(|l| [0.0, x1].map(|x| plane.at(x, lines.y_of(l, x))))
                .fold(f64::INFINITY, f64::min);
            let Some((y_lo, y_hi)) = lines.y_range(0.0, x1) else { return };
            if lowest > self.highest_left_of(col + 1, y_lo, y_hi) + self.z_eps {
                return;
            }
            let Some((y_min, y_max)) = lines.y_range(x0, x1) else { return };
            let first = (y_min.max(0.0) as usize).min(rows - 1);
            let last = (y_max.max(0.0) as usize).min(rows - 1);
            for cj in first..=last {
                // Cells wholly under the plane hold no blocker.
                let corners = self.field.cell_corners(col, cj);
                let (xf, yf) = (col as f64, cj as f64);
                let under = |h: f64, dx: f64, dy: f64| h <= plane.at(xf + dx, yf + dy) + self.z_eps;
                if under(corners[0], 0.0, 0.0)
                    && under(corners[1], 1.0, 0.0)
                    && under(corners[2], 0.0, 1.0)
                    && under(corners[3], 1.0, 1.0)
                {
                    continue;
                }
                for blocker in self.field.cell_triangles(col, cj) {
                    if let Some(region) = self.above_plane(&blocker, plane) {
                        lines.subtract_region(&region);
                        if lines.is_empty() {
                            return;
                        }
                    }
                }
            }
        }
    }

    /// The highest sample in local columns `0..=x` and rows near `y_lo..=y_hi`.
    fn highest_left_of(&self, x: usize, y_lo: f64, y_hi: f64) -> f64 {
        let bands = self.band_prefix_max.len() / self.field.width();
        let band_of = |y: f64| ((y.max(0.0) as usize) / BAND).min(bands - 1);
        (band_of(y_lo)..=band_of(y_hi))
            .map(|b| self.band_prefix_max[x + b * self.field.width()])
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The part of triangle `tri` (projected) where the surface is above `plane` by more than
    /// the tolerance, as a convex polygon; `None` if there is none.
    fn above_plane(&self, tri: &[DVec3; 3], plane: &Plane) -> Option<Vec<[f64; 2]>> {
        let e = tri.map(|v| v.z - plane.at(v.x, v.y) - self.z_eps);
        if e.iter().all(|&d| d <= 0.0) {
            return None;
        }
        let mut region = Vec::with_capacity(4);
        for k in 0..3 {
            let (p, q) = (tri[k], tri[(k + 1) % 3]);
            let (ep, eq) = (e[k], e[(k + 1) % 3]);
            if ep >= 0.0 {
                region.push([p.x, p.y]);
            }
            if (ep >= 0.0) != (eq >= 0.0) {
                let t = ep / (ep - eq);
                region.push([p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)]);
            }
        }
        (region.len() >= 3).then_some(region)
    }

    /// Whether some of `lines` passes through `s_tau` (texel (i, j)) at or above the surface.
    fn limit_ray_exists(&self, i: usize, j: usize, tri_lines: &TriangleLines) -> bool {
        let lines = &tri_lines.lines;
        if lines.is_empty() {
            return false;
        }
        let (x, jf) = (i as f64, j as f64);
        let top = self.field.height() - 1;
        let plane = &tri_lines.plane;
        let h_j = self.field.h(i, j);
        // On each half of s_tau the surface is linear: plane(x, y) - h(y) >= 0 is linear in y.
        let half = |y0: f64, y1: f64, neighbour: usize| -> bool {
            let slope = self.field.h(i, neighbour) - h_j; // per unit of |y - j|
            let dir = if neighbour > j { 1.0 } else { -1.0 };
            // plane.at(x, y) - (h_j + slope * dir * (y - j)) >= 0
            let k = plane.gy - slope * dir;
            let c = plane.c + plane.gx * x - h_j + slope * dir * jf;
            lines.meets(&[lines.y_at_least(x, y0), lines.y_at_most(x, y1), lines.y_linear(x, k, c)])
        };
        (j > 0 && half((jf - 0.5).max(0.0), jf, j - 1))
            || (j < top && half(jf, (jf + 0.5).min(top as f64), j + 1))
    }
}
