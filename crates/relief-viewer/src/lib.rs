//! relief's interactive viewer: a window (winit, X11) with a CPU framebuffer (softbuffer) in
//! which the user flies over a terrain that a [`SceneRenderer`] draws. The viewer has no
//! rendering logic of its own: it moves the camera, decides what resolution to render next
//! ([`ProgressiveScheduler`]: reduced while moving, refined to full at rest), hands the frame
//! to a render thread so that the event loop never blocks, and shows the result with an
//! overlay of figures and keys. A scene with a simulation ([`SceneRenderer::simulate`]) is
//! run, paused and stepped the same way: the viewer keeps its controls
//! ([`SimulationControl`]) and the render thread asks the scene for the steps before a frame.
//!
//! [`live`] draws relief-render's scenes as [`SceneRenderer`]s ([`live::live_scene`]).
//! `relief view` (in relief-cli) is its front end; the same loop runs scripted for tests
//! ([`Script`], `--frames N --screenshot S.png`), in a window or, without a display,
//! headless ([`run_headless`]).
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod camera_controller;
mod frame;
mod headless;
mod hud;
mod input_map;
pub mod live;
mod overlay;
mod progressive;
mod script;
mod simulation;
mod summary;
mod view_settings;
mod window;
mod winit_keys;

pub use camera_controller::{CameraController, Motion, Navigation, DEFAULT_FOV_DEG};
pub use frame::{blit, Cancel, Frame, FrameStats, SceneRenderer};
pub use headless::run_headless;
pub use input_map::{action_for, motion_from, Action, Key, KEY_HELP};
pub use progressive::{FrameRequest, ProgressiveScheduler};
pub use relief_render::camera_path::{
    CameraKey, CameraPath, CAMERA_PATH_FORMAT, CAMERA_PATH_VERSION,
};
pub use script::{Script, ScriptFrame, SCRIPT_FRAME_S};
pub use simulation::{SimulationControl, SimulationReport, SimulationRequest};
pub use summary::{FrameRecord, ViewerSummary};
pub use view_settings::{SceneChoices, ViewSettings};
pub use window::{check_display, run, ViewerConfig};

use std::path::PathBuf;

/// What can go wrong in the viewer, by cause.
#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    /// No display to open a window on.
    #[error("no display: {0}")]
    NoDisplay(String),
    /// The window or its framebuffer could not be made or drawn.
    #[error("window: {0}")]
    Window(String),
    /// The scene renderer failed.
    #[error("render: {0}")]
    Render(String),
    /// A file could not be written or read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A camera-path file that is not one, or could not be written.
    #[error(transparent)]
    CameraPath(#[from] relief_render::RenderError),
    /// A screenshot could not be written.
    #[error("screenshot: {0}")]
    Screenshot(#[from] relief_io::IoError),
    /// A script that does not parse.
    #[error("script: {0}")]
    Script(String),
}
