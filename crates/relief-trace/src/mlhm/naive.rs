//! The baseline MLHM box ray tracer: a 2D DDA over every cell of level 0, testing each cell's
//! column boxes exactly (Nilles & Müller 2025, section 4.1).

use super::cells::{first_hit_in_cell, ray_to_cells, segment, world_box};
use crate::cell_grid::axis_cell;
use crate::{Hit, MlhmHit, MlhmMode, MlhmTracer, Tracer};
use relief_core::{Aabb, DVec2, DVec3, Mlhm, MlhmHeights, Ray, Surface};
use std::sync::Arc;

/// Naive box ray tracing of an [`Mlhm`]: the ray is clipped to the scene's box, then walks the
/// cells it crosses in order (Amanatides-Woo 2D DDA) and, in each, slab-tests the boxes of the
/// cell's columns over the ray's parameter range inside the cell; the first cell with a hit
/// holds the first hit, since columns are exactly as wide as their cell.
///
/// Placement: cell `(x, y)` covers world `[ox + x s, ox + (x + 1) s) x [oy + y s, oy + (y + 1) s)`
/// with `(ox, oy)` the [`origin`](MlhmNaiveTracer::origin) (the grid's south-west corner) and
/// `s` the map's cell size; heights are world z in metres, unscaled. The tracer works in cell
/// space, `((x - ox) / s, (y - oy) / s, z)`, which keeps `t`.
///
/// Cells are half-open, as a height field's texels: a ray running exactly within a cell
/// boundary plane (say `dir.x = 0` with `x` on a boundary) is traced in the cell east (north)
/// of it only, as [`NaiveTracer`](crate::NaiveTracer) does.
///
/// Exact for every [`MlhmMode`]; its cost grows linearly with the cells crossed. As a
/// [`Tracer`] it intersects its default mode ([`MlhmNaiveTracer::with_mode`]).
///
/// ```
/// use std::sync::Arc;
/// use relief_core::{DVec2, DVec3, Mlhm, MlhmColumn, Ray};
/// use relief_trace::{MlhmMaterial, MlhmMode, MlhmNaiveTracer, MlhmTracer};
/// let mut map = Mlhm::new(1, 1, 2, 1.0)?;
/// // Ground of bedrock to 1 m under 1 m of water; a rock slab from 3 m to 4 m above.
/// let ground = MlhmColumn::new(1.0, 0.0, 1.0, 3.0);
/// map.set_cell(0, 0, &[ground, MlhmColumn::new(4.0, 0.0, 0.0, f32::INFINITY)])?;
/// let tracer = MlhmNaiveTracer::new(Arc::new(map), DVec2::ZERO);
/// // A ray under the overhang, going down, meets the water at 2 m...
/// let down = Ray::new(DVec3::new(0.5, 0.5, 2.5), -DVec3::Z);
/// let hit = tracer.intersect_mode(&down, MlhmMode::SolidsWater).unwrap();
/// assert_eq!((hit.hit.t, hit.material), (0.5, MlhmMaterial::Water));
/// // ...and, ignoring water, the bedrock at 1 m.
/// assert_eq!(tracer.intersect_mode(&down, MlhmMode::Solids).unwrap().hit.t, 1.5);
/// // A ray inside the water going up leaves it at 2 m, into air.
/// let up = Ray::new(DVec3::new(0.5, 0.5, 1.5), DVec3::Z);
/// let out = tracer.intersect_mode(&up, MlhmMode::SolidsAir).unwrap();
/// assert_eq!((out.hit.t, out.material), (0.5, MlhmMaterial::Air));
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone)]
pub struct MlhmNaiveTracer {
    map: Arc<Mlhm>,
    origin: DVec2,
    mode: MlhmMode,
    /// The heights bounding the map.
    heights: MlhmHeights,
}

impl MlhmNaiveTracer {
    /// A tracer of `map` with its south-west corner at world `origin`, intersecting
    /// [`MlhmMode::SolidsWater`] as a [`Tracer`].
    pub fn new(map: Arc<Mlhm>, origin: DVec2) -> Self {
        let heights = map.heights();
        MlhmNaiveTracer { map, origin, mode: MlhmMode::SolidsWater, heights }
    }

    /// The same tracer intersecting `mode` when used as a [`Tracer`].
    pub fn with_mode(self, mode: MlhmMode) -> Self {
        MlhmNaiveTracer { mode, ..self }
    }

