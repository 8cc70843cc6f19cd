//! The deferred MLHM lighting (Nilles & Müller 2025, section 4.6): one pass over a G-buffer
//! of MLHM hits ([`super::MlhmRenderer`]) that lights each pixel from its full-precision hit
//! and material. Terrain gets the sun through the reference BRDF (the one GGX lobe with the
//! reference's masking), shadowed by a shadow ray when the preset says so, the sky's light
//! scaled by the geometric AO, and an albedo blended from the volumes of bedrock and sand
//! within one cell of the hit. Water reflects and refracts by one secondary ray each (or is
//! shaded as an opaque surface at the low preset); light under water is absorbed by Beer's
//! law.

use super::brdf::{
    fresnel, reflect, refract, TERRAIN_F0, TERRAIN_ROUGHNESS, TERRAIN_UNDER_WATER_F0, WATER_F0,
    WATER_IOR, WATER_ROUGHNESS,
};
use super::environment::SkyLight;
use super::footprint::{filtered_normal, lift_direction, lit_share};
use super::materials::{solid_albedo, WATER_COLOUR};
use super::preset::{MlhmQuality, WaterAbsorption};
use super::ray_counts::MlhmRayCounts;
use super::renderer::{material_of, trace_visible};
use super::shading::MlhmShading;
use super::water::{absorption_distance, water_transmittance};
use crate::gbuffer::image_plane;
use crate::shading::schlick;
use crate::{
    shadow_ray_offset, GBuffer, GgxSpecular, PixelMask, ShadeError, Sun, TraceStats, TILE_SIZE,
};
use rayon::prelude::*;
use relief_core::{BlurredBox, Camera, DVec2, DVec3, Mlhm, Ray};
use relief_trace::{Hit, Medium, MlhmHit, MlhmMaterial, MlhmMode, MlhmTracer};
use std::f64::consts::PI;

/// How far, in units of the AO cube's half-size, a smooth surface's AO cube is shifted (twice)
/// to average its volume ([`Mlhm::blurred_volumes`]).
const AO_BLUR: f64 = 0.5;

/// Lights every pixel of `gbuffer`, which [`super::MlhmRenderer`] drew for `camera` from the
/// MLHM `tracer` traces, with `shading`: linear radiance per pixel (row-major, row 0 the top
/// row) and the secondary rays and lookups made (the camera rays are the renderer's).
///
/// Strips of [`TILE_SIZE`] rows are lit in parallel, tile by tile; each pixel is computed on
/// its own, from the G-buffer's full-precision hit, so the result does not depend on the
/// thread count.
///
/// Fails when a parameter is invalid, the G-buffer is not the camera's image size or keeps no
/// exact hits, or the image cannot be allocated.
pub fn shade_mlhm(
    gbuffer: &GBuffer,
    tracer: &dyn MlhmTracer,
    camera: &Camera,
    shading: &MlhmShading,
) -> Result<(Vec<[f32; 3]>, MlhmRayCounts), ShadeError> {
    shade_mlhm_marked(gbuffer, tracer, camera, shading, None)
}

