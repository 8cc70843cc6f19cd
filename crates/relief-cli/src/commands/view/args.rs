//! `relief view`.

use crate::args::values::*;
use crate::args::*;
use clap::Args;
use std::path::PathBuf;

/// `relief view`. The viewer flies pinhole cameras: `--ortho` and `--ortho-height` are
/// hidden and refused.
#[derive(Debug, Args)]
#[command(mut_arg("ortho", |a| a.hide(true)), mut_arg("ortho_height", |a| a.hide(true)))]
pub struct ViewArgs {
    /// The scene, tracer, starting camera and light (--size is the window's size when it
    /// opens; the full frame then follows the window, except in a --frames run).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// How a tile store is drawn.
    #[command(flatten)]
    pub tiles: TileRenderArgs,
    /// Render this many frames through the viewer's loop (playing --script, if given), then
    /// wait for the view to be complete at full size, save it to --screenshot and close: for
    /// tests and scripts (1 to 100000).
    #[arg(long, value_name = "N", value_parser = frames, allow_hyphen_values = true)]
    pub frames: Option<u32>,
    /// With --frames: the PNG the last frame is saved to (without the overlay).
    #[arg(long, value_name = "PNG", requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// With --frames: keys held or pressed frame by frame, instead of the keyboard: steps
    /// COUNT:KEYS separated by commas, keys joined by +, !K pressed once, - nothing. E.g.
    /// "30:W+Left,1:!T,10:-" flies forward turning left for 30 frames, switches the tracer and
    /// rests. Each frame moves the camera by 1/30 s.
    #[arg(long, requires = "frames", allow_hyphen_values = true)]
    pub script: Option<String>,
    /// Write every frame shown (size, whether the camera moved, render_ms, rays) to this JSON
    /// file when the viewer closes.
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
    /// Folder for screenshots (P: relief-view-NNN.png) and camera paths (R:
    /// relief-path-NNN.json) [default: the current folder].
    #[arg(long, value_name = "DIR")]
    pub output_dir: Option<PathBuf>,
    /// Time a frame may take while the camera moves, in milliseconds: the viewer renders at
    /// the largest reduced size that fits (5 to 1000; 50 is 20 frames/s).
    #[arg(long, value_name = "MS", default_value = "50", value_parser = frame_budget, allow_hyphen_values = true)]
    pub frame_budget: u64,
}
