//! The deferred shading pass: one parallel sweep over a G-buffer that lights every pixel.

use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec3, Ray};
use relief_trace::Tracer;

use crate::error::non_negative;
use crate::gbuffer::image_plane;
use crate::pixel_mask::PixelMask;
use crate::simd_shading::shade_strip_in_lanes;
use crate::sky::validate_fog_density;
use crate::tonemap::srgb8_pixel;
use crate::{
    aerial_perspective, ambient_lighting, direct_lighting, fog_density_for_scene, ground_footprint,
    shadow_ray, slope_from_normal, Albedo, GBuffer, GgxSpecular, HypsometricRamp, RayBatch,
    ShadeError, ShadingKernel, ShadingNormals, Sky, Sun, Tile, TraceStats, TILE_SIZE,
};

/// Everything the deferred pass needs besides the G-buffer: lights, materials, atmosphere.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadingParams {
    /// The sun: direction and irradiance `E`.
    pub sun: Sun,
    /// The sky: background gradient, ambient light and fog colour.
    pub sky: Sky,
    /// The terrain's diffuse albedo.
    pub albedo: Albedo,
    /// Whether to trace a shadow ray towards the sun from every lit pixel.
    pub shadows: bool,
    /// The GGX specular lobe, or `None` for a purely Lambertian terrain.
    pub specular: Option<GgxSpecular>,
    /// Aerial perspective: fog density per world unit (0 for none); see
    /// [`fog_density_for_scene`].
    pub fog_density: f64,
    /// Exposure to tone-map the result with (see [`crate::tonemap_to_srgb8`]).
    pub exposure: f64,
    /// Whether the passes that end in 8-bit sRGB ([`shade_to_srgb8`],
    /// [`crate::render_to_srgb8`]) light every pixel in `f64`. Off, pixels the `f32` kernel
    /// covers ([`crate::ShadingKernel`]) are lit in `f32` lanes, within one 8-bit step per
    /// channel of the `f64` picture and several times faster.
    pub precise: bool,
    /// The normals that light the hits: the G-buffer's exact geometric ones, or a height
    /// field's smooth ones ([`ShadingNormals`]); the sun's visibility stays the geometric
    /// normal's either way.
    pub normals: ShadingNormals,
}

impl Default for ShadingParams {
    /// Default sun and sky, a uniform grey albedo of 0.3, shadows, rough GGX specular, no fog,
    /// exposure 1, the `f32` kernel where it covers the pixels, faceted normals (smooth ones
    /// need the surface that gives them). [`ShadingParams::for_terrain`] fits the ramp and fog
    /// to a terrain instead.
    fn default() -> Self {
        ShadingParams {
            sun: Sun::default(),
            sky: Sky::default(),
            albedo: Albedo::Uniform([0.3; 3]),
            shadows: true,
            specular: Some(GgxSpecular::default()),
            fog_density: 0.0,
            exposure: 1.0,
            precise: false,
            normals: ShadingNormals::Faceted,
        }
    }
}

impl ShadingParams {
    /// Whether shading with these parameters traces shadow rays towards the sun: shadows on,
    /// the sun up and shining.
    pub fn traces_shadow_rays(&self) -> bool {
        self.shadows && self.sun.is_up() && self.sun.irradiance > 0.0
    }

    /// The defaults, with the hypsometric ramp spanning the elevations of `bounds` and fog
    /// scaled to its diagonal (30% at twice the diagonal).
    ///
    /// Fails when `bounds` is not finite or its z range is inverted.
    pub fn for_terrain(bounds: &Aabb) -> Result<Self, ShadeError> {
        Ok(ShadingParams {
            albedo: Albedo::Hypsometric(HypsometricRamp::new(bounds.min.z, bounds.max.z)?),
            fog_density: fog_density_for_scene(bounds.diagonal()),
            ..ShadingParams::default()
        })
    }

    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), ShadeError> {
        self.sun.validate()?;
        self.sky.validate()?;
        self.albedo.validate()?;
        if let Some(specular) = &self.specular {
            specular.validate()?;
        }
        validate_fog_density(self.fog_density)?;
        non_negative("exposure", self.exposure)
    }
}