    /// The mode intersected as a [`Tracer`].
    pub fn mode(&self) -> MlhmMode {
        self.mode
    }

    /// The scene's box in world space for `mode`: the footprint, from minus infinity (the
    /// lowest columns reach down forever) up to the highest box top (`+inf` for
    /// [`MlhmMode::SolidsAir`]).
    pub fn world_bounds(&self, mode: MlhmMode) -> Aabb {
        let top = match mode {
            MlhmMode::Solids => self.heights.solid_max,
            MlhmMode::SolidsWater => self.heights.water_max,
            MlhmMode::SolidsAir => f64::INFINITY,
        };
        world_box(&self.map, self.origin, top)
    }

    /// The 2D DDA over every cell the ray crosses, counting them into `steps`.
    fn walk_cells(&self, world_ray: &Ray, mode: MlhmMode, steps: &mut u32) -> Option<MlhmHit> {
        let ray = self.to_cell_space(world_ray)?;
        let inv = DVec3::ONE / ray.dir;
        let (w, h) = (self.map.width(), self.map.height());
        let top = self.world_bounds(mode).max.z;
        let bounds = Aabb::new(
            DVec3::new(0.0, 0.0, self.map.base() as f64),
            DVec3::new(w as f64, h as f64, top),
        );
        let clip = bounds.clip(&ray)?;
        let (mut cx, mut cy) = (
            axis_cell(ray.origin.x, ray.dir.x, inv.x, clip.t_enter, w),
            axis_cell(ray.origin.y, ray.dir.y, inv.y, clip.t_enter, h),
        );
        let (step_x, step_y) = (ray.dir.x.signum() as isize, ray.dir.y.signum() as isize);
        loop {
            *steps = steps.saturating_add(1);
            let seg = segment(&ray, inv, &clip, cx, cy);
            if let Some(hit) =
                first_hit_in_cell(&self.map, world_ray, &ray, inv, mode, cx, cy, &seg)
            {
                return Some(hit);
            }
            let t_next = seg.t_next_x.min(seg.t_next_y);
            if t_next >= clip.t_exit || t_next.is_nan() {
                return None;
            }
            // Through a corner, step both axes at once.
            if seg.t_next_x == t_next {
                cx = cx.checked_add_signed(step_x).filter(|&c| c < w)?;
            }
            if seg.t_next_y == t_next {
                cy = cy.checked_add_signed(step_y).filter(|&c| c < h)?;
            }
        }
    }

    /// The world ray in cell space, or `None` when it cannot be traced.
    fn to_cell_space(&self, ray: &Ray) -> Option<Ray> {
        ray_to_cells(&self.map, self.origin, ray)
    }
}

impl MlhmTracer for MlhmNaiveTracer {
    fn map(&self) -> &Arc<Mlhm> {
        &self.map
    }

    fn origin(&self) -> DVec2 {
        self.origin
    }

    fn intersect_mode_counted(
        &self,
        ray: &Ray,
        mode: MlhmMode,
        steps: &mut u32,
    ) -> Option<MlhmHit> {
        self.walk_cells(ray, mode, steps)
    }
}

