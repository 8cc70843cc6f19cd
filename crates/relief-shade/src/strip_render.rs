//! The whole render in one pass: each worker traces a strip of rows into a G-buffer of its
//! own, shades it and tone-maps it, so no image-sized G-buffer is ever held.

use std::time::{Duration, Instant};

use rayon::prelude::*;
use relief_core::{Aabb, Camera};
use relief_trace::Tracer;

use crate::deferred::ShadingPass;
use crate::gbuffer::image_plane;
use crate::pixel_mask::PixelMask;
use crate::render::{trace_strip, HitEncoder};
use crate::{GBuffer, ShadeError, ShadingKernel, ShadingParams, TraceStats, TILE_SIZE};

/// What [`render_to_srgb8`] keeps of the primary hits besides the picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct KeptHits {
    /// The distance to each pixel's hit, as [`GBuffer::distance`] holds it.
    pub depth: bool,
    /// Each pixel's unit normal, as [`GBuffer::normal`] holds it.
    pub normals: bool,
}

/// A picture from [`render_to_srgb8`], with what it was asked to keep.
#[derive(Debug, Clone, PartialEq)]
pub struct StripRender {
    /// 8-bit sRGB, row-major from the top.
    pub rgb: Vec<[u8; 3]>,
    /// The depth image (`+inf` for a miss), row-major from the top, when kept.
    pub depth: Option<Vec<f32>>,
    /// The unit normals (zeros for a miss), row-major from the top, when kept.
    pub normals: Option<Vec<[f32; 3]>>,
    /// The rays counted and the time spent.
    pub stats: StripRenderStats,
}

/// What [`render_to_srgb8`] counted and timed.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StripRenderStats {
    /// The camera rays.
    pub primary: TraceStats,
    /// The shadow rays.
    pub shadow: TraceStats,
    /// Milliseconds of the pass's wall time spent tracing camera rays: the wall time split in
    /// proportion to the time the workers spent tracing and shading.
    pub trace_ms: f64,
    /// The rest of the pass's wall time: shading, shadow rays and tone mapping.
    pub shade_ms: f64,
}

