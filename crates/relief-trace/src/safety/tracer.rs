//! The safety-shape tracer: accurate marching on x-centerlines with precomputed safe steps,
//! a dichotomous search on centerlines and the exact final test (Baboud et al. 2011, 5.2.2).

use super::frame::{Frame, LocalField, RayClass};
use super::options::RaySet;
use super::shapes::SafetyShapes;
use crate::cell_grid::{CellGrid, CellRay};
use crate::{Hit, NaiveTracer, TraceError, Tracer};
use relief_core::{Aabb, BoxFace, Clip, DVec3, HeightField, Ray, Surface};
use std::sync::Arc;

/// How the ray is intersected inside the last inter-texel (section 7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FinalTest {
    /// The two triangles: exact.
    #[default]
    Triangles,
    /// The view-dependent linear surface: the height varies linearly along the ray between
    /// centerline crossings. Same silhouettes, approximate in between.
    Linear,
}

/// Exact ray casting of the `triangles` surface of a static height field with precomputed
/// safety shapes. Rays the shapes were not built for (interior rays for exterior shapes, rays
/// steeper than `phi_max`) are traced cell by cell instead, so every answer stays exact; use
/// [`SafetyTracer::check_view`] to refuse such views up front.
#[derive(Debug, Clone)]
pub struct SafetyTracer {
    field: Arc<HeightField>,
    grid: CellGrid,
    shapes: Arc<SafetyShapes>,
    naive: NaiveTracer,
    final_test: FinalTest,
    /// "Clearly above the surface" means above by more than this.
    slack: f64,
    /// `tan(phi_max)` of the shapes, if bounded.
    max_slope: Option<f64>,
}

impl SafetyTracer {
    /// A tracer of `field`'s `triangles` surface with `shapes` built for it.
    pub fn new(
        field: Arc<HeightField>,
        shapes: Arc<SafetyShapes>,
        final_test: FinalTest,
    ) -> Result<Self, TraceError> {
        if (shapes.width(), shapes.height()) != (field.width(), field.height()) {
            return Err(TraceError::Options(format!(
                "safety shapes of a {}x{} field given for a {}x{} field",
                shapes.width(),
                shapes.height(),
                field.width(),
                field.height()
            )));
        }
        if field.hole_count() > 0 {
            return Err(TraceError::Unsupported("safety shapes need a field without voids".into()));
        }
        let grid = CellGrid::new(&field, Surface::Triangles);
        let naive = NaiveTracer::new(field.clone(), Surface::Triangles);
        let magnitude = field.min_sample().abs().max(field.max_sample().abs()) as f64;
        let (slack, max_slope) = (1e-9 * (1.0 + magnitude), shapes.options().max_slope());
        Ok(SafetyTracer { field, grid, shapes, naive, final_test, slack, max_slope })
    }

    /// The shapes in use.
    pub fn shapes(&self) -> &SafetyShapes {
        &self.shapes
    }

    /// Whether the shapes guarantee a ray (world space): exterior shapes need a ray coming from
    /// outside the terrain's bounding box, a `phi_max` bound a ray at most that steep.
    pub fn admits(&self, world_ray: &Ray) -> bool {
        let clip = self.grid.clip(&self.grid.to_cell_space(world_ray));
        clip.is_none_or(|clip| self.admits_clipped(world_ray, &clip))
    }

    /// [`SafetyTracer::admits`] for a ray already clipped to the bounding box.
    #[inline]
    fn admits_clipped(&self, world_ray: &Ray, clip: &Clip) -> bool {
        if self.max_slope.is_some_and(|max_slope| too_steep(world_ray.dir, max_slope)) {
            return false;
        }
        self.shapes.options().rays == RaySet::All || clip.face != BoxFace::Inside
    }

    /// Refuses, with a reason, a view whose rays the shapes were not built for: `eye` and the
    /// directions of its primary rays, and (for shadows) the direction towards the light. For
    /// a camera whose rays do not all start at one eye (an orthographic one), see
    /// [`SafetyTracer::check_rays`].
    pub fn check_view(
        &self,
        eye: DVec3,
        directions: impl Iterator<Item = DVec3>,
        light: Option<DVec3>,
    ) -> Result<(), TraceError> {
        self.check_origin(eye)?;
        self.check_directions(directions, light)
    }