impl Tracer for MlhmNaiveTracer {
    fn name(&self) -> &'static str {
        "mlhm-naive"
    }

    /// MLHM columns are flat-topped boxes.
    fn surface(&self) -> Surface {
        Surface::Boxes
    }

    fn bounds(&self) -> Aabb {
        self.world_bounds(self.mode)
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        self.intersect_mode_counted(ray, self.mode, steps).map(|h| h.hit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MlhmMaterial;
    use relief_core::MlhmColumn;

    const INF: f32 = f32::INFINITY;

    /// Two cells: (0, 0) flat ground at 1 m; (1, 0) ground at 1 m with a rock from 2 m to 3 m.
    fn overhang() -> MlhmNaiveTracer {
        let mut map = Mlhm::new(2, 1, 2, 2.0).unwrap();
        map.set_cell(0, 0, &[MlhmColumn::new(1.0, 0.0, 0.0, INF)]).unwrap();
        map.set_cell(
            1,
            0,
            &[MlhmColumn::new(0.5, 0.5, 0.0, 2.0), MlhmColumn::new(2.5, 0.5, 0.0, INF)],
        )
        .unwrap();
        MlhmNaiveTracer::new(Arc::new(map), DVec2::new(10.0, 20.0))
    }

    #[test]
    fn horizontal_ray_under_the_overhang_passes_and_above_hits_its_side() {
        let t = overhang();
        let under = Ray::new(DVec3::new(9.0, 21.0, 1.5), DVec3::X);
        assert_eq!(t.intersect_mode(&under, MlhmMode::Solids), None);
        let at_rock = Ray::new(DVec3::new(9.0, 21.0, 2.5), DVec3::X);
        let hit = t.intersect_mode(&at_rock, MlhmMode::Solids).unwrap();
        assert_eq!((hit.hit.t, hit.hit.normal, hit.cell, hit.column), (3.0, -DVec3::X, (1, 0), 1));
        assert_eq!(hit.material, MlhmMaterial::Bedrock);
    }

    #[test]
    fn rays_from_the_cave_hit_its_ceiling_and_floor() {
        let t = overhang();
        let up = Ray::new(DVec3::new(13.0, 21.0, 1.5), DVec3::Z);
        let hit = t.intersect_mode(&up, MlhmMode::SolidsWater).unwrap();
        assert_eq!((hit.hit.t, hit.hit.normal), (0.5, -DVec3::Z));
        let down = Ray::new(DVec3::new(13.0, 21.0, 1.5), -DVec3::Z);
        let hit = t.intersect_mode(&down, MlhmMode::SolidsWater).unwrap();
        assert_eq!((hit.hit.t, hit.hit.normal, hit.material), (0.5, DVec3::Z, MlhmMaterial::Sand));
        let inside = Ray::new(DVec3::new(13.0, 21.0, 0.25), DVec3::new(1.0, 0.0, 1.0));
        let hit = t.intersect_mode(&inside, MlhmMode::Solids).unwrap();
        assert_eq!((hit.hit.t, hit.material), (0.0, MlhmMaterial::Bedrock));
    }

    #[test]
    fn rays_on_cell_boundaries_take_the_half_open_cell() {
        let t = overhang();
        // x = 12 is the boundary between cell 0 (ground at 1 m) and cell 1 (sand to 1 m,
        // rock from 2 m to 3 m).
        let down = Ray::new(DVec3::new(12.0, 21.0, 5.0), -DVec3::Z);
        let hit = t.intersect_mode(&down, MlhmMode::Solids).unwrap();
        assert_eq!((hit.hit.t, hit.cell, hit.column), (2.0, (1, 0), 1));
        // Along the southern edge of the grid, eastwards at 2.5 m: the rock's west face.
        let east = Ray::new(DVec3::new(10.0, 20.0, 2.5), DVec3::X);
        let hit = t.intersect_mode(&east, MlhmMode::SolidsWater).unwrap();
        assert_eq!((hit.hit.t, hit.hit.normal), (2.0, -DVec3::X));
        for mode in MlhmMode::ALL {
            assert_eq!(mode.name().parse::<MlhmMode>(), Ok(mode));
        }
        assert!("water".parse::<MlhmMode>().is_err());
    }

    #[test]
    fn degenerate_rays_miss_without_panicking() {
        let t = overhang();
        let nan = f64::NAN;
        for ray in [
            Ray::new(DVec3::new(nan, 0.0, 0.0), DVec3::Z),
            Ray::new(DVec3::ZERO, DVec3::ZERO),
            Ray::new(DVec3::ZERO, DVec3::new(f64::INFINITY, 0.0, 0.0)),
            Ray::new(DVec3::new(11.0, 21.0, 5.0), -DVec3::Z).with_range(nan, 1.0),
            Ray::new(DVec3::new(11.0, 21.0, 5.0), -DVec3::Z).with_range(2.0, 1.0),
        ] {
            for mode in MlhmMode::ALL {
                assert_eq!(t.intersect_mode(&ray, mode), None, "{ray:?}");
            }
        }
        // Huge values lose all precision but must not panic: a miss and a hit are both
        // legitimate answers, but a hit is a point at a real distance, in the scene.
        let huge = Ray::new(DVec3::splat(1e308), DVec3::splat(-1e308));
        let tiny = Ray::new(DVec3::new(10.0, 21.0, 5.0), DVec3::new(1e-320, 0.0, -1.0));
        for mode in MlhmMode::ALL {
            if let Some(found) = t.intersect_mode(&huge, mode) {
                assert!(found.hit.t.is_finite() && found.hit.t >= 0.0, "{mode}: {found:?}");
                assert!(found.cell.0 < 2 && found.cell.1 < 1, "{mode}: {found:?}");
            }
            assert_eq!(t.intersect_mode(&tiny, mode), None, "{mode}");
        }
    }
}
