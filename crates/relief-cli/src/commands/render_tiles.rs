//! `relief render STORE`: a tile store (made by `relief tile`) rendered in bounded memory, the
//! tiles chosen by the screen-space error and loaded for this one picture.

use super::render::{input_name, write_outputs};
use crate::args::{RenderArgs, TextureFilterChoice};
use crate::scene::height_field::shading;
use crate::{applies, memory, outputs, progress};
use anyhow::Result;
use relief_core::Surface;
use relief_shade::{
    render_gbuffer, shade_to_srgb8, Albedo, FilteredAlbedo, TextureFilter, DEFAULT_MAX_ANISOTROPY,
};
use relief_tiles::{FrameRequest, TextureStore, TextureStreamer, TileStore, TileStreamer};
use serde_json::json;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// Tile stores: the screen-space error where `--max-error-px` gives none (Dick et al. 2009).
pub const DEFAULT_MAX_ERROR_PX: f64 = 2.0 / 3.0;
/// Tile stores: megabytes of tiles in memory where `--cache-mb` gives none.
pub const DEFAULT_CACHE_MB: u64 = 512;
/// Textured tile stores: megabytes of texture tiles in memory where `--texture-cache-mb`
/// gives none.
pub const DEFAULT_TEXTURE_CACHE_MB: u64 = 256;

/// Renders the tile store at `path`.
pub fn run(args: &RenderArgs, path: &Path, started: Instant) -> Result<()> {
    refuse_options(args, path)?;
    let scene = &args.scene;
    let store = TileStore::open(path)?;
    // The store's photo colours the terrain unless --texture drapes another picture.
    let texture = match TextureStore::open(path, store.header())? {
        Some(texture) if scene.texture.is_none() => Some(texture),
        _ => None,
    };
    if let (None, Some(option)) = (&texture, args.tiles.texture_given()) {
        let here = match scene.texture {
            Some(_) => "--texture, which drapes its own picture".to_string(),
            None => format!("a tile store without a texture ({})", path.display()),
        };
        return Err(applies::refuse(option, "textured tile stores (relief tile --texture)", &here));
    }
    let surface = scene.surface.unwrap_or(Surface::Triangles);
    let bounds = store.world_bounds(surface);
    let camera = crate::scene::camera(scene, &bounds)?;
    let params = shading(scene, &store.world_bounds(Surface::Boxes))?;
    let (width, height) = (store.header().width, store.header().height);
    let cache_mb = args.tiles.cache_mb.unwrap_or(DEFAULT_CACHE_MB);
    let streamer = TileStreamer::new(store, surface, cache_mb << 20)?;
    let load_ms = outputs::ms_since(started);

    let build_started = Instant::now();
    let request = FrameRequest {
        max_error_px: args.tiles.max_error_px.unwrap_or(DEFAULT_MAX_ERROR_PX),
        // Shadow rays reach tiles outside the view.
        cull: !params.shadows,
        wait: true,
    };
    let (terrain, frame) = streamer.frame(&camera, request)?;
    let terrain = Arc::new(terrain);
    let build_ms = outputs::ms_since(build_started);

    let pixels = camera.width() as u64 * camera.height() as u64;
    let bar = progress::bar(pixels, "tracing");
    let trace_started = Instant::now();
    let (gbuffer, primary) = render_gbuffer(&*terrain, &camera, &bounds, &|n| bar.inc(n))?;
    let trace_ms = outputs::ms_since(trace_started);
    bar.finish_and_clear();
    let texture_started = Instant::now();
    let mut params = params;
    let filter_choice = args.tiles.texture_filter.unwrap_or(TextureFilterChoice::Anisotropic);
    let textured = match texture {
        Some(texture) => {
            let mb = args.tiles.texture_cache_mb.unwrap_or(DEFAULT_TEXTURE_CACHE_MB);
            let textures = TextureStreamer::new(texture, mb << 20)?;
            let filter = match filter_choice {
                TextureFilterChoice::Anisotropic => {
                    TextureFilter::Anisotropic { max_anisotropy: DEFAULT_MAX_ANISOTROPY }
                }
                TextureFilterChoice::Bilinear => TextureFilter::Bilinear,
            };
            let (frame, stats) = textures.frame(&gbuffer, &camera, terrain.clone(), filter)?;
            params.albedo = Albedo::Filtered(FilteredAlbedo(Arc::new(frame)));
            Some(stats)
        }
        None => None,
    };
    let texture_ms = outputs::ms_since(texture_started);
    let shade_started = Instant::now();
    let (rgb, shadow) = shade_to_srgb8(&gbuffer, &*terrain, &camera, &params)?;
    let shade_ms = outputs::ms_since(shade_started);
    let write_started = Instant::now();
    write_outputs(args, &camera, &gbuffer, rgb.as_flattened())?;
    let write_ms = outputs::ms_since(write_started);
    let (w, h) = (camera.width(), camera.height());
    let texture_note = match &textured {
        Some(t) => {
            let filter = match filter_choice {
                TextureFilterChoice::Anisotropic => "anisotropic",
                TextureFilterChoice::Bilinear => "bilinear",
            };
            let level = match t.min_level {
                0 => String::new(),
                l => format!(" from level {l} (finer ones exceed --texture-cache-mb)"),
            };
            format!(", {} texture tiles filtered {filter}{level}", t.tiles)
        }
        None => String::new(),
    };
    eprintln!(
        "wrote {} ({w}x{h}, {surface} tile store, {} tiles at <= {:.3} px error{texture_note})",
        args.output.display(),
        frame.tiles_drawn,
        frame.max_error_px
    );
    let Some(stats_path) = &args.stats else { return Ok(()) };
    let hits = gbuffer.distance.iter().filter(|d| d.is_finite()).count();
    let stats = json!({
        "input": input_name(args),
        "kind": "tile store",
        "terrain": [width, height],
        "surface": surface.to_string(),
        "tracer": "tiles",
        "width": w,
        "height": h,
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
        "load_ms": load_ms,
        "build_ms": build_ms,
        "trace_ms": trace_ms,
        "texture_ms": texture_ms,
        "texture_tiles": textured.map(|t| t.tiles),
        "texture_tiles_loaded": textured.map(|t| t.tiles_loaded),
        "texture_min_level": textured.map(|t| t.min_level),
        "resident_texture_bytes": textured.map(|t| t.resident_bytes),
        "shade_ms": shade_ms,
        "write_ms": write_ms,
        "total_ms": outputs::ms_since(started),
    });
    outputs::write_stats(stats_path, &stats)
}

/// Refuses the options that do nothing for a tile store.
fn refuse_options(args: &RenderArgs, path: &Path) -> Result<()> {
    let here = format!("a tile store ({})", path.display());
    if let Some(option) = args.hybrid.given() {
        return Err(applies::refuse(option, "--tracer hybrid", &here));
    }
    let scene = &args.scene;
    let input = &scene.input;
    let given = [
        (scene.tracer.is_some(), "--tracer"),
        (scene.mode.is_some(), "--mode"),
        (scene.preset.is_some(), "--preset"),
        (input.read.voids.is_some(), "--voids"),
        (input.spacing.is_some(), "--spacing"),
        (input.north_up, "--north-up"),
    ];
    match given.into_iter().find_map(|(given, name)| given.then_some(name)) {
        Some(option) => Err(applies::refuse(option, "height files", &here)),
        None => Ok(()),
    }
}
