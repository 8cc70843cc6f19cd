//! What the smooth MLHM tracer ([`MlhmSmoothTracer`]) tells shading (Nilles & Müller 2025,
//! 4.4-4.6): a hit's corrective step, material, normal by finite differences and column, the
//! medium at a point, and the soft shadows of eq. 8.

use super::smooth_tracer::Marched;
use crate::{
    medium_at, Hit, Medium, MlhmField, MlhmHit, MlhmMaterial, MlhmMode, MlhmNormalScheme,
    MlhmSmoothTracer, MlhmTracer,
};
use relief_core::{DVec2, DVec3, MaterialVolumes, Mlhm, Ray};
use std::sync::Arc;

/// How far secondary rays start off a hit along its normal, in units of σ.
const SURFACE_OFFSET: f64 = 0.03;

/// The penumbra's growth with distance (`α_s`, per cell) and its largest size (`β_s`) in the
/// soft shadow (eq. 8).
const PENUMBRA_GROWTH: f64 = 0.01;
const PENUMBRA_MAX: f64 = 0.5;

impl MlhmSmoothTracer {
    /// The hit at the inside sample `marched` of `world_ray`: the corrective step (eq. 7),
    /// material, normal, cell and column.
    fn finish(&self, world_ray: &Ray, mode: MlhmMode, marched: Marched) -> MlhmHit {
        let speed = world_ray.dir.length();
        let missing = self.implicit.target() - marched.sample.volume;
        let mut t = marched.t;
        if missing > 0.0 {
            t = (t + self.implicit.step(missing) / speed).min(world_ray.t_max);
        }
        let position = world_ray.at(t);
        let local = position - self.origin.extend(0.0);
        let volumes = self.implicit.volumes(&self.map, local);
        let field = match mode {
            MlhmMode::Solids => MlhmField::Solid,
            MlhmMode::SolidsWater => MlhmField::SolidWater,
            MlhmMode::SolidsAir => marched.sample.field,
        };
        let solid_material = if volumes.bedrock >= volumes.sand {
            MlhmMaterial::Bedrock
        } else {
            MlhmMaterial::Sand
        };
        let material = match field {
            MlhmField::Air => MlhmMaterial::Air,
            MlhmField::SolidWater if !self.implicit.is_inside(volumes.solid()) => {
                MlhmMaterial::Water
            }
            MlhmField::Solid | MlhmField::SolidWater => solid_material,
        };
        let normal = self.normal(local, field, &volumes, world_ray.dir);
        let s = self.map.cell_size();
        let cell_of = |v: f64, cells: usize| ((v / s).floor().max(0.0) as usize).min(cells - 1);
        let cell = (cell_of(local.x, self.map.width()), cell_of(local.y, self.map.height()));
        // The column whose span, from its floor up to its ceiling, holds the hit.
        let mut column = 0;
        let mut floor = f32::NEG_INFINITY;
        for (k, c) in self.map.cell_columns(cell.0, cell.1).enumerate() {
            if (floor as f64) <= local.z {
                column = k;
            }
            floor = c.ceiling;
        }
        MlhmHit { hit: Hit { t, position, normal }, material, cell, column }
    }

    /// The unit normal `-grad V` of `field` at `local` (whose volumes at radius σ are
    /// `volumes`), facing against `dir`; `-dir` normalised where the gradient vanishes.
    fn normal(
        &self,
        local: DVec3,
        field: MlhmField,
        volumes: &MaterialVolumes,
        dir: DVec3,
    ) -> DVec3 {
        let n = &self.normal_implicit;
        let base = match self.options.normals {
            MlhmNormalScheme::Central | MlhmNormalScheme::Smoothed => 0.0,
            MlhmNormalScheme::Forward if n.radius() == self.implicit.radius() => {
                n.field_volume_from(&self.map, local, field, volumes)
            }
            MlhmNormalScheme::Forward => n.field_volume(&self.map, local, field),
        };
        let gradient = n.gradient_with_base(
            &self.map,
            local,
            field,
            self.normal_spacing,
            self.options.normals,
            base,
        );
        let length = gradient.length();
        if !(length > 0.0 && length.is_finite()) {
            return -dir.normalize();
        }
        let normal = -gradient / length;
        if normal.dot(dir) > 0.0 {
            -normal
        } else {
            normal
        }
    }

