//! `relief flythrough`.

use crate::args::values::*;
use crate::args::*;
use clap::Args;
use std::path::PathBuf;

/// `relief flythrough`. The camera options of `relief render` (`--eye`, `--target`, `--up`,
/// `--view`, `--fov`, `--ortho`, `--ortho-height`) are hidden and refused: the cameras come
/// from `--path`.
#[derive(Debug, Args)]
#[command(
    mut_arg("eye", |a| a.hide(true)),
    mut_arg("target", |a| a.hide(true)),
    mut_arg("up", |a| a.hide(true)),
    mut_arg("view", |a| a.hide(true)),
    mut_arg("fov", |a| a.hide(true)),
    mut_arg("ortho", |a| a.hide(true)),
    mut_arg("ortho_height", |a| a.hide(true))
)]
pub struct FlythroughArgs {
    /// The scene (INPUT: a tile store made by `relief tile`, a height file or an MLHM scene),
    /// tracer and light; --size is the frames' size.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The camera path: JSON as `relief view` records it (docs/camera-path.md).
    #[arg(long, value_name = "JSON")]
    pub path: PathBuf,
    /// Frames to render, spread evenly over the path's time span, from its first key to its
    /// last (1: the first key only; 1 to 100000).
    #[arg(long, value_name = "N", value_parser = frames, allow_hyphen_values = true)]
    pub frames: u32,
    /// The folder the frames are written to, as frame-00000.png, frame-00001.png, ...
    /// (created if missing; frames already there are overwritten).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Write every frame's figures (time_ms, tiles_drawn, tiles_standing_in, tiles_wanted,
    /// resident_bytes, rss_bytes, io_wait_ms, max_error_px, ...) and a summary (median_time_ms,
    /// ...) to this JSON file.
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
    /// Tile stores: every frame waits for the tiles it needs, as `relief render STORE` does
    /// (then each frame is that render of its camera, the same every run). Without it only the
    /// first frame waits; later ones draw the tiles in memory, coarser ones standing in for
    /// those still loading, so they depend on how fast the disk is.
    #[arg(long)]
    pub wait: bool,
    /// How hard the frames' PNGs are compressed: none, fast, balanced or high.
    #[arg(long, value_name = "LEVEL", default_value = "fast")]
    pub png_compression: relief_io::PngCompression,
    /// Options of tile stores.
    #[command(flatten)]
    pub tiles: TileRenderArgs,
}
