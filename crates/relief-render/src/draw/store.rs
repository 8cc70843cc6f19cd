//! A tile store drawn in bounded memory: the tiles chosen by the screen-space error and
//! loaded for the picture, traced into a G-buffer and shaded (the store's photo filtered
//! over each pixel's footprint, where it has one).

use super::picture::{kept_arrays, ms_since, object, Picture};
use crate::error::RenderError;
use crate::memory;
use crate::progress::Progress;
use crate::scenes::store::StoreScene;
use relief_core::Camera;
use relief_shade::{render_gbuffer, shade_to_srgb8, KeptHits, TextureFilter};
use relief_tiles::FrameStats;
use serde_json::json;
use std::sync::Arc;
use std::time::Instant;

/// A frame of a tile store: its pixels, what the streamer did and the shadow rays traced.
pub struct StoreFrame {
    /// sRGB pixels, rows from the top.
    pub rgb: Vec<[u8; 3]>,
    /// The tiles the frame asked for, drew and stood in.
    pub tiles: FrameStats,
    /// Rays traced: primary and shadow.
    pub rays: u64,
    /// Mean steps of a primary ray.
    pub mean_steps: f64,
}

/// Draws `camera`'s frame of `scene` with the shading `params` (the scene's, or the viewer's
/// sun, shadows and exposure), waiting for its tiles where `wait` says (else coarser ones in
/// memory stand in).
pub fn frame(
    scene: &StoreScene,
    camera: &Camera,
    params: &relief_shade::ShadingParams,
    wait: bool,
) -> Result<StoreFrame, RenderError> {
    let request = relief_tiles::FrameRequest {
        max_error_px: scene.max_error_px,
        cull: !params.shadows,
        wait,
    };
    let (terrain, tiles) = scene.streamer.frame(camera, request)?;
    let terrain = Arc::new(terrain);
    let (gbuffer, primary) = render_gbuffer(&*terrain, camera, &scene.bounds, &|_| {})?;
    let (textured, _) = scene.frame_params(&gbuffer, camera, &terrain, wait)?;
    let params = relief_shade::ShadingParams {
        albedo: textured.albedo,
        normals: textured.normals,
        ..params.clone()
    };
    let (rgb, shadow) = shade_to_srgb8(&gbuffer, &*terrain, camera, &params)?;
    let pixels = u64::from(camera.width()) * u64::from(camera.height());
    Ok(StoreFrame { rgb, tiles, rays: pixels + shadow.rays, mean_steps: primary.mean_steps() })
}

/// Draws `scene` from `camera`, its tiles loaded for this one picture, keeping the depth and
/// normals `keep` asks for.
pub fn draw(
    scene: &StoreScene,
    camera: &Camera,
    keep: KeptHits,
    progress: &dyn Progress,
) -> Result<Picture, RenderError> {
    let (surface, bounds) = (scene.surface, scene.bounds);
    let header = scene.streamer.store().header();
    let (width, height) = (header.width, header.height);
    let build_started = Instant::now();
    let (terrain, frame) = scene.streamer.frame(camera, scene.request(true))?;
    let terrain = Arc::new(terrain);
    let build_ms = ms_since(build_started);

    let pixels = camera.width() as u64 * camera.height() as u64;
    progress.begin("tracing", Some(pixels));
    let trace_started = Instant::now();
    let traced = render_gbuffer(&*terrain, camera, &bounds, &|n| progress.advance(n));
    let trace_ms = ms_since(trace_started);
    progress.end();
    let (mut gbuffer, primary) = traced?;
    let texture_started = Instant::now();
    let (params, textured) = scene.frame_params(&gbuffer, camera, &terrain, true)?;
    let texture_ms = ms_since(texture_started);
    let shade_started = Instant::now();
    let (rgb, shadow) = shade_to_srgb8(&gbuffer, &*terrain, camera, &params)?;
    let shade_ms = ms_since(shade_started);
    let texture_note = match (&textured, &scene.texture) {
        (Some(t), Some((_, filter))) => {
            let filter = match filter {
                TextureFilter::Anisotropic { .. } => "anisotropic",
                TextureFilter::Bilinear => "bilinear",
            };
            let level = match t.min_level {
                0 => String::new(),
                l => format!(" from level {l} (finer ones exceed --texture-cache-mb)"),
            };
            format!(", {} texture tiles filtered {filter}{level}", t.tiles)
        }
        _ => String::new(),
    };
    let summary = format!(
        "{surface} tile store, {} tiles at <= {:.3} px error{texture_note}",
        frame.tiles_drawn, frame.max_error_px
    );
    let hits = gbuffer.distance.iter().filter(|d| d.is_finite()).count();
    let stats = object(json!({
        "kind": "tile store",
        "terrain": [width, height],
        "surface": surface.to_string(),
        "tracer": "tiles",
        "width": camera.width(),
        "height": camera.height(),
        "threads": rayon::current_num_threads(),
        "rays": pixels,
        "hits": hits,
        "shadow_rays": shadow.rays,
        "mean_steps": primary.mean_steps(),
        "max_error_px": frame.max_error_px,
        "tiles_wanted": frame.tiles_wanted,
        "tiles_drawn": frame.tiles_drawn,
        "io_wait_ms": frame.io_wait_ms,
        "resident_tile_bytes": frame.resident_bytes,
        "peak_rss_bytes": memory::peak_resident_bytes(),
        "build_ms": build_ms,
        "trace_ms": trace_ms,
        "texture_ms": texture_ms,
        "texture_tiles": textured.map(|t| t.tiles),
        "texture_tiles_loaded": textured.map(|t| t.tiles_loaded),
        "texture_min_level": textured.map(|t| t.min_level),
        "resident_texture_bytes": textured.map(|t| t.resident_bytes),
        "shade_ms": shade_ms,
    }));
    let (depth, normals) = kept_arrays(&mut gbuffer, keep);
    let (w, h) = (camera.width(), camera.height());
    Ok(Picture { width: w, height: h, rgb, depth, normals, summary, notes: vec![], stats })
}