/// Shades every pixel of `gbuffer`, which `camera` saw, into linear radiance (row-major,
/// row 0 the top row), and counts the shadow rays traced through `tracer`.
///
/// A hit pixel gets [`direct_lighting`] from the sun (its visibility from a shadow ray when
/// `params.shadows`), plus [`ambient_lighting`] from the sky, then [`aerial_perspective`]
/// towards the sky colour along the view ray. A miss gets the sky's colour along its ray.
/// Strips of tiles are shaded in parallel, each tile's shadow rays traced as one batch
/// ([`Tracer::occluded_batch`]); the result does not depend on the thread count.
///
/// The hit point is rebuilt from the eye and the stored distance in `f64` rather than read
/// from the `f32` positions, which lose precision far from the world origin.
///
/// Fails when a parameter is invalid or the G-buffer does not match the camera's image size.
pub fn shade(
    gbuffer: &GBuffer,
    tracer: &dyn Tracer,
    camera: &Camera,
    params: &ShadingParams,
) -> Result<(Vec<[f32; 3]>, TraceStats), ShadeError> {
    shade_with(gbuffer, tracer, camera, params, |radiance| radiance.as_vec3().to_array())
}

/// As [`shade`] followed by [`crate::tonemap_to_srgb8`] with `params.exposure`, pixel by
/// pixel, without holding the linear image: the same bytes with a sixth of the memory when
/// `params.precise` is set or the `f32` kernel does not cover the parameters
/// ([`ShadingKernel`]); else lit in `f32` lanes, within one 8-bit step per channel of those
/// bytes, with the same shadow rays.
pub fn shade_to_srgb8(
    gbuffer: &GBuffer,
    tracer: &dyn Tracer,
    camera: &Camera,
    params: &ShadingParams,
) -> Result<(Vec<[u8; 3]>, TraceStats), ShadeError> {
    params.validate()?;
    gbuffer.validate_for(camera)?;
    let kernel = ShadingKernel::new(camera, params);
    let width = gbuffer.width;
    let mut rgb = image_plane(gbuffer.len(), [0u8; 3], "shaded image")?;
    let pass = ShadingPass::new(gbuffer, 0, tracer, camera, params);
    let stats = rgb
        .par_chunks_mut(TILE_SIZE * width)
        .enumerate()
        .map(|(s, strip)| pass.shade_strip_srgb8(s * TILE_SIZE, strip, kernel.as_ref()))
        .reduce(TraceStats::default, TraceStats::merge);
    Ok((rgb, stats))
}

/// The deferred pass of [`shade`], each pixel's radiance stored as `store` makes it.
fn shade_with<T: Copy + Default + Send>(
    gbuffer: &GBuffer,
    tracer: &dyn Tracer,
    camera: &Camera,
    params: &ShadingParams,
    store: impl Fn(DVec3) -> T + Sync,
) -> Result<(Vec<T>, TraceStats), ShadeError> {
    params.validate()?;
    gbuffer.validate_for(camera)?;
    let width = gbuffer.width;
    let mut radiance = image_plane(gbuffer.len(), T::default(), "shaded image")?;
    let pass = ShadingPass::new(gbuffer, 0, tracer, camera, params);
    let stats = radiance
        .par_chunks_mut(TILE_SIZE * width)
        .enumerate()
        .map(|(s, strip)| pass.shade_strip(s * TILE_SIZE, strip, &store))
        .reduce(TraceStats::default, TraceStats::merge);
    Ok((radiance, stats))
}

/// The pixels of one tile, seen and lit, with their shadow rays traced as one batch.
#[derive(Default)]
struct ShadowTile {
    /// Each pixel's camera ray.
    camera_rays: Vec<Ray>,
    /// What each pixel sees.
    views: Vec<View>,
    /// The shadow rays of the pixels that need one.
    batch: RayBatch,
    /// Which pixel of the tile each shadow ray belongs to.
    owners: Vec<usize>,
    /// The sun's visibility per pixel of the tile (0 for pixels that face away or miss).
    visibility: Vec<f64>,
}

impl ShadowTile {
    /// Looks up what the pixels of `tile` see, traces the shadow rays of those that need one
    /// and records every pixel's visibility.
    fn trace(&mut self, pass: &ShadingPass, tile: Tile, stats: &mut TraceStats) {
        self.camera_rays.clear();
        self.views.clear();
        self.batch.clear();
        self.owners.clear();
        self.visibility.clear();
        tile.camera_rays(pass.camera, &mut self.camera_rays);
        for (n, ((i, j), &ray)) in tile.pixels().zip(&self.camera_rays).enumerate() {
            // A pixel a mask leaves out is not drawn: seen as a miss, it costs no shadow ray.
            let view = match pass.mask {
                Some(mask) if !mask.contains(i, j) => View { ray, hit: None },
                _ => pass.view(i, j, ray),
            };
            let visibility = match pass.lighting(&view) {
                Lighting::Unlit => 0.0,
                Lighting::Lit => 1.0,
                Lighting::Shadowed(ray) => {
                    self.batch.rays.push(ray);
                    self.owners.push(n);
                    0.0
                }
            };
            self.views.push(view);
            self.visibility.push(visibility);
        }
        trace_shadows(&mut self.batch, pass.tracer, &self.owners, &mut self.visibility, stats);
    }
}

