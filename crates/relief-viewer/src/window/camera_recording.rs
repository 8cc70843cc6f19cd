//! A camera path being recorded (R): a key for every frame shown, timed by the clock or, in a
//! scripted run, by the script's frames.

use super::output_files::next_free;
use crate::script::SCRIPT_FRAME_S;
use crate::{CameraController, ViewerError};
use crate::{CameraKey, CameraPath};
use std::path::Path;
use std::time::Instant;

/// A camera path being recorded, and when (and at which script frame) it started.
pub(crate) struct CameraRecording {
    started: Instant,
    start_frame: usize,
    path: CameraPath,
}

impl CameraRecording {
    /// A recording starting now, at script frame `script_frame`.
    pub(crate) fn start(script_frame: usize) -> Self {
        CameraRecording {
            started: Instant::now(),
            start_frame: script_frame,
            path: CameraPath::default(),
        }
    }

    /// Adds the controller's camera, timed by the clock, or in a scripted run (at its frame
    /// `script_frame`) by the script's frames, so that its recordings are the same every run.
    pub(crate) fn push(&mut self, controller: &CameraController, script_frame: Option<usize>) {
        let time_s = match script_frame {
            Some(frame) => (frame - self.start_frame) as f64 * SCRIPT_FRAME_S,
            None => self.started.elapsed().as_secs_f64(),
        };
        self.path.push(CameraKey {
            time_s,
            eye: controller.eye().to_array(),
            target: controller.target().to_array(),
            up: controller.up().to_array(),
            fov_deg: controller.fov_deg(),
        });
    }

    /// Writes the path to the next free `relief-path-NNN.json` of `output_dir`.
    pub(crate) fn write(self, output_dir: &Path) -> Result<(), ViewerError> {
        let file = next_free(output_dir, "relief-path", "json");
        self.path.write(&file)?;
        eprintln!("saved {} ({} cameras)", file.display(), self.path.keys.len());
        Ok(())
    }
}
