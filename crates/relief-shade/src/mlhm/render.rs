//! The MLHM renderer: primary rays, water reflections and refractions, sun shadows and the
//! geometric ambient occlusion of Nilles & Müller (2025), section 4.6, shaded per pixel.

use super::brdf::{
    fresnel, reflect, refract, MicrofacetLobe, TERRAIN_F0, TERRAIN_ROUGHNESS,
    TERRAIN_UNDER_WATER_F0, WATER_F0, WATER_IOR, WATER_ROUGHNESS,
};
use super::environment::{reference_sky, SkyLight};
use super::materials::{solid_albedo, WATER_COLOUR};
use super::water::{absorption_distance, water_transmittance};
use super::{MlhmPreset, MlhmQuality};
use crate::error::non_negative;
use crate::{
    shadow_ray_offset, GBuffer, GBufferPixel, ShadeError, Sky, Sun, TraceStats, TILE_SIZE,
};
use rayon::prelude::*;
use relief_core::{Camera, DVec2, DVec3, Mlhm, Ray};
use relief_trace::{Medium, MlhmHit, MlhmMaterial, MlhmMode, MlhmTracer};
use std::f64::consts::PI;

/// The default strength of the sky's light: with the default sun 35 degrees up, flat open
/// ground gets about a third of its light from the sky, as on a clear day.
pub const SKY_LIGHT: f64 = 0.4;

/// Lights, preset and exposure of an MLHM rendering.
#[derive(Debug, Clone, PartialEq)]
pub struct MlhmShading {
    /// What the rendering computes (see [`MlhmPreset::quality`]).
    pub quality: MlhmQuality,
    /// The sun: direction and irradiance.
    pub sun: Sun,
    /// The sky seen behind the terrain and lighting it.
    pub sky: Sky,
    /// How brightly the sky lights the terrain relative to how bright it looks (the reference
    /// renderer's ambient light intensity against its sun).
    pub sky_light: f64,
    /// Exposure before tone mapping (see [`crate::tonemap_reinhard_to_rgb8`]).
    pub exposure: f64,
}

impl MlhmShading {
    /// The reference look at `preset`: the default sun, the reference sky lighting with
    /// [`SKY_LIGHT`], exposure 1.
    pub fn new(preset: MlhmPreset) -> Self {
        MlhmShading {
            quality: preset.quality(),
            sun: Sun::default(),
            sky: reference_sky(),
            sky_light: SKY_LIGHT,
            exposure: 1.0,
        }
    }

    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), ShadeError> {
        self.sun.validate()?;
        self.sky.validate()?;
        if let Some(a) = self.quality.ao_radius {
            if !(a.is_finite() && a > 0.0) {
                return Err(ShadeError::parameter(
                    "AO radius",
                    format!("{a} is not a positive length"),
                ));
            }
        }
        non_negative("sky light", self.sky_light)?;
        non_negative("exposure", self.exposure)
    }
}

/// The rays and lookups a rendering made, by kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MlhmRayCounts {
    /// Camera rays.
    pub primary: TraceStats,
    /// Shadow rays towards the sun.
    pub shadow: TraceStats,
    /// Rays reflected off water.
    pub reflection: TraceStats,
    /// Rays refracted through water.
    pub refraction: TraceStats,
    /// Upward rays to the water surface (expensive absorption); in box mode each stays in
    /// its cell.
    pub upward: TraceStats,
    /// Ambient-occlusion volumes measured.
    pub occlusion: u64,
}

impl MlhmRayCounts {
    /// The counts of both `self` and `other`.
    #[must_use]
    pub fn merge(self, other: MlhmRayCounts) -> MlhmRayCounts {
        MlhmRayCounts {
            primary: self.primary.merge(other.primary),
            shadow: self.shadow.merge(other.shadow),
            reflection: self.reflection.merge(other.reflection),
            refraction: self.refraction.merge(other.refraction),
            upward: self.upward.merge(other.upward),
            occlusion: self.occlusion + other.occlusion,
        }
    }

    /// Rays traced through the scene: primary, shadow, reflected, refracted and upward rays.
    pub fn rays(&self) -> u64 {
        self.primary.rays
            + self.shadow.rays
            + self.reflection.rays
            + self.refraction.rays
            + self.upward.rays
    }
}

/// A rendered MLHM image.
#[derive(Debug, Clone, PartialEq)]
pub struct MlhmImage {
    /// What the camera rays hit (distance, position, normal; material weights are bedrock,
    /// sand, water and air, one-hot).
    pub gbuffer: GBuffer,
    /// Linear radiance per pixel, row-major, row 0 the top row.
    pub radiance: Vec<[f32; 3]>,
    /// The rays traced.
    pub counts: MlhmRayCounts,
}