/// Traces the shadow rays of `batch` with `tracer`, sets the visibility of each ray's owner
/// (`owners[k]` indexes `visibility`) to 0 where the ray is occluded and 1 where it is not, and
/// counts the rays in `stats`.
pub(crate) fn trace_shadows<T: From<u8>>(
    batch: &mut RayBatch,
    tracer: &dyn Tracer,
    owners: &[usize],
    visibility: &mut [T],
    stats: &mut TraceStats,
) {
    batch.occlude(tracer);
    for ((&n, &occluded), &steps) in owners.iter().zip(&batch.occluded).zip(&batch.steps) {
        stats.record(steps, occluded);
        visibility[n] = T::from(!occluded as u8);
    }
}

/// What a pixel sees: its view ray and, on a hit, the distance, position and unit normal.
struct View {
    ray: Ray,
    hit: Option<ViewHit>,
}

/// A hit as a pixel sees it.
#[derive(Clone, Copy)]
struct ViewHit {
    distance: f64,
    position: DVec3,
    /// The unit geometric normal: whether and whence the sun is seen.
    geometric: DVec3,
    /// The unit normal that lights it ([`ShadingNormals::at`]).
    shading: DVec3,
}

/// How the sun reaches a pixel, before shadows are traced.
enum Lighting {
    /// Not at all: a miss, a surface facing away, or no sun.
    Unlit,
    /// Fully: shadows are off.
    Lit,
    /// Unless this shadow ray is occluded.
    Shadowed(Ray),
}

/// The per-pass constants of [`shade`], over a G-buffer of whole rows of the camera's image
/// from `first_row` on (all of them, or a strip).
pub(crate) struct ShadingPass<'a> {
    pub(crate) gbuffer: &'a GBuffer,
    first_row: usize,
    pub(crate) tracer: &'a dyn Tracer,
    pub(crate) camera: &'a Camera,
    pub(crate) params: &'a ShadingParams,
    pub(crate) to_sun: DVec3,
    sky_ambient: DVec3,
    /// The pixels shaded, where not all ([`ShadingPass::marked`]).
    pub(crate) mask: Option<&'a PixelMask>,
}

impl<'a> ShadingPass<'a> {
    /// The pass that shades `gbuffer`, whose row 0 is row `first_row` of `camera`'s image,
    /// tracing shadow rays through `tracer`; the parameters must be valid.
    pub(crate) fn new(
        gbuffer: &'a GBuffer,
        first_row: usize,
        tracer: &'a dyn Tracer,
        camera: &'a Camera,
        params: &'a ShadingParams,
    ) -> Self {
        ShadingPass {
            gbuffer,
            first_row,
            tracer,
            camera,
            params,
            to_sun: params.sun.direction(),
            sky_ambient: params.sky.ambient(),
            mask: None,
        }
    }

    /// The pass shading only the pixels `mask` marks (in whole tiles, or runs of
    /// [`TILE_SIZE`] pixels of a row, that hold one): the others are left as they were.
    pub(crate) fn marked(self, mask: Option<&'a PixelMask>) -> Self {
        ShadingPass { mask, ..self }
    }

    /// Shades the image rows from `top` on (at most [`TILE_SIZE`], all in the G-buffer) into
    /// `out`, tile by tile: the shadow rays of a tile go to the tracer as one batch, then its
    /// pixels are shaded and stored as `store` makes them.
    pub(crate) fn shade_strip<T>(
        &self,
        top: usize,
        out: &mut [T],
        store: &impl Fn(DVec3) -> T,
    ) -> TraceStats {
        let width = self.gbuffer.width;
        let rows = out.len() / width;
        let mut stats = TraceStats::default();
        let mut shadows = ShadowTile::default();
        for tile_x in (0..width).step_by(TILE_SIZE) {
            let tile = Tile::new(tile_x, top, width, top + rows);
            if self.mask.is_some_and(|m| !m.any_in_tile(tile)) {
                continue;
            }
            shadows.trace(self, tile, &mut stats);
            let seen = shadows.views.iter().zip(&shadows.visibility);
            for ((i, j), (view, &visibility)) in tile.pixels().zip(seen) {
                out[i + (j - top) * width] = store(self.radiance(i, j, view, visibility));
            }
        }
        stats
    }