    /// As [`SafetyTracer::check_view`], for primary rays that may each start elsewhere (an
    /// orthographic camera's start on the plane through its eye): every ray's origin and
    /// direction is checked.
    pub fn check_rays(
        &self,
        rays: impl Iterator<Item = Ray>,
        light: Option<DVec3>,
    ) -> Result<(), TraceError> {
        let mut directions = Vec::new();
        for ray in rays {
            self.check_origin(ray.origin)?;
            directions.push(ray.dir);
        }
        self.check_directions(directions.into_iter(), light)
    }

    /// Refuses a ray origin inside the terrain's box for exterior shapes.
    fn check_origin(&self, eye: DVec3) -> Result<(), TraceError> {
        let options = self.shapes.options();
        if options.rays == RaySet::Exterior {
            let bounds = self.field.world_bounds(Surface::Triangles);
            let inside = (0..3).all(|k| eye[k] > bounds.min[k] && eye[k] < bounds.max[k]);
            if inside {
                return Err(TraceError::ViewNotAdmitted(format!(
                    "{} shapes serve exterior rays only, and the eye is inside the \
                     terrain's bounding box; use cyl_all shapes or move the camera out",
                    options.variant()
                )));
            }
        }
        Ok(())
    }

    /// Refuses primary ray `directions`, or shadow rays towards `light`, steeper than the
    /// shapes' `phi_max`.
    fn check_directions(
        &self,
        directions: impl Iterator<Item = DVec3>,
        light: Option<DVec3>,
    ) -> Result<(), TraceError> {
        let options = self.shapes.options();
        if let Some(max_slope) = options.max_slope() {
            let phi = options.phi_max_deg.unwrap_or(90.0);
            let steep = |d: DVec3| too_steep(d, max_slope);
            if directions.into_iter().any(steep) {
                return Err(TraceError::ViewNotAdmitted(format!(
                    "the shapes admit rays at most {phi} degrees from horizontal, and this view \
                     has rays looking higher; look further down or build shapes without phi max"
                )));
            }
            // Shadow rays are traced from the light, downwards.
            if light.is_some_and(|l| steep(-l)) {
                return Err(TraceError::ViewNotAdmitted(format!(
                    "the shapes admit rays at most {phi} degrees from horizontal, and shadow rays \
                     from this sun are not; raise the sun or render without shadows"
                )));
            }
        }
        Ok(())
    }

    /// The first hit, marching with the shapes (the ray must be admitted and not vertical).
    fn march(
        &self,
        world_ray: &Ray,
        ray: &CellRay,
        clip: &Clip,
        class: RayClass,
        steps: &mut u32,
    ) -> Option<Hit> {
        let frame = Frame::new(class, self.field.width(), self.field.height());
        let local = LocalField::new(frame, self.field.samples());
        let dir = frame.dir_to_local(ray.dir);
        let march = Marching {
            tracer: self,
            world_ray,
            ray,
            clip,
            frame,
            local,
            origin: frame.point_to_local(ray.origin),
            dir,
            inv_dir_x: 1.0 / dir.x,
        };
        march.run(steps)
    }
}

impl Tracer for SafetyTracer {
    fn name(&self) -> &'static str {
        "safety"
    }

    fn surface(&self) -> Surface {
        Surface::Triangles
    }

    fn bounds(&self) -> Aabb {
        self.grid.world_bounds()
    }

    fn intersect_counted(&self, world_ray: &Ray, steps: &mut u32) -> Option<Hit> {
        let ray = self.grid.to_cell_space(world_ray);
        let clip = self.grid.clip(&ray)?;
        match RayClass::of(ray.dir) {
            Some(class) if self.admits_clipped(world_ray, &clip) => {
                self.march(world_ray, &ray, &clip, class, steps)
            }
            _ => self.naive.intersect_counted(world_ray, steps),
        }
    }

    fn occluded_counted(&self, world_ray: &Ray, steps: &mut u32) -> bool {
        if self.shapes.options().rays == RaySet::All && self.max_slope.is_none() {
            return self.intersect_counted(world_ray, steps).is_some();
        }
        // Exterior or phi-max shapes: a segment that runs out of the box is traced backwards
        // from just outside it, like a shadow ray cast from the light (downwards, from outside).
        let ray = self.grid.to_cell_space(world_ray);
        let unbounded = CellRay { ray: Ray { t_max: f64::INFINITY, ..ray.ray }, ..ray };
        let Some(box_span) = self.grid.clip(&unbounded) else { return false };
        if world_ray.t_max < box_span.t_exit {
            return self.naive.occluded_counted(world_ray, steps);
        }
        let near = box_span.t_enter.max(world_ray.t_min);
        if near > box_span.t_exit {
            return false;
        }
        // Start just outside the box; end just outside it too when the segment enters it from
        // outside, so rounding cannot cut off a hit on the box's faces.
        let margin = 1e-6 * (1.0 + box_span.t_exit.abs());
        let past_near = if near > world_ray.t_min { margin } else { 0.0 };
        let back = Ray {
            origin: world_ray.at(box_span.t_exit + margin),
            dir: -world_ray.dir,
            t_min: 0.0,
            t_max: margin + (box_span.t_exit - near) + past_near,
        };
        self.intersect_counted(&back, steps).is_some()
    }
}

