//! `relief render STORE`: a tile store (made by `relief tile`) rendered in bounded memory, the
//! tiles chosen by the screen-space error and loaded for this one picture.

use super::render::{input_name, write_outputs};
use crate::args::{RenderArgs, SceneArgs, TextureFilterChoice, TileRenderArgs};
use crate::scene::height_field::shading;
use crate::{applies, memory, outputs, progress};
use anyhow::Result;
use relief_core::{Aabb, Camera, Surface};
use relief_shade::{
    render_gbuffer, shade_to_srgb8, Albedo, FilteredAlbedo, GBuffer, ShadingParams, TextureFilter,
    DEFAULT_MAX_ANISOTROPY,
};
use relief_tiles::{
    FrameRequest, TextureFrameStats, TextureStore, TextureStreamer, TileStore, TileStreamer,
    TiledTerrain,
};
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

/// A tile store opened for frames: its streamer (cache and loader), the surface drawn, the
/// box it fills, the shading, the frames' error bound and the store's photo, if any.
pub struct StoreScene {
    /// The store's frames.
    pub streamer: TileStreamer,
    /// The surface drawn (default: triangles).
    pub surface: Surface,
    /// The box the surface fills.
    pub bounds: Aabb,
    /// Lights and materials, fitted to the terrain.
    pub params: ShadingParams,
    /// The screen-space error bound asked for, pixels.
    pub max_error_px: f64,
    /// The store's photo with its own cache, and how it is filtered; `None` for a store
    /// without one, or when `--texture` drapes another picture.
    pub texture: Option<(TextureStreamer, TextureFilter)>,
}

impl StoreScene {
    /// Opens the store at `path` as `scene` and `tiles` say (its cache bound by
    /// `--cache-mb`), refusing the options that do nothing for a store.
    pub fn open(scene: &SceneArgs, tiles: &TileRenderArgs, path: &Path) -> Result<Self> {
        refuse_scene_options(scene, path)?;
        let store = TileStore::open(path)?;
        let texture = texture_of(&store, scene, tiles, path)?;
        let surface = scene.surface.unwrap_or(Surface::Triangles);
        let bounds = store.world_bounds(surface);
        let params = shading(scene, &store.world_bounds(Surface::Boxes))?;
        let cache_mb = tiles.cache_mb.unwrap_or(DEFAULT_CACHE_MB);
        let streamer = TileStreamer::new(store, surface, cache_mb << 20)?;
        let max_error_px = tiles.max_error_px.unwrap_or(DEFAULT_MAX_ERROR_PX);
        Ok(StoreScene { streamer, surface, bounds, params, max_error_px, texture })
    }

    /// The shading of the frame `camera` saw into `gbuffer` over `terrain`: the store's photo,
    /// when it has one, filtered over each pixel's footprint (its tiles loaded for the frame
    /// when it `wait`s, else coarser ones standing in), else the scene's own.
    pub fn frame_params(
        &self,
        gbuffer: &GBuffer,
        camera: &Camera,
        terrain: &Arc<TiledTerrain>,
        wait: bool,
    ) -> Result<(ShadingParams, Option<TextureFrameStats>)> {
        let Some((textures, filter)) = &self.texture else {
            return Ok((self.params.clone(), None));
        };
        let (frame, stats) = textures.frame(gbuffer, camera, terrain.clone(), *filter, wait)?;
        let params = ShadingParams {
            albedo: Albedo::Filtered(FilteredAlbedo(Arc::new(frame))),
            ..self.params.clone()
        };
        Ok((params, Some(stats)))
    }

    /// What a frame asks of the streamer: the error bound, culling only when no shadow rays
    /// are cast (they reach tiles outside the view), and whether to `wait` for the tiles.
    pub fn request(&self, wait: bool) -> FrameRequest {
        FrameRequest { max_error_px: self.max_error_px, cull: !self.params.shadows, wait }
    }
}

/// Renders the tile store at `path`.
pub fn run(args: &RenderArgs, path: &Path, started: Instant) -> Result<()> {
    if let Some(option) = args.hybrid.given() {
        let here = format!("a tile store ({})", path.display());
        return Err(applies::refuse(option, "--tracer hybrid", &here));
    }
    let scene = StoreScene::open(&args.scene, &args.tiles, path)?;
    let (surface, bounds) = (scene.surface, scene.bounds);
    let camera = crate::scene::camera(&args.scene, &bounds)?;
    let header = scene.streamer.store().header();
    let (width, height) = (header.width, header.height);
    let load_ms = outputs::ms_since(started);

    let build_started = Instant::now();
    let (terrain, frame) = scene.streamer.frame(&camera, scene.request(true))?;
    let terrain = Arc::new(terrain);
    let build_ms = outputs::ms_since(build_started);

    let pixels = camera.width() as u64 * camera.height() as u64;
    let bar = progress::bar(pixels, "tracing");
    let trace_started = Instant::now();
    let (gbuffer, primary) = render_gbuffer(&*terrain, &camera, &bounds, &|n| bar.inc(n))?;
    let trace_ms = outputs::ms_since(trace_started);
    bar.finish_and_clear();
    let texture_started = Instant::now();
    let (params, textured) = scene.frame_params(&gbuffer, &camera, &terrain, true)?;
    let texture_ms = outputs::ms_since(texture_started);
    let shade_started = Instant::now();
    let (rgb, shadow) = shade_to_srgb8(&gbuffer, &*terrain, &camera, &params)?;
    let shade_ms = outputs::ms_since(shade_started);
    let write_started = Instant::now();
    write_outputs(args, &camera, &gbuffer, rgb.as_flattened())?;
    let write_ms = outputs::ms_since(write_started);
    let (w, h) = (camera.width(), camera.height());
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

/// The photo of `store` (at `path`) with its cache and filter, unless `--texture` drapes
/// another picture; refuses the texture options for a store without one.
fn texture_of(
    store: &TileStore,
    scene: &SceneArgs,
    tiles: &TileRenderArgs,
    path: &Path,
) -> Result<Option<(TextureStreamer, TextureFilter)>> {
    let texture = match TextureStore::open(path, store.header())? {
        Some(texture) if scene.texture.is_none() => texture,
        _ => {
            let Some(option) = tiles.texture_given() else { return Ok(None) };
            let here = match scene.texture {
                Some(_) => "--texture, which drapes its own picture".to_string(),
                None => format!("a tile store without a texture ({})", path.display()),
            };
            let what = "textured tile stores (relief tile --texture)";
            return Err(applies::refuse(option, what, &here));
        }
    };
    let filter = match tiles.texture_filter.unwrap_or(TextureFilterChoice::Anisotropic) {
        TextureFilterChoice::Anisotropic => {
            TextureFilter::Anisotropic { max_anisotropy: DEFAULT_MAX_ANISOTROPY }
        }
        TextureFilterChoice::Bilinear => TextureFilter::Bilinear,
    };
    let mb = tiles.texture_cache_mb.unwrap_or(DEFAULT_TEXTURE_CACHE_MB);
    Ok(Some((TextureStreamer::new(texture, mb << 20)?, filter)))
}

/// Refuses the options of `scene` that do nothing for a tile store (at `path`).
fn refuse_scene_options(scene: &SceneArgs, path: &Path) -> Result<()> {
    let here = format!("a tile store ({})", path.display());
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