    /// Where a shadow ray that starts on (or just inside) the solid surface leaves it: the
    /// first parameter, within 2σ of its start, at which the solid volume is below the hit
    /// volume; `None` when it stays inside that far (the ray starts in the terrain).
    fn leave_start(&self, ray: &Ray, steps: &mut u32) -> Option<f64> {
        let speed = ray.dir.length();
        let limit = ray.t_min + 2.0 * self.implicit.radius() / speed;
        let min_step = 0.01 * self.implicit.radius() / speed;
        let mut t = ray.t_min;
        while t <= limit && t <= ray.t_max {
            *steps = steps.saturating_add(1);
            let local = ray.at(t) - self.origin.extend(0.0);
            let v = self.implicit.field_volume(&self.map, local, MlhmField::Solid);
            if !self.implicit.is_inside(v) {
                return Some(t);
            }
            let excess = v - self.implicit.hit_volume();
            t += (self.implicit.step(excess) / speed).max(min_step);
        }
        None
    }
}

impl MlhmTracer for MlhmSmoothTracer {
    fn map(&self) -> &Arc<Mlhm> {
        &self.map
    }

    fn origin(&self) -> DVec2 {
        self.origin
    }

    /// The smooth surface has no faces: its normals and soft shadows are smooth already.
    fn faceted(&self) -> bool {
        false
    }

    /// σ, the half-size of the cube whose volume defines the surface.
    fn smoothing_radius(&self) -> Option<f64> {
        Some(self.implicit.radius())
    }

    fn intersect_mode_counted(
        &self,
        ray: &Ray,
        mode: MlhmMode,
        steps: &mut u32,
    ) -> Option<MlhmHit> {
        let marched = self.trace(ray, mode, steps, &mut |_, _| {})?;
        Some(self.finish(ray, mode, marched))
    }

    /// The medium as the smooth surfaces see it: solid where the solids' surface holds `p`
    /// inside, water where only the solid + water surface does (its depth the distance
    /// straight up to where a ray leaves the water, or to the water top of the column below
    /// `p` when a solid comes first), air elsewhere and outside the grid's footprint.
    fn medium(&self, p: DVec3) -> Medium {
        let local = p - self.origin.extend(0.0);
        let (w, h) = (self.map.width() as f64, self.map.height() as f64);
        let s = self.map.cell_size();
        if !(local.x >= 0.0 && local.y >= 0.0 && local.x <= w * s && local.y <= h * s) {
            return Medium::Air;
        }
        let volumes = self.implicit.volumes(&self.map, local);
        if self.implicit.is_inside(volumes.solid()) {
            return Medium::Solid;
        }
        if !self.implicit.is_inside(volumes.total()) {
            return Medium::Air;
        }
        let up = Ray::new(p, DVec3::Z);
        let depth = match self.intersect_mode(&up, MlhmMode::SolidsAir) {
            Some(hit) if hit.material == MlhmMaterial::Air => hit.hit.t,
            _ => match medium_at(&self.map, self.origin, p) {
                Medium::Water { depth } => depth,
                Medium::Air | Medium::Solid => 0.0,
            },
        };
        Medium::Water { depth }
    }

    /// `0.03 σ`: a hit holds between 0.99 and 1 times the target volume, and 0.03 σ along
    /// the normal of a flat surface changes that by 3 % of the target, out of the inside of
    /// the surface left (and, for a ray entering water, into the inside of the water).
    fn surface_offset(&self) -> f64 {
        SURFACE_OFFSET * self.implicit.radius()
    }

    /// The soft shadow of eq. 8: with `V` the solid volume at each march sample (inside the
    /// level-1 nodes the ray meets, where the surface is near) at distance `d` from the ray's
    /// origin, `γ = min max(((target - V) / (2σ)³) / min(0.01 d / cell size, 0.5), 0)`,
    /// clamped to `[0, 1]`; 0 when the ray meets the surface (the hard shadow, which stops
    /// light leaking through thin features). Hard shadows only (0 or 1) when
    /// [`MlhmSmoothOptions::soft_shadows`](crate::MlhmSmoothOptions::soft_shadows) is off.
    ///
    /// Shadow rays start on the surface they shade, where the solid volume is about the
    /// target, so the march starts where the ray leaves the inside of the surface (at most
    /// 2σ from its origin; a ray still inside there is in shadow).
    fn light_visibility(&self, ray: &Ray, steps: &mut u32) -> f64 {
        let Some(t_start) = self.leave_start(ray, steps) else {
            return 0.0;
        };
        let ray = ray.with_range(t_start, ray.t_max);
        let (target, cube) = (self.implicit.target(), self.implicit.cube_volume());
        let per_metre = PENUMBRA_GROWTH / self.map.cell_size();
        let speed = ray.dir.length();
        let mut visibility = 1.0f64;
        let soft = self.options.soft_shadows;
        let hit = self.trace(&ray, MlhmMode::Solids, steps, &mut |t, v| {
            let penumbra = (per_metre * t * speed).min(PENUMBRA_MAX);
            if soft && penumbra > 0.0 {
                visibility = visibility.min((((target - v) / cube) / penumbra).max(0.0));
            }
        });
        if hit.is_some() {
            0.0
        } else {
            visibility.clamp(0.0, 1.0)
        }
    }
}