/// Whether direction `d` climbs more steeply than `max_slope` (rise over horizontal run).
#[inline]
fn too_steep(d: DVec3, max_slope: f64) -> bool {
    d.z > max_slope * d.truncate().length() + 1e-12 * d.length()
}

/// One ray marching through a class's local frame (class `x+`: `dir.x > 0`).
struct Marching<'a> {
    tracer: &'a SafetyTracer,
    world_ray: &'a Ray,
    ray: &'a CellRay,
    clip: &'a Clip,
    frame: Frame,
    local: LocalField<'a>,
    origin: DVec3,
    dir: DVec3,
    /// `1 / dir.x`.
    inv_dir_x: f64,
}

impl Marching<'_> {
    fn run(&self, steps: &mut u32) -> Option<Hit> {
        let width = self.local.width();
        let x_in = self.origin.x + self.clip.t_enter * self.dir.x;
        let x_out = self.origin.x + self.clip.t_exit * self.dir.x;
        // Truncation is the floor here: the values are not negative (NaN goes to 0).
        let last = (x_out.max(0.0) as usize).min(width - 1);
        let tail = last < width - 1 && x_out > last as f64;
        // The index of the last test position: the exit point itself when it lies past the last
        // centerline.
        let end = last + tail as usize;
        let first = (x_in.max(0.0) as usize).min(width - 2);
        // March from the centerline at or before the entry when the ray passes over the grid
        // there: above the box (it came in through the top), or entering through the face on
        // that centerline. Otherwise (through a side along x, or starting inside the box) test
        // the column it enters in first.
        let on_first = {
            let (y, z) = self.at_centerline(first);
            (0.0..=(self.local.height() - 1) as f64).contains(&y)
                && (z > self.tracer.grid.bounds().max.z || x_in - first as f64 <= 1e-9)
                && self.clip.face != BoxFace::Inside
        };
        let mut lo = first;
        if !on_first {
            if let Some(hit) = self.column(first, None, steps) {
                return Some(hit);
            }
            lo += 1;
        }
        let dz = self.dir.z * self.inv_dir_x;
        // The ray's (y, z, gap) at `lo`, when the previous step already computed it.
        let mut known = None;
        // The column before the final centerline is always tested or safely stepped over.
        while lo <= last && lo < width - 1 {
            *steps += 1;
            let here = known.take().unwrap_or_else(|| self.position(lo));
            let k = match here {
                (y, z, gap) if gap > 0.0 => {
                    let texel = ((y + 0.5).max(0.0) as usize).min(self.local.height() - 1);
                    let index = self.frame.grid_index(lo, texel);
                    self.tracer.shapes.step(self.frame.class, index, z, dz) as usize
                }
                _ => 0,
            };
            if k == 0 {
                // A naive step through one column; the signs on its centerlines decide which
                // cells need the exact test, and the far one is where the next step starts.
                if lo < last {
                    let next = self.position(lo + 1);
                    let ends = Some((here.2 > 0.0, next.2 > 0.0));
                    if let Some(hit) = self.column(lo, ends, steps) {
                        return Some(hit);
                    }
                    known = Some(next);
                } else if let Some(hit) = self.column(lo, None, steps) {
                    return Some(hit);
                }
                lo += 1;
                continue;
            }
            let hi = (lo + k).min(end);
            if hi == lo {
                return None;
            }
            let gap_hi = if hi > last {
                let gap = self.exit_gap();
                if gap > 0.0 {
                    return None;
                }
                gap
            } else {
                let there = self.position(hi);
                if there.2 > 0.0 {
                    (lo, known) = (hi, Some(there));
                    continue;
                }
                there.2
            };
            // One crossing at most between lo and hi: regula falsi on centerlines (the Illinois
            // variant), which usually brackets it in two tests where bisection takes log2(k).
            let (mut a, mut gap_a, mut b, mut gap_b) = (lo, here.2, hi, gap_hi);
            let mut kept = 0i8;
            while b - a > 1 {
                *steps += 1;
                let along = gap_a / (gap_a - gap_b);
                let m = (a + ((b - a) as f64 * along) as usize).clamp(a + 1, b - 1);
                let gap = self.position(m).2;
                if gap > 0.0 {
                    (a, gap_a) = (m, gap);
                    if kept == 1 {
                        gap_b *= 0.5;
                    }
                    kept = 1;
                } else {
                    (b, gap_b) = (m, gap);
                    if kept == -1 {
                        gap_a *= 0.5;
                    }
                    kept = -1;
                }
            }
            let m = b;
            // Clearly above at a, not at a + 1 (unless a + 1 is where the ray leaves the box).
            let ends = (m <= last).then_some((true, false));
            if let Some(hit) = self.final_column(a, ends, steps) {
                return Some(hit);
            }
            // Only a graze within the slack: march on past it.
            lo = a + 1;
        }
        None
    }

    /// The ray's local y and z on x-centerline `i`.
    #[inline]
    fn at_centerline(&self, i: usize) -> (f64, f64) {
        let t = (i as f64 - self.origin.x) * self.inv_dir_x;
        (self.origin.y + t * self.dir.y, self.origin.z + t * self.dir.z)
    }

    /// The ray's local y and z on x-centerline `i`, and how far it is clearly above the surface
    /// there (positive: clearly above; otherwise below or within the slack).
    #[inline]
    fn position(&self, i: usize) -> (f64, f64, f64) {
        let (y, z) = self.at_centerline(i);
        (y, z, z - self.local.centerline_height(i, y) - self.tracer.slack)
    }

    /// How far the ray is clearly above the surface where it leaves the bounding box.
    fn exit_gap(&self) -> f64 {
        let p = self.frame.point_to_local(self.ray.at(self.clip.t_exit));
        p.z - self.local.surface_height(p.x, p.y) - self.tracer.slack
    }

    /// The exact first hit in local column `c` (between x-centerlines `c` and `c + 1`): the
    /// grid cells the ray crosses there, tested exactly as the naive tracer tests them. A cell
    /// the ray passes clearly above at both ends is skipped: within a cell the ray's height
    /// over the surface is concave, so it cannot dip below in between.
    /// `ends`, when known, says whether the ray is clearly above the surface on the column's
    /// two x-centerlines.
    fn column(&self, c: usize, ends: Option<(bool, bool)>, steps: &mut u32) -> Option<Hit> {
        let rows = self.local.height() - 1;
        let (t0, t1) = self.column_span(c);
        if t0 > t1 {
            return None;
        }
        let (y0, y1) = (self.origin.y + t0 * self.dir.y, self.origin.y + t1 * self.dir.y);
        let row_of = |y: f64| (y.max(0.0) as usize).min(rows - 1);
        let (r0, r1) = (row_of(y0), row_of(y1));
        let near_boundary = |y: f64| {
            let f = y - (y as i64) as f64;
            f.abs() < 1e-7 || f.abs() > 1.0 - 1e-7
        };
        if near_boundary(y0) || near_boundary(y1) || r0.abs_diff(r1) > 1 {
            // Rounding could put the ray in the neighbouring row: test every candidate.
            let (lo, hi) = (y0.min(y1) - 1e-7, y0.max(y1) + 1e-7);
            let mut best: Option<Hit> = None;
            for row in row_of(lo)..=row_of(hi) {
                if let Some(hit) = self.cell_hit(c, row, steps) {
                    if best.is_none_or(|b| hit.t < b.t) {
                        best = Some(hit);
                    }
                }
            }
            return best;
        }
        let slack = self.tracer.slack;
        // The ray's height over the surface where it enters and leaves the column: on the
        // x-centerlines themselves unless the clip cuts the column short.
        let x_gap = |t: f64, x: usize, on_line: bool| {
            if on_line {
                let (y, z) = self.at_centerline(x);
                z - self.local.centerline_height(x, y)
            } else {
                self.gap(t)
            }
        };
        let (above0, above1) = ends.unwrap_or_else(|| {
            let (full0, full1) = self.column_span_unclipped(c);
            (x_gap(t0, c, t0 == full0) > slack, x_gap(t1, c + 1, t1 == full1) > slack)
        });
        if r0 == r1 {
            if above0 && above1 {
                return None;
            }
            return self.cell_hit(c, r0, steps);
        }
        // The ray crosses the y-centerline `row` inside the column: the surface along it is
        // linear between the samples (c, row) and (c + 1, row).
        let row = r0.max(r1);
        let t_row = (row as f64 - self.origin.y) / self.dir.y;
        let p = self.origin + t_row * self.dir;
        let (h0, h1) = (self.local.h(c, row), self.local.h(c + 1, row));
        let above_row = p.z - (h0 + (h1 - h0) * (p.x - c as f64)) > slack;
        if !(above0 && above_row) {
            if let Some(hit) = self.cell_hit(c, r0, steps) {
                return Some(hit);
            }
        }
        if !(above_row && above1) {
            return self.cell_hit(c, r1, steps);
        }
        None
    }

    /// The exact hit in local cell (c, row), as the naive tracer computes it.
    fn cell_hit(&self, c: usize, row: usize, steps: &mut u32) -> Option<Hit> {
        *steps += 1;
        let grid = &self.tracer.grid;
        let (gx, gy) = self.frame.cell_to_grid(c, row);
        let seg = grid.segment(self.ray, self.clip, gx, gy);
        let (t, normal) =
            grid.intersect_cell(self.tracer.field.samples(), self.ray, gx, gy, &seg)?;
        Some(grid.world_hit(self.world_ray, t, normal))
    }

    /// The ray's height over the surface at parameter `t`.
    #[inline]
    fn gap(&self, t: f64) -> f64 {
        let p = self.origin + t * self.dir;
        p.z - self.local.surface_height(p.x, p.y)
    }

    /// The ray parameters where it crosses the x-centerlines `c` and `c + 1`.
    #[inline]
    fn column_span_unclipped(&self, c: usize) -> (f64, f64) {
        let t0 = (c as f64 - self.origin.x) * self.inv_dir_x;
        let t1 = (c as f64 + 1.0 - self.origin.x) * self.inv_dir_x;
        (t0, t1)
    }

    /// The ray parameters where it crosses local column `c`, within the clip.
    fn column_span(&self, c: usize) -> (f64, f64) {
        let (t0, t1) = self.column_span_unclipped(c);
        (t0.max(self.clip.t_enter), t1.min(self.clip.t_exit))
    }

    /// The hit in the column the bisection ended in: exact, or on the linear surface.
    fn final_column(&self, c: usize, ends: Option<(bool, bool)>, steps: &mut u32) -> Option<Hit> {
        match self.tracer.final_test {
            FinalTest::Triangles => self.column(c, ends, steps),
            FinalTest::Linear => self.linear_hit(c).or_else(|| self.column(c, ends, steps)),
        }
    }

    /// Section 7's view-dependent surface: the ray's height above the surface is taken as
    /// linear between the centerline crossings (x-centerlines `c`, `c + 1` and the y-centerline
    /// between them, if any).
    fn linear_hit(&self, c: usize) -> Option<Hit> {
        let (t0, t1) = self.column_span(c);
        let mut ts = vec![t0];
        let (y0, y1) = (self.origin.y + t0 * self.dir.y, self.origin.y + t1 * self.dir.y);
        let row = y0.min(y1).floor() + 1.0;
        if row < y0.max(y1) && self.dir.y != 0.0 {
            ts.push((row - self.origin.y) / self.dir.y);
        }
        ts.push(t1);
        let gap = |t: f64| {
            let p = self.origin + t * self.dir;
            p.z - self.local.surface_height(p.x, p.y)
        };
        for pair in ts.windows(2) {
            let (ga, gb) = (gap(pair[0]), gap(pair[1]));
            if ga > 0.0 && gb <= 0.0 {
                let t = pair[0] + (pair[1] - pair[0]) * ga / (ga - gb);
                let p = self.frame.point_to_local(self.ray.at(t));
                let (gx, gy) = self
                    .frame
                    .cell_to_grid(c, (p.y.floor().max(0.0) as usize).min(self.local.height() - 2));
                let normal = self.tracer.grid.triangle_normal(
                    self.tracer.field.samples(),
                    gx,
                    gy,
                    self.ray.at(t),
                );
                return Some(self.tracer.grid.world_hit(self.world_ray, t, normal));
            }
        }
        None
    }
}