/// Renders the MLHM that `tracer` traces, as `camera` sees it, with `shading`.
///
/// Each pixel's camera ray meets the visible surface (solids and water; solids and air for a
/// camera under water). Terrain gets the sun through the reference BRDF (shadowed by a shadow
/// ray when the preset says so), the sky's light scaled by the geometric AO, and an albedo
/// blended from the volumes of bedrock and sand within one cell of the hit. Water reflects and
/// refracts by one secondary ray each (or is shaded as an opaque surface at the low preset);
/// light under water is absorbed by Beer's law. Strips of [`TILE_SIZE`] rows are rendered in
/// parallel, tile by tile; the result does not depend on the thread count. `progress` gets the
/// pixels of each finished tile.
///
/// Fails when a parameter is invalid or the image cannot be allocated.
pub fn render_mlhm(
    tracer: &dyn MlhmTracer,
    camera: &Camera,
    shading: &MlhmShading,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<MlhmImage, ShadeError> {
    shading.validate()?;
    let (width, height) = (camera.width() as usize, camera.height() as usize);
    let mut gbuffer = GBuffer::new(width, height)?;
    let mut radiance = vec![[0.0f32; 3]; width * height];
    let map = tracer.map().as_ref();
    let pass = Pass {
        tracer,
        map,
        origin: tracer.origin(),
        camera,
        quality: shading.quality,
        sun: shading.sun,
        to_sun: shading.sun.direction(),
        sky: SkyLight::new(shading.sky, shading.sky_light),
    };
    let mut pixels = vec![GBufferPixel::MISS; width * height];
    let strip = TILE_SIZE * width;
    let counts = pixels
        .par_chunks_mut(strip)
        .zip(radiance.par_chunks_mut(strip))
        .enumerate()
        .map(|(s, (pixels, radiance))| {
            let mut counts = MlhmRayCounts::default();
            let rows = pixels.len() / width;
            for tile_x in (0..width).step_by(TILE_SIZE) {
                let cols = tile_x..(tile_x + TILE_SIZE).min(width);
                for r in 0..rows {
                    for i in cols.clone() {
                        let (pixel, light) = pass.pixel(i, s * TILE_SIZE + r, &mut counts);
                        pixels[i + r * width] = pixel;
                        radiance[i + r * width] = light.as_vec3().to_array();
                    }
                }
                progress((cols.len() * rows) as u64);
            }
            counts
        })
        .reduce(MlhmRayCounts::default, MlhmRayCounts::merge);
    for (k, p) in pixels.iter().enumerate() {
        gbuffer.set_pixel(k, p)?;
    }
    Ok(MlhmImage { gbuffer, radiance, counts })
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

/// The per-rendering constants.
struct Pass<'a> {
    tracer: &'a dyn MlhmTracer,
    map: &'a Mlhm,
    origin: DVec2,
    camera: &'a Camera,
    quality: MlhmQuality,
    sun: Sun,
    to_sun: DVec3,
    sky: SkyLight,
}

impl Pass<'_> {
    /// The G-buffer entry and radiance of pixel `(i, j)`.
    fn pixel(&self, i: usize, j: usize, counts: &mut MlhmRayCounts) -> (GBufferPixel, DVec3) {
        // (i, j) lies inside the camera's u32 image.
        let ray = self.camera.ray(i as u32, j as u32);
        let in_water = matches!(self.tracer.medium(ray.origin), Medium::Water { .. });
        let hit = self.trace(&ray, in_water, &mut counts.primary);
        let light = self.radiance(&ray, hit, in_water, 0.0, Bounce::Primary, counts);
        let Some(h) = hit else { return (GBufferPixel::MISS, light) };
        let mut material = [0.0f32; 4];
        material[match h.material {
            MlhmMaterial::Bedrock => 0,
            MlhmMaterial::Sand => 1,
            MlhmMaterial::Water => 2,
            MlhmMaterial::Air => 3,
        }] = 1.0;
        let s = self.map.cell_size();
        let size = DVec2::new(self.map.width() as f64, self.map.height() as f64) * s;
        let uv = ((h.hit.position.truncate() - self.origin) / size).clamp(DVec2::ZERO, DVec2::ONE);
        let pixel = GBufferPixel {
            distance: h.hit.t as f32,
            position: h.hit.position.as_vec3().to_array(),
            normal: h.hit.normal.as_vec3().to_array(),
            material,
            uv: uv.as_vec2().to_array(),
            footprint: self.camera.pixel_footprint(h.hit.t) as f32,
        };
        (pixel, light)
    }

    /// The first hit of `ray` with what stops it: solids and water from air, solids and air
    /// from inside water.
    fn trace(&self, ray: &Ray, in_water: bool, stats: &mut TraceStats) -> Option<MlhmHit> {
        let mode = if in_water { MlhmMode::SolidsAir } else { MlhmMode::SolidsWater };
        let mut steps = 0;
        let hit = self.tracer.intersect_mode_counted(ray, mode, &mut steps);
        stats.record(steps, hit.is_some());
        hit
    }

    /// Radiance arriving along `ray` from its first `hit` (`None`: it escaped), for a ray
    /// travelling in water when `in_water`; `travelled` is the path length before `ray`.
    fn radiance(
        &self,
        ray: &Ray,
        hit: Option<MlhmHit>,
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
            super::WaterAbsorption::Cheap => 0.0,
            super::WaterAbsorption::Expensive if h.material == MlhmMaterial::Air => 0.0,
            super::WaterAbsorption::Expensive => {
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

    /// Visibility of the sun from `p` (normal `n`): by a shadow ray through the solids when
    /// shadows are on for this bounce (see [`MlhmTracer::light_visibility`]), else 1 on the
    /// lit side.
    fn sun_visibility(
        &self,
        p: DVec3,
        n: DVec3,
        along: f64,
        lit: bool,
        counts: &mut MlhmRayCounts,
    ) -> f64 {
        if !self.sun.is_up() || n.dot(self.to_sun) <= 0.0 {
            return 0.0;
        }
        if !(self.quality.shadows && lit) {
            return 1.0;
        }
        let ray = Ray::new(p + n * self.bias(p, along), self.to_sun);
        let mut steps = 0;
        let visibility = self.tracer.light_visibility(&ray, &mut steps);
        counts.shadow.record(steps, visibility < 1.0);
        visibility
    }

    /// The geometric ambient occlusion at `p` of normal `n`: with `V` the solid volume in the
    /// cube of half-size `a` centred at `p + a n`, `(1 - V / (2a)³)²`.
    fn occlusion(&self, p: DVec3, n: DVec3, lit: bool, counts: &mut MlhmRayCounts) -> f64 {
        let Some(a) = self.quality.ao_radius.filter(|_| lit) else { return 1.0 };
        counts.occlusion += 1;
        let centre = p - self.origin.extend(0.0) + n * a;
        let solid = self.map.solid_volume(centre - a, centre + a);
        let free = (1.0 - solid / (8.0 * a * a * a)).clamp(0.0, 1.0);
        free * free
    }

    /// Terrain at hit `h` of `ray`: sun and sky through the reference BRDF.
    fn terrain(
        &self,
        ray: &Ray,
        h: &MlhmHit,
        in_water: bool,
        along: f64,
        bounce: Bounce,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let (p, n, v) = (h.hit.position, h.hit.normal, -ray.dir);
        let lit = bounce == Bounce::Primary || self.quality.secondary_lighting;
        let s = self.map.cell_size();
        let local = p - self.origin.extend(0.0);
        let albedo = solid_albedo(&self.map.material_volumes(local - s, local + s), h.material);
        let f0 = if in_water { TERRAIN_UNDER_WATER_F0 } else { TERRAIN_F0 };
        let lobe = MicrofacetLobe { roughness: TERRAIN_ROUGHNESS, f0 };
        let visibility = self.sun_visibility(p, n, along, lit, counts);
        let n_l = n.dot(self.to_sun).max(0.0);
        let direct = (albedo / PI + DVec3::splat(lobe.specular(n, v, self.to_sun)))
            * (self.sun.irradiance * n_l * visibility);
        let ao = self.occlusion(p, n, lit, counts);
        let glossy = super::brdf::schlick(n.dot(v), f0) * self.sky.irradiance(reflect(-v, n)) / PI;
        direct + (albedo * self.sky.irradiance(n) / PI + glossy) * ao
    }

    /// The sun's highlight on a water surface of normal `n` seen along `v`.
    fn water_highlight(
        &self,
        p: DVec3,
        n: DVec3,
        v: DVec3,
        along: f64,
        lit: bool,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let lobe = MicrofacetLobe { roughness: WATER_ROUGHNESS, f0: WATER_F0 };
        let specular = lobe.specular(n, v, self.to_sun);
        if specular <= 0.0 {
            return DVec3::ZERO;
        }
        let visibility = self.sun_visibility(p, n, along, lit, counts);
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

    /// The water surface seen from air at `p` (normal `n` facing the ray): a reflection and
    /// a refraction ray mixed by Fresnel, or an opaque water colour without secondary rays.
    fn water_from_air(
        &self,
        ray: &Ray,
        p: DVec3,
        n: DVec3,
        along: f64,
        bounce: Bounce,
        counts: &mut MlhmRayCounts,
    ) -> DVec3 {
        let v = -ray.dir;
        let lit = bounce == Bounce::Primary || self.quality.secondary_lighting;
        let f = fresnel(n.dot(v), 1.0 / WATER_IOR, WATER_F0);
        let highlight = self.water_highlight(p, n, v, along, lit, counts);
        let mirror = reflect(ray.dir, n);
        if !(self.quality.water_rays && bounce == Bounce::Primary) {
            let body = DVec3::from(WATER_COLOUR) / PI
                * (self.sky.irradiance(n)
                    + DVec3::splat(self.sun.irradiance * n.dot(self.to_sun).max(0.0)));
            return (1.0 - f) * body + f * self.sky.radiance(mirror) + highlight;
        }
        let eps = self.bias(p, along);
        let reflection =
            self.secondary(p + n * eps, mirror, false, along, Secondary::Reflected, counts);
        let refraction = match refract(ray.dir, n, 1.0 / WATER_IOR) {
            Some(dir) => {
                self.secondary(p - n * eps, dir, true, along, Secondary::Refracted, counts)
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
