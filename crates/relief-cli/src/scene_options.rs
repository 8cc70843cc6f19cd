//! The scene layer's options (relief_render::SceneOptions, CameraOptions) as the command
//! line's scene, tile-store and hybrid arguments give them.

use crate::applies;
use crate::args::{HybridArgs, SafetyArgs, SceneArgs, TextureFilterChoice, TileRenderArgs};
use crate::input::terrain_settings;
use anyhow::Result;
use relief_render::options::{
    DEFAULT_CACHE_MB, DEFAULT_MAX_ERROR_PX, DEFAULT_NODE_BUDGET, DEFAULT_TEXTURE_CACHE_MB,
};
use relief_render::{
    CameraOptions, ColourSettings, HybridSettings, LightSettings, MeshSettings, MlhmSettings,
    SafetySettings, SceneOptions, StoreSettings,
};
use relief_shade::{TextureFilter, DEFAULT_MAX_ANISOTROPY};

/// The options `scene` gives, with a tile store's from `tiles` and the hybrid renderer's from
/// `hybrid` where the command takes them.
pub fn scene_options(
    scene: &SceneArgs,
    tiles: Option<&TileRenderArgs>,
    hybrid: Option<&HybridArgs>,
) -> SceneOptions {
    SceneOptions {
        terrain: terrain_settings(&scene.input),
        surface: scene.surface,
        tracer: scene.tracer.clone(),
        safety: safety_settings(&scene.safety),
        mode: scene.mode,
        sigma: scene.sigma,
        mlhm: MlhmSettings {
            preset: scene.preset,
            hierarchy_bounds: scene.hierarchy_bounds,
            backtrack: scene.backtrack,
            no_ao: scene.no_ao,
        },
        mesh: MeshSettings {
            tau_px: scene.tau,
            voxel_height: scene.voxel_height,
            node_budget: scene.node_budget.map_or(Some(DEFAULT_NODE_BUDGET), |b| b.0),
        },
        store: tiles.map(store_settings).unwrap_or_default(),
        hybrid: hybrid.map(hybrid_settings).unwrap_or_default(),
        light: LightSettings {
            sun: scene.sun,
            no_shadows: scene.no_shadows,
            exposure: scene.exposure,
            texture: scene.texture.clone(),
            colours: ColourSettings {
                map: scene.colormap,
                height_range: scene.height_range,
                sea_level: scene.sea_level,
            },
            shading_normals: scene.shading_normals,
        },
    }
}

/// The safety tracer's settings `args` give.
pub fn safety_settings(args: &SafetyArgs) -> SafetySettings {
    SafetySettings {
        variant: args.safety,
        phi_max: args.phi_max,
        isotropic: args.isotropic,
        positive: args.positive,
        linear_surface: args.linear_surface,
        reach: args.safety_reach,
        cache_dir: args.cache_dir.clone(),
        no_cache: args.no_cache,
    }
}

/// A tile store's settings `args` give (the defaults where they give none).
fn store_settings(args: &TileRenderArgs) -> StoreSettings {
    let texture_filter = match args.texture_filter.unwrap_or(TextureFilterChoice::Anisotropic) {
        TextureFilterChoice::Anisotropic => {
            TextureFilter::Anisotropic { max_anisotropy: DEFAULT_MAX_ANISOTROPY }
        }
        TextureFilterChoice::Bilinear => TextureFilter::Bilinear,
    };
    StoreSettings {
        max_error_px: args.max_error_px.unwrap_or(DEFAULT_MAX_ERROR_PX),
        cache_bytes: args.cache_mb.unwrap_or(DEFAULT_CACHE_MB) << 20,
        texture_filter,
        texture_cache_bytes: args.texture_cache_mb.unwrap_or(DEFAULT_TEXTURE_CACHE_MB) << 20,
    }
}

/// The hybrid renderer's settings `args` give.
fn hybrid_settings(args: &HybridArgs) -> HybridSettings {
    HybridSettings { params: args.params(), far: args.far, show_lop: args.show_lop }
}

/// The camera `args` give: `--eye` and `--target`, or the framing from `--view`, pinhole or
/// (`--ortho`) orthographic. `--fov` with `--ortho`, and `--ortho-height` without it, are
/// refused: they would do nothing.
pub fn camera_options(args: &SceneArgs) -> Result<CameraOptions> {
    if args.ortho && args.fov.is_some() {
        return Err(applies::refuse("--fov", "perspective cameras", "--ortho"));
    }
    if !args.ortho && args.ortho_height.is_some() {
        return Err(applies::refuse("--ortho-height", "--ortho", "a perspective camera"));
    }
    Ok(CameraOptions {
        size: args.size,
        eye: args.eye,
        target: args.target,
        up: args.up,
        view: args.view,
        ortho: args.ortho,
        ortho_height: args.ortho_height,
        fov_deg: args.fov,
    })
}