/// [`shade_mlhm`] of the pixels `mask` marks only, where there is one (the others are left
/// black): how an anti-aliasing pass lights the pixels it samples again.
pub(crate) fn shade_mlhm_marked(
    gbuffer: &GBuffer,
    tracer: &dyn MlhmTracer,
    camera: &Camera,
    shading: &MlhmShading,
    mask: Option<&PixelMask>,
) -> Result<(Vec<[f32; 3]>, MlhmRayCounts), ShadeError> {
    shading.validate()?;
    gbuffer.validate_for(camera)?;
    if gbuffer.exact_hits.is_none() {
        return Err(ShadeError::Mismatch(
            "the G-buffer keeps no exact hits (draw it with MlhmRenderer)".into(),
        ));
    }
    let width = gbuffer.width;
    let mut radiance = image_plane(gbuffer.len(), [0.0f32; 3], "MLHM radiance")?;
    let pass = Pass {
        tracer,
        map: tracer.map().as_ref(),
        origin: tracer.origin(),
        camera,
        quality: shading.quality,
        sun: shading.sun,
        to_sun: shading.sun.direction(),
        sky: SkyLight::new(shading.sky, shading.sky_light),
        faceted: tracer.faceted(),
        smoothing: tracer.smoothing_radius(),
    };
    let counts = radiance
        .par_chunks_mut(TILE_SIZE * width)
        .enumerate()
        .map(|(s, out)| {
            let mut counts = MlhmRayCounts::default();
            let rows = out.len() / width;
            for tile_x in (0..width).step_by(TILE_SIZE) {
                for r in 0..rows {
                    for i in tile_x..(tile_x + TILE_SIZE).min(width) {
                        let j = s * TILE_SIZE + r;
                        if mask.is_some_and(|m| !m.contains(i, j)) {
                            continue;
                        }
                        let k = i + j * width;
                        let seen = gbuffer.exact_hit(k).map(|hit| SurfaceHit {
                            hit,
                            material: material_of(gbuffer.material[k]),
                        });
                        let light = pass.pixel(i, j, seen, &mut counts);
                        out[i + r * width] = light.as_vec3().to_array();
                    }
                }
            }
            counts
        })
        .reduce(MlhmRayCounts::default, MlhmRayCounts::merge);
    Ok((radiance, counts))
}

/// A surface a ray met: where, and of which material.
#[derive(Debug, Clone, Copy)]
struct SurfaceHit {
    hit: Hit,
    material: MlhmMaterial,
}

impl From<MlhmHit> for SurfaceHit {
    fn from(h: MlhmHit) -> Self {
        SurfaceHit { hit: h.hit, material: h.material }
    }
}

/// Whether a surface is seen straight from the camera or through a reflection or refraction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Bounce {
    Primary,
    Secondary,
}

/// Which of a water surface's two secondary rays a ray is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Secondary {
    Reflected,
    Refracted,
}

/// The per-rendering constants of the MLHM lighting.
struct Pass<'a> {
    tracer: &'a dyn MlhmTracer,
    map: &'a Mlhm,
    origin: DVec2,
    camera: &'a Camera,
    quality: MlhmQuality,
    sun: Sun,
    to_sun: DVec3,
    sky: SkyLight,
    /// Whether the tracer's hits lie on box faces, whose shading terms are filtered over the
    /// pixel's footprint.
    faceted: bool,
    /// The radius over which the tracer's surface smooths the boxes, `None` for the boxes.
    smoothing: Option<f64>,
}

