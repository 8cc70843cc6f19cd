//! The walk of one shadow ray over its first cells: what it proves lit or occluded.

use super::*;
use crate::cell_grid::triangle_planes;

impl<T: Tracer> SunShadows<T> {
    /// The walk of `ray`: what it proves, or from where on the ray it proves nothing.
    pub(super) fn walk(&self, ray: &Ray, steps: &mut u32) -> Walked {
        match self.start(ray) {
            Some((r, t0, cell)) => self.walk_from(&r, t0, cell, steps),
            None => Walked::From(ray.t_min),
        }
    }

    /// A ray the walk can decide, in cell space with the sun's reciprocal direction, with
    /// where it starts (`t_min`) and the cell under that point; `None` for a ray of another
    /// direction, with an empty or non-finite range, or not starting over the grid.
    #[inline]
    pub(super) fn start(&self, ray: &Ray) -> Option<Start> {
        if ray.dir != self.towards_sun || self.bound.is_empty() {
            return None;
        }
        // The ray in cell space, as the tracers map it, with the sun's reciprocal direction.
        let mut r = self.grid.to_cell_space_dir_only(ray);
        r.inv_dir = self.cell_inv_dir;
        let t0 = r.t_min;
        if !(t0.is_finite() && t0 <= r.t_max) {
            return None;
        }
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (o, d) = (r.origin, r.dir);
        let (xa, ya, za) = (o.x + t0 * d.x, o.y + t0 * d.y, o.z + t0 * d.z);
        if !(xa >= 0.0 && xa <= cells_x as f64 && ya >= 0.0 && ya <= cells_y as f64) {
            return None;
        }
        if za.is_nan() {
            return None;
        }
        Some((r, t0, ((xa as usize).min(cells_x - 1), (ya as usize).min(cells_y - 1))))
    }

    /// The walk of [`SunShadows::decide`] from `t0`, over cell `(cx, cy)`.
    pub(super) fn walk_from(
        &self,
        r: &CellRay,
        t0: f64,
        (mut cx, mut cy): (usize, usize),
        steps: &mut u32,
    ) -> Walked {
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (o, d, inv) = (r.origin, r.dir, r.inv_dir);
        let (mut xa, mut ya, mut za) = (o.x + t0 * d.x, o.y + t0 * d.y, o.z + t0 * d.z);
        if self.fast_triangles && (d.x != 0.0 || d.y != 0.0) {
            return self.walk_triangles(r, t0, (cx, cy), steps);
        }
        let samples = self.field.samples();
        let mut t_a = t0;
        let leave = |c: usize, o: f64, d: f64, inv: f64| {
            if d > 0.0 {
                ((c + 1) as f64 - o) * inv
            } else if d < 0.0 {
                (c as f64 - o) * inv
            } else {
                f64::INFINITY
            }
        };
        for _ in 0..self.walk {
            *steps += 1;
            if za - self.margin > self.bound_at(cx, cy) as f64 {
                return Walked::Lit;
            }
            let (tx, ty) = (leave(cx, o.x, d.x, inv.x), leave(cy, o.y, d.y, inv.y));
            let t_b = tx.min(ty);
            // A vertical ray stays over its point.
            let (xb, yb) =
                if t_b.is_finite() { (o.x + t_b * d.x, o.y + t_b * d.y) } else { (xa, ya) };
            let zb = if t_b.is_finite() { o.z + t_b * d.z } else { f64::INFINITY };
            if !self.passes_above(samples, (cx, cy), r, t_a, [xa, ya, za], [xb, yb, zb]) {
                // Near the solid: inside it over this cell, or (through a wall) over the next?
                if self.inside(samples, (cx, cy), r, t_a, t_b) {
                    return Walked::Occluded;
                }
                let (nx, ny) = (
                    if tx == t_b { step(cx, d.x, cells_x) } else { Some(cx) },
                    if ty == t_b { step(cy, d.y, cells_y) } else { Some(cy) },
                );
                let (Some(nx), Some(ny)) = (nx, ny) else { return Walked::From(t_a) };
                let t_c = leave(nx, o.x, d.x, inv.x).min(leave(ny, o.y, d.y, inv.y));
                return if self.inside(samples, (nx, ny), r, t_b, t_c) {
                    Walked::Occluded
                } else {
                    Walked::From(t_a)
                };
            }
            if !t_b.is_finite() {
                return Walked::Lit;
            }
            // Step to the next cell; leaving the grid with every cell cleared proves the ray.
            if tx == t_b {
                match step(cx, d.x, cells_x) {
                    Some(c) => cx = c,
                    None => return Walked::Lit,
                }
            }
            if ty == t_b {
                match step(cy, d.y, cells_y) {
                    Some(c) => cy = c,
                    None => return Walked::Lit,
                }
            }
            (t_a, xa, ya, za) = (t_b, xb, yb, zb);
        }
        Walked::From(t_a)
    }

