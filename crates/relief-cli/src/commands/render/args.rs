//! `relief render`: its outputs.

use crate::args::*;
use clap::Args;
use std::path::PathBuf;

/// `relief render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene, tracer, camera and light.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output picture: .png, or .jpg/.jpeg.
    #[arg(short, long, default_value = "relief.png")]
    pub output: PathBuf,
    /// Anti-aliasing: adaptive (one ray a pixel, then 4 in the pixels whose depth, normal or
    /// colour differs from a neighbour's: silhouettes, edges, shadow boundaries), N (N x N
    /// rays in every pixel, on a stratified grid; 1 to 8) or off. The depth and normals
    /// written are those of the pixels' centre rays [default: adaptive].
    #[arg(long, value_name = "MODE", default_value = "adaptive")]
    pub aa: relief_render::Antialiasing,
    /// Also write the distance to the first hit per pixel (.npy, f32, H x W, +inf on a miss).
    #[arg(long)]
    pub depth: Option<PathBuf>,
    /// Also write the unit world normal per pixel (.npy, f32, H x W x 3, zero on a miss).
    #[arg(long)]
    pub normals: Option<PathBuf>,
    /// Write the stage timings to this JSON file after the render: load_ms (reading the
    /// input, framing), build_ms (the tracer's structures), trace_ms, shade_ms, write_ms and
    /// total_ms, with the rays, hits, image size and tracer. A height field's ray casters
    /// trace and shade strip by strip: trace_ms and shade_ms split that pass's time in
    /// proportion to the workers' time in each. For an MLHM scene the renderer shades as it
    /// traces: trace_ms holds both, shade_ms the tone mapping.
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
    /// How hard a .png picture is compressed: none, fast (several times faster to write than
    /// balanced, a slightly larger file), balanced or high (the smallest file) [default: fast].
    #[arg(long, value_name = "LEVEL")]
    pub png_compression: Option<relief_io::PngCompression>,
    /// Legend, scale bar and north arrow.
    #[command(flatten)]
    pub furniture: FurnitureArgs,
    /// Options of the hybrid renderer.
    #[command(flatten)]
    pub hybrid: HybridArgs,
    /// Options of tile stores.
    #[command(flatten)]
    pub tiles: TileRenderArgs,
}
