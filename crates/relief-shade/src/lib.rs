//! relief-shade: turns a tracer's view of a terrain into an image.
//!
//! 1. [`render_gbuffer`] traces one ray per pixel into a [`GBuffer`] (distance, position,
//!    normal, material weights, texture coordinates, pixel footprint), tile by tile in parallel.
//! 2. [`shade`] lights the G-buffer in one deferred pass: a [`Sun`] with shadow rays, a
//!    Lambert + GGX BRDF ([`direct_lighting`]), ambient light and aerial perspective from the
//!    [`Sky`], albedo from a [`HypsometricRamp`], a [`ColourMap`] over heights, an
//!    [`RgbTexture`], or a [`FootprintAlbedo`] filtered over each pixel's [`GroundFootprint`]
//!    ([`filter_texture`]: bilinear or anisotropic, Dick et al. 2009).
//! 3. [`tonemap_to_srgb8`] maps the linear radiance to 8-bit sRGB.
//!
//! [`shade_map()`] makes the rasters GIS users overlay on their DEM: cast shadows, the sky-view
//! factor and the hillshade at every sample, aligned with the height field.
//!
//! [`depth_metrics()`] compares a depth image with a reference one as the hybrid-rendering paper
//! does (PSNR, wrong pixels, relative error).
//!
//! Every renderer has the one shape of [`Renderer`]: the ray caster ([`RayCaster`]), the
//! hybrid renderer ([`HybridRenderer`], per-cell machinery in [`hybrid`]), geometry clipmaps
//! ([`ClipmapRenderer`]), the stacks mesh ([`StacksRenderer`]) and multi-layered height maps
//! ([`mlhm::MlhmRenderer`]), whose deferred lighting ([`mlhm::shade_mlhm`]) is the reference
//! shading of Nilles & Müller (2025) with water, shadows and ambient occlusion, at four
//! quality presets.
//!
//! Every step gives the same result whatever the number of threads.
//!
//! ```
//! use std::sync::Arc;
//! use relief_core::{Camera, GridGeometry, HeightField, Surface};
//! use relief_trace::{build_tracer, TracerKind};
//! use relief_shade::{render_gbuffer, shade, tonemap_to_srgb8, ShadingParams};
//!
//! let samples = (0..64).map(|k| ((k % 8) as f32 * 0.7).sin() + (k / 8) as f32 * 0.2).collect();
//! let field = Arc::new(HeightField::new(8, 8, samples, GridGeometry::unit()).unwrap());
//! let bounds = field.world_bounds(Surface::Triangles);
//! let tracer = build_tracer(field, Surface::Triangles, TracerKind::Mipmap);
//! let camera = Camera::frame(&bounds, 64, 48).unwrap();
//! let (gbuffer, _primary) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
//! let params = ShadingParams::for_terrain(&bounds).unwrap();
//! let (radiance, _shadow) = shade(&gbuffer, &*tracer, &camera, &params).unwrap();
//! let rgb = tonemap_to_srgb8(&radiance, params.exposure).unwrap();
//! assert_eq!(rgb.len(), 64 * 48 * 3);
//! ```
#![deny(missing_docs)]
// Denied, not forbidden: the one exception is the call of the shading kernel compiled for the
// processor's SIMD extensions once they are detected (simd_shading/shading_kernel.rs).
#![deny(unsafe_code)]

mod albedo;
mod clipmap_renderer;
pub mod colour_maps;
mod colour_ramp;
mod deferred;
mod depth_metrics;
mod error;
mod footprint;
mod gbuffer;
pub mod horizon;
pub mod hybrid;
pub mod mlhm;
mod pixel_mask;
mod ray_batch;
mod render;
mod renderer;
#[cfg(target_arch = "x86_64")]
mod resolve_lanes;
mod resolve_shade;
pub mod shade_map;
mod shading;
mod shading_normals;
pub mod simd_shading;
mod sky;
pub mod solar;
mod srgb8_table;
mod stacks_renderer;
mod stats;
mod strip_render;
mod sun;
mod texture;
mod tonemap;
mod triangle_resolve;
pub mod viewshed;

pub use albedo::{Albedo, FilteredAlbedo};
pub use clipmap_renderer::{ClipmapRenderer, ClipmapStats};
pub use colour_maps::{ColourMap, HeightColourMap};
pub use colour_ramp::{hypsometric_colour, HypsometricRamp};
pub use deferred::{shade, shade_to_srgb8, ShadingParams};
pub use depth_metrics::{depth_errors, depth_metrics, DepthImage, DepthMetrics, DepthScale};
pub use error::ShadeError;
pub use gbuffer::{GBuffer, GBufferPixel};
pub use hybrid::{FarField, HybridParams, HybridRenderer, HybridStats, PixelSource};
pub use pixel_mask::PixelMask;
pub use ray_batch::RayBatch;
pub use relief_core::colour::{linear_to_srgb, srgb_to_linear};
pub use relief_core::texture::{
    filter_texture, ground_footprint, pixel_ground_footprint, slope_from_normal, FootprintAlbedo,
    FootprintAxes, GroundFootprint, MipTexture, PixelHits, TexelFootprint, TextureFilter,
    DEFAULT_MAX_ANISOTROPY,
};
pub use render::{render_gbuffer, render_gbuffer_into, Tile, TILE_SIZE};
pub use renderer::{RayCaster, Renderer, StageTimings};
pub use shade_map::{
    shade_map, shade_map_region, ShadeLayer, ShadeMap, ShadeMapParams, SunPosition,
};
pub use shading::{ambient_lighting, direct_lighting, GgxSpecular, DIELECTRIC_F0};
pub use shading_normals::{NormalStyle, ShadingNormals};
pub use simd_shading::{LaneWidth, ShadingKernel};
pub use sky::{aerial_perspective, fog_density_for_scene, Sky, FOG_AT_TWICE_DIAGONAL};
pub use stacks_renderer::{StacksFrameStats, StacksRenderer};
pub use stats::TraceStats;
pub use strip_render::{
    render_marked_to_srgb8, render_to_srgb8, KeptHits, StripRender, StripRenderStats, StripTracers,
};
pub use sun::{
    light_visibility, shadow_ray, shadow_ray_offset, sun_direction, sun_shadow_sweep, Sun,
    SHADOW_BIAS,
};
pub use texture::RgbTexture;
pub use tonemap::{aces_filmic, tonemap_reinhard_to_rgb8, tonemap_to_srgb8};