    /// The walk of [`SunShadows::decide`] over the `triangles` surface of a field without
    /// holes, for a ray that moves horizontally, from `t0` over cell `(cx, cy)`: the same tests
    /// (the bound at each cell's entry point, both planes of the cell at both ends of the
    /// ray's part over it), with few branches the processor could mispredict.
    #[inline]
    pub(super) fn walk_triangles(
        &self,
        r: &CellRay,
        t0: f64,
        (mut cx, mut cy): (usize, usize),
        steps: &mut u32,
    ) -> Walked {
        let (o, d, inv) = (r.origin, r.dir, r.inv_dir);
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (w, samples, margin) = (self.field.width(), self.field.samples(), self.margin);
        // The boundary a cell is left through along each axis (`cx + up_x`), and the step.
        let (up_x, up_y) = ((d.x > 0.0) as usize, (d.y > 0.0) as usize);
        let (step_x, step_y) =
            (if d.x > 0.0 { 1 } else { usize::MAX }, if d.y > 0.0 { 1 } else { usize::MAX });
        let leave = |c: usize, up: usize, o: f64, d: f64, inv: f64| {
            if d != 0.0 {
                ((c + up) as f64 - o) * inv
            } else {
                f64::INFINITY
            }
        };
        let (mut t_a, mut xa, mut ya, mut za) =
            (t0, o.x + t0 * d.x, o.y + t0 * d.y, o.z + t0 * d.z);
        for _ in 0..self.walk {
            *steps += 1;
            if za - margin > self.bound_at(cx, cy) as f64 {
                return Walked::Lit;
            }
            let (tx, ty) = (leave(cx, up_x, o.x, d.x, inv.x), leave(cy, up_y, o.y, d.y, inv.y));
            let t_b = tx.min(ty);
            let (xb, yb, zb) = (o.x + t_b * d.x, o.y + t_b * d.y, o.z + t_b * d.z);
            let planes = triangle_planes(samples, w, cx, cy);
            let (ua, va, ub, vb) = (xa - cx as f64, ya - cy as f64, xb - cx as f64, yb - cy as f64);
            let mut above = true;
            for (p0, pu, pv) in planes {
                above &= (za - (p0 + pu * ua + pv * va) > margin)
                    & (zb - (p0 + pu * ub + pv * vb) > margin);
            }
            if !above {
                let samples = self.field.samples();
                if self.inside(samples, (cx, cy), r, t_a, t_b) {
                    return Walked::Occluded;
                }
                return Walked::From(t_a);
            }
            if tx == t_b {
                cx = cx.wrapping_add(step_x);
            }
            if ty == t_b {
                cy = cy.wrapping_add(step_y);
            }
            // Leaving the grid with every cell cleared proves the ray.
            if cx >= cells_x || cy >= cells_y {
                return Walked::Lit;
            }
            (t_a, xa, ya, za) = (t_b, xb, yb, zb);
        }
        Walked::From(t_a)
    }

