//! A `--frames` run without a window or a display: the scripted run's loop of the window
//! ([`App`]), driven by the render thread's frames as they come instead of by the window's
//! event loop, so that it draws the same frames, screenshot and stats.

use crate::frame::SceneRenderer;
use crate::summary::ViewerSummary;
use crate::window::{spawn_render_thread, App, LoopControl, Rendered};
use crate::{ViewerConfig, ViewerError};
use std::sync::{mpsc, Arc};

/// Draws the frames of a `--frames` run (`config.frames` must be set) without a window or a
/// display: the scripted run's loop, the same frames, the same screenshot and stats, with the
/// render thread's frames taken as they come instead of through the window's event loop.
pub fn run_headless(
    renderer: Arc<dyn SceneRenderer>,
    config: ViewerConfig,
) -> Result<ViewerSummary, ViewerError> {
    if config.frames.is_none() {
        return Err(ViewerError::NoDisplay(
            "a viewer without a window draws a --frames run only".into(),
        ));
    }
    let (send, receive) = mpsc::channel::<Rendered>();
    let (jobs, worker) =
        spawn_render_thread(renderer.clone(), move |rendered| send.send(rendered).is_ok());
    let mut app = App::new(renderer, config, jobs);
    let control = Headless::default();
    app.play_script_frame(&control, 0);
    app.drive_script(&control);
    while !control.exiting() && app.busy {
        match receive.recv() {
            Ok(rendered) => app.on_rendered(&control, rendered),
            Err(_) => break,
        }
    }
    drop(app.jobs.take());
    let _ = worker.join();
    app.finish()
}

/// The loop of a run without a window: it stops when asked.
#[derive(Default)]
struct Headless(std::cell::Cell<bool>);

impl LoopControl for Headless {
    fn exit(&self) {
        self.0.set(true);
    }

    fn exiting(&self) -> bool {
        self.0.get()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Cancel, Frame, FrameStats, SceneChoices, Script, ViewSettings};
    use relief_core::{Camera, DVec3, Projection};
    use std::path::PathBuf;
    use std::time::Duration;

    /// A scene of one colour.
    struct Flat;

    impl SceneRenderer for Flat {
        fn describe(&self) -> String {
            "flat scene".into()
        }

        fn scene_size(&self) -> f64 {
            10.0
        }

        fn render(&self, camera: &Camera, _: &ViewSettings, _: &Cancel) -> Result<Frame, String> {
            let (width, height) = (camera.width(), camera.height());
            let rgb = vec![[10, 20, 30]; (width * height) as usize];
            Ok(Frame { width, height, rgb, stats: FrameStats::default(), note: None })
        }
    }

    fn config(frames: Option<u32>, screenshot: Option<PathBuf>) -> ViewerConfig {
        let projection = Projection::Perspective { fov_deg: 45.0 };
        let camera =
            Camera::new(DVec3::new(0.0, -10.0, 5.0), DVec3::ZERO, DVec3::Z, projection, 24, 16)
                .unwrap();
        let settings = ViewSettings::new(SceneChoices::default(), (0.0, 30.0), 1.0, true);
        ViewerConfig {
            size: (24, 16),
            camera,
            settings,
            frames,
            script: Script::parse("3:W").unwrap(),
            screenshot,
            output_dir: std::env::temp_dir(),
            stats: None,
            frame_budget: Duration::from_millis(50),
        }
    }

    #[test]
    fn a_headless_run_draws_its_frames_and_saves_the_last_at_full_size() {
        let shot = std::env::temp_dir().join(format!("relief-headless-{}.png", std::process::id()));
        let summary = run_headless(Arc::new(Flat), config(Some(4), Some(shot.clone()))).unwrap();
        assert!(summary.frames.len() >= 4, "{:?}", summary.frames);
        let last = summary.frames.last().unwrap();
        assert_eq!((last.width, last.height, last.moving), (24, 16, false));
        assert_eq!(summary.screenshot.as_deref(), Some(shot.as_path()));
        assert!(shot.is_file());
        std::fs::remove_file(shot).unwrap();
    }

    #[test]
    fn a_headless_run_needs_frames() {
        assert!(run_headless(Arc::new(Flat), config(None, None)).is_err());
    }
}
