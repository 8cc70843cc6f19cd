//! What the viewer opens with: size, camera, settings, and what a scripted run does.

use crate::script::Script;
use crate::ViewSettings;
use relief_core::Camera;
use std::path::PathBuf;
use std::time::Duration;

/// What the viewer opens with.
#[derive(Debug, Clone)]
pub struct ViewerConfig {
    /// The full image size (and the window's first inner size), pixels.
    pub size: (u32, u32),
    /// The starting camera.
    pub camera: Camera,
    /// The starting settings.
    pub settings: ViewSettings,
    /// Stop after this many frames shown (and once the view is at full resolution), saving
    /// the last one to `screenshot`.
    pub frames: Option<u32>,
    /// Input played frame by frame instead of the keyboard (with `frames`).
    pub script: Script,
    /// Where the last frame goes when `frames` ends the run.
    pub screenshot: Option<PathBuf>,
    /// Where screenshots (P) and camera paths (R) are written.
    pub output_dir: PathBuf,
    /// Where to write every frame's timing as JSON when the viewer closes.
    pub stats: Option<PathBuf>,
    /// The time a frame may take while the camera moves.
    pub frame_budget: Duration,
}