    /// Whether the ray's point halfway between `t_a` and `t_b` (its part over cell
    /// `(cx, cy)`) lies within the ray's range, at least [`NEAR`] inside the cell's footprint,
    /// and inside the cell's solid by the margin: above the solid's bottom, below its top
    /// (boxes) or below the larger of the two triangles' planes (triangles). Then every exact
    /// tracer finds the ray occluded.
    #[inline]
    pub(super) fn inside(
        &self,
        samples: &[f32],
        (cx, cy): (usize, usize),
        r: &CellRay,
        t_a: f64,
        t_b: f64,
    ) -> bool {
        let t = 0.5 * (t_a + t_b);
        if !(t.is_finite() && t <= r.t_max) || self.grid.is_empty_cell(cx, cy) {
            return false;
        }
        let p = r.origin + t * r.dir;
        let (u, v) = (p.x - cx as f64, p.y - cy as f64);
        let interior = |u: f64| u > NEAR && u < 1.0 - NEAR;
        if !(interior(u) && interior(v) && p.z - self.margin > self.grid.bounds().min.z) {
            return false;
        }
        let w = self.field.width();
        let i = cx + cy * w;
        let top = match self.grid.surface() {
            Surface::Boxes => samples[i] as f64,
            Surface::Triangles => {
                let (a, b) = (samples[i] as f64, samples[i + 1] as f64);
                let (c, d) = (samples[i + w] as f64, samples[i + w + 1] as f64);
                let planes = if relief_core::splits_along_ad(a, b, c, d) {
                    [(a, b - a, d - b), (a, d - c, c - a)]
                } else {
                    [(a, b - a, c - a), (b + c - d, d - c, d - b)]
                };
                planes.map(|(p0, pu, pv)| p0 + pu * u + pv * v).into_iter().fold(f64::MIN, f64::max)
            }
        };
        p.z + self.margin < top
    }

    /// Whether the ray's part from `a` (at `t_a`) to `b` (cell space, rising), over cell
    /// `(cx, cy)`, passes above the solid of every cell within [`NEAR`] of it by the margin.
    ///
    /// For `triangles`, over a cell with a surface, the ray must pass above both planes of
    /// the cell (the surface is the larger, and the planes are linear along the ray, so both
    /// ends decide): the surface is continuous across the cell's edges (its neighbours with
    /// a surface share the edge samples; the others hold nothing), so the neighbours' solid
    /// within [`NEAR`] is below the ray too. Otherwise (`boxes`, or a cell over a hole,
    /// beside whose walls the ray may pass) the ray must pass above the highest point of
    /// every cell within [`NEAR`] of the part from where it comes that near.
    #[inline]
    pub(super) fn passes_above(
        &self,
        samples: &[f32],
        (cx, cy): (usize, usize),
        r: &CellRay,
        t_a: f64,
        [xa, ya, za]: [f64; 3],
        [xb, yb, zb]: [f64; 3],
    ) -> bool {
        if self.grid.surface() == Surface::Triangles && !self.grid.is_empty_cell(cx, cy) {
            // The two planes over local (u, v), as the exact test has them.
            let planes = triangle_planes(samples, self.field.width(), cx, cy);
            let (ua, va) = (xa - cx as f64, ya - cy as f64);
            let (ub, vb) = (xb - cx as f64, yb - cy as f64);
            return planes.iter().all(|&(p0, pu, pv)| {
                za - (p0 + pu * ua + pv * va) > self.margin
                    && zb - (p0 + pu * ub + pv * vb) > self.margin
            });
        }
        // (Truncation is the floor of the non-negative values.)
        let span = |lo: f64, hi: f64, cells: usize| {
            let first = (lo - NEAR).max(0.0) as usize;
            let last = ((hi + NEAR).max(0.0) as usize).min(cells - 1);
            first..=last
        };
        // When the ray comes within NEAR of cell m along one axis (before `t_a`: already).
        let near_from = |m: usize, o: f64, d: f64, inv: f64| {
            if d > 0.0 {
                (m as f64 - NEAR - o) * inv
            } else if d < 0.0 {
                ((m + 1) as f64 + NEAR - o) * inv
            } else {
                f64::NEG_INFINITY
            }
        };
        let (o, d, inv) = (r.origin, r.dir, r.inv_dir);
        for my in span(ya.min(yb), ya.max(yb), self.grid.cells_y()) {
            let ty = near_from(my, o.y, d.y, inv.y);
            for mx in span(xa.min(xb), xa.max(xb), self.grid.cells_x()) {
                let top = self.grid.cell_max(samples, mx, my) as f64;
                let t = ty.max(near_from(mx, o.x, d.x, inv.x));
                let z = if t > t_a { o.z + t * d.z } else { za };
                // (Not `<=`: a NaN height proves nothing.)
                if (z - self.margin).partial_cmp(&top) != Some(std::cmp::Ordering::Greater) {
                    return false;
                }
            }
        }
        true
    }
}

/// The next cell index along an axis the ray moves along with sign `d`, or `None` past the
/// grid's `cells`.
#[inline]
fn step(c: usize, d: f64, cells: usize) -> Option<usize> {
    if d > 0.0 {
        Some(c + 1).filter(|&c| c < cells)
    } else {
        c.checked_sub(1)
    }
}