impl Pass<'_> {
    /// The radiance of pixel `(i, j)`, whose camera ray saw `seen` (its full-precision hit
    /// and material from the G-buffer).
    fn pixel(
        &self,
        i: usize,
        j: usize,
        seen: Option<SurfaceHit>,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        // (i, j) lies inside the camera's u32 image.
        let ray = self.camera.ray(i as u32, j as u32);
        let in_water = matches!(self.tracer.medium(ray.origin), Medium::Water { .. });
        self.radiance(&ray, seen, in_water, 0.0, Bounce::Primary, counts)
    }

    /// The first hit of `ray` with what stops it: solids and water from air, solids and air
    /// from inside water.
    fn trace(&self, ray: &Ray, in_water: bool, stats: &mut TraceStats) -> Option<SurfaceHit> {
        trace_visible(self.tracer, ray, in_water, stats).map(SurfaceHit::from)
    }

    /// Radiance arriving along `ray` from its first `hit` (`None`: it escaped), for a ray
    /// travelling in water when `in_water`; `travelled` is the path length before `ray`.
    fn radiance(
        &self,
        ray: &Ray,
        hit: Option<SurfaceHit>,
        in_water: bool,
        travelled: f64,
        bounce: Bounce,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let Some(h) = hit else {
            return if in_water { self.deep_water() } else { self.sky.radiance(ray.dir) };
        };
        let (p, n, t) = (h.hit.position, h.hit.normal, h.hit.t);
        let along = travelled + t;
        let surface = match h.material {
            MlhmMaterial::Bedrock | MlhmMaterial::Sand => {
                self.terrain(ray, &h, in_water, along, bounce, counts)
            }
            MlhmMaterial::Water => self.water_from_air(ray, p, n, along, bounce, counts),
            MlhmMaterial::Air => self.water_from_below(ray, p, n, along, bounce, counts),
        };
        if !in_water {
            return surface;
        }
        let depth = match self.quality.absorption {
            WaterAbsorption::Cheap => 0.0,
            WaterAbsorption::Expensive if h.material == MlhmMaterial::Air => 0.0,
            WaterAbsorption::Expensive => {
                // Straight up through the water to where it ends: in box mode the ray stays
                // in its cell.
                let up = Ray::new(p + n * self.bias(p, along), DVec3::Z);
                let mut steps = 0;
                let end = self.tracer.intersect_mode_counted(&up, MlhmMode::SolidsAir, &mut steps);
                counts.upward.record(steps, end.is_some());
                end.map_or(0.0, |e| e.hit.t)
            }
        };
        surface * water_transmittance(absorption_distance(self.quality.absorption, t, depth))
    }

    /// The offset of a secondary ray's origin off the surface at `p`, `along` the path from
    /// the eye: as [`shadow_ray`](crate::shadow_ray)'s, at least the tracer's
    /// [`surface_offset`](MlhmTracer::surface_offset).
    fn bias(&self, p: DVec3, along: f64) -> f64 {
        shadow_ray_offset(p, along).max(self.tracer.surface_offset())
    }

    /// The colour of water too deep to see through: its colour in the sky's light.
    fn deep_water(&self) -> DVec3 {
        DVec3::from(WATER_COLOUR) * self.sky.irradiance(DVec3::Z) / PI * 0.25
    }

    /// The width of a pixel's footprint at `along` metres from the eye (see
    /// [`Camera::pixel_footprint`]).
    fn footprint(&self, along: f64) -> f64 {
        self.camera.pixel_footprint(along)
    }

    /// Visibility of the sun from `p` on a face of normal `face`, shaded with the normal `n`
    /// (see [`Pass::shading_normal`]): by shadow rays through the solids when shadows are on
    /// for this bounce (see [`MlhmTracer::light_visibility`]), else 1 on the lit side.
    ///
    /// On box faces the shadow is filtered over the `footprint` ([`lit_share`]): the rays
    /// start off the face, shifted across the sun's rays by up to the footprint's width as
    /// the sun sees it (`footprint * n.l`). A smooth surface's soft shadow is taken as the
    /// tracer gives it.
    #[allow(clippy::too_many_arguments)]
    fn sun_visibility(
        &self,
        p: DVec3,
        face: DVec3,
        n: DVec3,
        along: f64,
        footprint: f64,
        lit: bool,
        counts: &mut MlhmRayCounts,
    ) -> f64 {
        let n_l = n.dot(self.to_sun);
        if !self.sun.is_up() || n_l <= 0.0 {
            return 0.0;
        }
        if !(self.quality.shadows && lit) {
            return 1.0;
        }
        let start = p + face * self.bias(p, along);
        let mut shadow_ray = |origin: DVec3| {
            let mut steps = 0;
            let visibility =
                self.tracer.light_visibility(&Ray::new(origin, self.to_sun), &mut steps);
            counts.shadow.record(steps, visibility < 1.0);
            visibility
        };
        if !self.faceted {
            return shadow_ray(start);
        }
        let lift = lift_direction(n, self.to_sun);
        lit_share(footprint * n_l, |shift| shadow_ray(start + lift * shift) < 1.0)
    }

    /// The normal `p` is shaded with, on a face of normal `face` of the solids (or, where
    /// `water`, of the water's surface seen from air) seen over a pixel `footprint` wide: on
    /// box faces, the boxes' normal filtered over the footprint ([`filtered_normal`]); the
    /// face's own on a smooth surface.
    fn shading_normal(&self, p: DVec3, face: DVec3, footprint: f64, water: bool) -> DVec3 {
        if !self.faceted {
            return face;
        }
        filtered_normal(self.map, p - self.origin.extend(0.0), face, footprint, water)
    }

    /// The geometric ambient occlusion at `p` of normal `n`: with `V` the solid volume in the
    /// cube of half-size `a` centred at `p + a n`, `(1 - V / (2a)³)²`. On a smooth surface
    /// `a` is at least its smoothing radius and `V` is averaged over shifts of the cube by up to `AO_BLUR a` twice
    /// ([`Mlhm::blurred_volumes`]): the plain cube's volume of box columns has a kink at
    /// every cell edge and column top, which drew a rib per cell on steep smooth slopes.
    fn occlusion(&self, p: DVec3, n: DVec3, lit: bool, counts: &mut MlhmRayCounts) -> f64 {
        let Some(a) = self.quality.ao_radius.filter(|_| lit) else { return 1.0 };
        // The boxes lie up to about σ off a smooth surface (inside it at a rounded edge): a
        // smaller cube would sit inside them there and read black.
        let a = a.max(self.smoothing.unwrap_or(0.0));
        counts.occlusion += 1;
        let centre = p - self.origin.extend(0.0) + n * a;
        let solid = if self.faceted {
            self.map.solid_volume(centre - a, centre + a)
        } else {
            let k = BlurredBox { half: a, blurs: [AO_BLUR * a; 2] };
            self.map.blurred_volumes(centre, [k; 3]).solid()
        };
        let free = (1.0 - solid / (8.0 * a * a * a)).clamp(0.0, 1.0);
        free * free
    }

    /// Terrain at hit `h` of `ray`: sun and sky through the reference BRDF.
    fn terrain(
        &self,
        ray: &Ray,
        h: &SurfaceHit,
        in_water: bool,
        along: f64,
        bounce: Bounce,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let (p, face, v) = (h.hit.position, h.hit.normal, -ray.dir);
        let footprint = self.footprint(along);
        let n = self.shading_normal(p, face, footprint, false);
        let lit = bounce == Bounce::Primary || self.quality.secondary_lighting;
        let s = self.map.cell_size();
        let local = p - self.origin.extend(0.0);
        let albedo = solid_albedo(&self.map.material_volumes(local - s, local + s), h.material);
        let f0 = if in_water { TERRAIN_UNDER_WATER_F0 } else { TERRAIN_F0 };
        let lobe = GgxSpecular { roughness: TERRAIN_ROUGHNESS, f0 };
        let visibility = self.sun_visibility(p, face, n, along, footprint, lit, counts);
        let n_l = n.dot(self.to_sun).max(0.0);
        let direct = (albedo / PI + DVec3::splat(lobe.brdf_smith_schlick(n, v, self.to_sun)))
            * (self.sun.irradiance * n_l * visibility);
        let ao = self.occlusion(p, n, lit, counts);
        let glossy = schlick(n.dot(v), f0) * self.sky.irradiance(reflect(-v, n)) / PI;
        direct + (albedo * self.sky.irradiance(n) / PI + glossy) * ao
    }

    /// The sun's highlight on a water surface (face normal `face`, shaded with normal `n`)
    /// seen along `v`.
    #[allow(clippy::too_many_arguments)]
    fn water_highlight(
        &self,
        p: DVec3,
        face: DVec3,
        n: DVec3,
        v: DVec3,
        along: f64,
        lit: bool,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let lobe = GgxSpecular { roughness: WATER_ROUGHNESS, f0: WATER_F0 };
        let specular = lobe.brdf_smith_schlick(n, v, self.to_sun);
        if specular <= 0.0 {
            return DVec3::ZERO;
        }
        let footprint = self.footprint(along);
        let visibility = self.sun_visibility(p, face, n, along, footprint, lit, counts);
        DVec3::splat(specular * self.sun.irradiance * n.dot(self.to_sun).max(0.0) * visibility)
    }

    /// Radiance arriving along the secondary ray from `origin` in `dir`, which travels in
    /// water when `in_water`, `along` the path from the eye so far; counted as `kind`.
    fn secondary(
        &self,
        origin: DVec3,
        dir: DVec3,
        in_water: bool,
        along: f64,
        kind: Secondary,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let ray = Ray::new(origin, dir);
        let stats = match kind {
            Secondary::Reflected => &mut counts.reflection,
            Secondary::Refracted => &mut counts.refraction,
        };
        let hit = self.trace(&ray, in_water, stats);
        self.radiance(&ray, hit, in_water, along, Bounce::Secondary, counts)
    }

    /// The water surface seen from air at `p` (face normal `face` facing the ray): a
    /// reflection and a refraction ray mixed by Fresnel, or an opaque water colour without
    /// secondary rays. Directions and Fresnel follow the shading normal
    /// ([`Pass::shading_normal`]); the secondary rays start off the face.
    fn water_from_air(
        &self,
        ray: &Ray,
        p: DVec3,
        face: DVec3,
        along: f64,
        bounce: Bounce,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let v = -ray.dir;
        // A mirror needs the viewer on the normal's side.
        let n = Some(self.shading_normal(p, face, self.footprint(along), true))
            .filter(|n| n.dot(v) > 0.0)
            .unwrap_or(face);
        let lit = bounce == Bounce::Primary || self.quality.secondary_lighting;
        let f = fresnel(n.dot(v), 1.0 / WATER_IOR, WATER_F0);
        let highlight = self.water_highlight(p, face, n, v, along, lit, counts);
        let mirror = reflect(ray.dir, n);
        if !(self.quality.water_rays && bounce == Bounce::Primary) {
            let body = DVec3::from(WATER_COLOUR) / PI
                * (self.sky.irradiance(n)
                    + DVec3::splat(self.sun.irradiance * n.dot(self.to_sun).max(0.0)));
            return (1.0 - f) * body + f * self.sky.radiance(mirror) + highlight;
        }
        let eps = self.bias(p, along);
        let reflection =
            self.secondary(p + face * eps, mirror, false, along, Secondary::Reflected, counts);
        let refraction = match refract(ray.dir, n, 1.0 / WATER_IOR) {
            Some(dir) => {
                self.secondary(p - face * eps, dir, true, along, Secondary::Refracted, counts)
            }
            None => DVec3::ZERO,
        };
        (1.0 - f) * refraction + f * reflection + highlight
    }

    /// The water surface seen from under water at `p` (normal `n` facing down into the
    /// water): a reflection back into the water and a refraction into the air, with total
    /// internal reflection beyond the critical angle.
    fn water_from_below(
        &self,
        ray: &Ray,
        p: DVec3,
        n: DVec3,
        along: f64,
        bounce: Bounce,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let v = -ray.dir;
        let f = fresnel(n.dot(v), WATER_IOR, WATER_F0);
        let refracted_dir = refract(ray.dir, n, WATER_IOR);
        if !(self.quality.water_rays && bounce == Bounce::Primary) {
            let through = refracted_dir.map_or(DVec3::ZERO, |d| self.sky.radiance(d));
            return (1.0 - f) * through + f * self.deep_water();
        }
        let eps = self.bias(p, along);
        let mirror = reflect(ray.dir, n);
        let reflection =
            self.secondary(p + n * eps, mirror, true, along, Secondary::Reflected, counts);
        let refraction = match refracted_dir {
            Some(dir) => {
                self.secondary(p - n * eps, dir, false, along, Secondary::Refracted, counts)
            }
            None => DVec3::ZERO,
        };
        (1.0 - f) * refraction + f * reflection
    }
}