/// Renders `camera`'s picture of the terrain `tracer` intersects (world bounds `bounds`) to
/// 8-bit sRGB, its shadow rays traced by `shadow_tracer` (the same tracer, or one that decides
/// the sun's shadow rays faster, as [`relief_trace::SunShadows`] wrapping it does), with the
/// depth and normals `keep` asks for: the bytes (and depth and normals) of
/// [`crate::render_gbuffer`] followed by [`crate::shade_to_srgb8`], without an image-sized
/// G-buffer.
///
/// Strips of [`TILE_SIZE`] rows are traced and shaded in parallel, each in a G-buffer of its
/// worker's (56 bytes a pixel of one strip, which stays in cache, instead of the image's);
/// every pixel is computed as the two-pass render computes it, so the picture is the same
/// byte for byte, whatever the thread count. `progress` is called with each tile's pixel
/// count as its camera rays are traced. Fails when a parameter is invalid or the outputs
/// cannot be allocated.
pub fn render_to_srgb8(
    tracer: &dyn Tracer,
    shadow_tracer: &dyn Tracer,
    camera: &Camera,
    bounds: &Aabb,
    params: &ShadingParams,
    keep: KeptHits,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<StripRender, ShadeError> {
    let tracers = StripTracers { primary: tracer, shadow: shadow_tracer };
    render_strips(tracers, camera, bounds, params, keep, None, progress)
}

/// [`render_to_srgb8`] of the pixels `mask` marks only: each is the byte [`render_to_srgb8`]
/// gives it (its depth and normal too); the others are not drawn (what they hold is not
/// meant to be read), at almost no cost, so that an anti-aliasing pass samples again only
/// the pixels that need it. Fails as [`render_to_srgb8`] does, and when the mask is not of the
/// camera's image size.
pub fn render_marked_to_srgb8(
    tracers: StripTracers,
    camera: &Camera,
    bounds: &Aabb,
    params: &ShadingParams,
    keep: KeptHits,
    mask: &PixelMask,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<StripRender, ShadeError> {
    if !mask.fits(camera.width() as usize, camera.height() as usize) {
        return Err(ShadeError::Limits(format!(
            "a mask of {} x {} pixels for a picture of {} x {}",
            mask.width(),
            mask.height(),
            camera.width(),
            camera.height()
        )));
    }
    render_strips(tracers, camera, bounds, params, keep, Some(mask), progress)
}

/// The tracers of a strip render: the camera rays', and the shadow rays' (the same tracer, or
/// one that decides the sun's shadow rays faster).
#[derive(Clone, Copy)]
pub struct StripTracers<'a> {
    /// Traces the camera rays.
    pub primary: &'a dyn Tracer,
    /// Traces the shadow rays.
    pub shadow: &'a dyn Tracer,
}

/// [`render_to_srgb8`], of the pixels `mask` marks where there is one.
fn render_strips(
    tracers: StripTracers,
    camera: &Camera,
    bounds: &Aabb,
    params: &ShadingParams,
    keep: KeptHits,
    mask: Option<&PixelMask>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<StripRender, ShadeError> {
    let StripTracers { primary: tracer, shadow: shadow_tracer } = tracers;
    params.validate()?;
    let (width, height) = (camera.width() as usize, camera.height() as usize);
    // The strip G-buffer also refuses an empty image.
    GBuffer::new(width, TILE_SIZE.min(height))?;
    let n = width * height;
    let mut rgb = image_plane(n, [0u8; 3], "picture")?;
    let mut depth = keep.depth.then(|| image_plane(n, 0.0f32, "depth image")).transpose()?;
    let mut normals = keep.normals.then(|| image_plane(n, [0.0f32; 3], "normals")).transpose()?;
    let strip_len = TILE_SIZE * width;
    let mut depth_strips = depth.as_mut().map(|d| d.chunks_mut(strip_len));
    let mut normal_strips = normals.as_mut().map(|d| d.chunks_mut(strip_len));
    let strips: Vec<Strip> = rgb
        .chunks_mut(strip_len)
        .enumerate()
        .map(|(s, rgb)| Strip {
            top: s * TILE_SIZE,
            rgb,
            depth: depth_strips.as_mut().and_then(Iterator::next),
            normals: normal_strips.as_mut().and_then(Iterator::next),
        })
        .collect();
    let encoder = HitEncoder::for_shading(bounds, camera, &params.albedo);
    let kernel = ShadingKernel::new(camera, params);
    let started = Instant::now();
    let totals = strips
        .into_par_iter()
        .map_init(
            || GBuffer::new(width, TILE_SIZE.min(height)).ok(),
            |strip_gbuffer, strip| -> Result<StripTotals, ShadeError> {
                let strip_gbuffer = strip_gbuffer.as_mut().ok_or_else(|| {
                    ShadeError::Limits(format!(
                        "cannot allocate a G-buffer of {width} x {TILE_SIZE}"
                    ))
                })?;
                let (top, pixels) = (strip.top, strip.rgb.len());
                if mask.is_some_and(|m| !m.any_in_rows(top, pixels / width)) {
                    return Ok(StripTotals::default());
                }
                let traced = Instant::now();
                let mut rows = strip_gbuffer.rows_mut(pixels / width);
                let primary = trace_strip(tracer, &encoder, top, &mut rows, mask, progress);
                let shaded = Instant::now();
                let pass = ShadingPass::new(strip_gbuffer, top, shadow_tracer, camera, params)
                    .marked(mask);
                let shadow = pass.shade_strip_srgb8(top, strip.rgb, kernel.as_ref());
                if let Some(depth) = strip.depth {
                    depth.copy_from_slice(&strip_gbuffer.distance[..pixels]);
                }
                if let Some(normals) = strip.normals {
                    normals.copy_from_slice(&strip_gbuffer.normal[..pixels]);
                }
                let done = Instant::now();
                Ok(StripTotals {
                    primary,
                    shadow,
                    tracing: shaded - traced,
                    shading: done - shaded,
                })
            },
        )
        .try_reduce(StripTotals::default, |a, b| Ok(a.merge(b)))?;
    let wall_ms = started.elapsed().as_secs_f64() * 1e3;
    let busy = (totals.tracing + totals.shading).as_secs_f64();
    let trace_share = if busy > 0.0 { totals.tracing.as_secs_f64() / busy } else { 0.0 };
    let stats = StripRenderStats {
        primary: totals.primary,
        shadow: totals.shadow,
        trace_ms: wall_ms * trace_share,
        shade_ms: wall_ms * (1.0 - trace_share),
    };
    Ok(StripRender { rgb, depth, normals, stats })
}

/// One strip's share of the outputs.
struct Strip<'a> {
    /// The strip's first image row.
    top: usize,
    rgb: &'a mut [[u8; 3]],
    depth: Option<&'a mut [f32]>,
    normals: Option<&'a mut [[f32; 3]]>,
}

/// The counts and worker times of some strips.
#[derive(Default)]
struct StripTotals {
    primary: TraceStats,
    shadow: TraceStats,
    tracing: Duration,
    shading: Duration,
}

impl StripTotals {
    fn merge(self, other: StripTotals) -> StripTotals {
        StripTotals {
            primary: self.primary.merge(other.primary),
            shadow: self.shadow.merge(other.shadow),
            tracing: self.tracing + other.tracing,
            shading: self.shading + other.shading,
        }
    }
}