    /// As [`ShadingPass::shade_strip`] into 8-bit sRGB with `params.exposure`: in `f32`
    /// lanes when `kernel` is given (see [`shade_strip_in_lanes`]), else in `f64`.
    pub(crate) fn shade_strip_srgb8(
        &self,
        top: usize,
        out: &mut [[u8; 3]],
        kernel: Option<&ShadingKernel>,
    ) -> TraceStats {
        match kernel {
            Some(kernel) => shade_strip_in_lanes(self, kernel, top, out),
            None => {
                let exposure = self.params.exposure as f32;
                let store = |radiance: DVec3| srgb8_pixel(radiance.as_vec3().to_array(), exposure);
                self.shade_strip(top, out, &store)
            }
        }
    }

    /// The G-buffer index of image pixel (i, j).
    #[inline]
    pub(crate) fn index(&self, i: usize, j: usize) -> usize {
        i + (j - self.first_row) * self.gbuffer.width
    }

    /// What pixel (i, j), whose camera ray is `ray`, sees.
    #[inline]
    fn view(&self, i: usize, j: usize, ray: Ray) -> View {
        let g = self.gbuffer;
        let k = self.index(i, j);
        let distance = g.distance[k] as f64;
        if !distance.is_finite() {
            return View { ray, hit: None };
        }
        let geometric = DVec3::from(g.normal[k].map(f64::from)).normalize_or_zero();
        let position = ray.at(distance);
        let shading = self.params.normals.at(position, geometric, distance);
        View { ray, hit: Some(ViewHit { distance, position, geometric, shading }) }
    }

    /// How the sun reaches what `view` sees: whether it needs a shadow ray (see
    /// [`shadow_ray`]).
    ///
    /// Both the facing test and the shadow ray's origin (offset along the normal) use the
    /// exact geometric normal, whatever normals light the hit: a facet that faces away from
    /// the sun is in its own shadow on the exact surface, so a smooth normal that still faces
    /// the sun there would send a shadow ray into the next facet and speckle lit slopes at a
    /// low sun with self-shadowing acne. The shadows are therefore the faceted picture's, bit
    /// for bit; the smooth normal only grades the light ([`direct_lighting`] gives nothing
    /// where it faces away).
    fn lighting(&self, view: &View) -> Lighting {
        let p = self.params;
        let Some(ViewHit { distance, position, geometric: normal, .. }) = view.hit else {
            return Lighting::Unlit;
        };
        let lit = p.sun.is_up() && p.sun.irradiance > 0.0 && normal.dot(self.to_sun) > 0.0;
        match (lit, p.shadows) {
            (false, _) => Lighting::Unlit,
            (true, false) => Lighting::Lit,
            (true, true) => Lighting::Shadowed(shadow_ray(position, normal, distance, self.to_sun)),
        }
    }

    /// Radiance of pixel (i, j), which sees `view` with sun visibility `visibility`.
    #[inline]
    fn radiance(&self, i: usize, j: usize, view: &View, visibility: f64) -> DVec3 {
        let (g, p) = (self.gbuffer, self.params);
        let ray = view.ray;
        let sky = p.sky.radiance(ray.dir);
        let Some(ViewHit { distance, position, shading: normal, .. }) = view.hit else {
            return sky;
        };
        let albedo = match &p.albedo {
            Albedo::Filtered(source) => {
                let slope =
                    source.0.tangent_slope(position).unwrap_or_else(|| slope_from_normal(normal));
                let footprint = ground_footprint(self.camera, i as u32, j as u32, position, slope);
                source.0.albedo(&footprint)
            }
            Albedo::GBufferColour { .. } => {
                let m = g.material[self.index(i, j)];
                DVec3::new(m[0] as f64, m[1] as f64, m[2] as f64)
            }
            other => other.at(position, normal, g.uv[self.index(i, j)]),
        };
        let direct = direct_lighting(
            albedo,
            normal,
            -ray.dir,
            self.to_sun,
            p.sun.irradiance,
            visibility,
            p.specular.as_ref(),
        );
        let surface = direct + ambient_lighting(albedo, normal, self.sky_ambient);
        aerial_perspective(surface, sky, distance, p.fog_density)
    }
}
