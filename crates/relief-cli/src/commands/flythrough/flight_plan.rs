//! The plan of a fly-through: the camera path read, and every frame's time and camera on it.

use super::args::FlythroughArgs;
use anyhow::{bail, Context, Result};
use relief_core::Camera;
use relief_render::CameraPath;
use std::path::PathBuf;

/// The cameras of the flight, one a frame, at the frames' times on the path.
pub(super) struct FlightPlan {
    /// The path's file.
    pub path: PathBuf,
    /// The path's first and last key times, seconds.
    pub span: (f64, f64),
    /// Each frame's time on the path, seconds.
    pub times: Vec<f64>,
    /// Each frame's camera.
    pub cameras: Vec<Camera>,
}

/// Reads the camera path and makes every frame's camera: `--frames` times spread evenly
/// over its span, each camera interpolated between the keys around it (see
/// [`CameraPath::frame_key`], which Python's `relief.flight_plan` calls too). Refuses a path without keys, and names the frame whose
/// interpolated camera is unusable (its eye on its target, or no up vector).
pub(super) fn plan(args: &FlythroughArgs) -> Result<FlightPlan> {
    let path = CameraPath::read(&args.path).context("--path")?;
    let Some(span) = path.time_span() else {
        bail!("--path {}: the camera path has no keys", args.path.display());
    };
    let (w, h) = args.scene.size;
    let times = path.frame_times(args.frames);
    let mut replaced_up = 0;
    let mut cameras = Vec::with_capacity(times.len());
    for (index, &time_s) in times.iter().enumerate() {
        let (key, replaced) =
            path.frame_key(time_s).context("a path with keys has a camera at every time")?;
        replaced_up += usize::from(replaced);
        let camera = key.camera(w, h).with_context(|| {
            format!(
                "--path {}: frame {index} (t = {time_s} s) interpolates an unusable camera",
                args.path.display()
            )
        })?;
        cameras.push(camera);
    }
    if replaced_up > 0 {
        eprintln!(
            "note: the interpolated up vector of {replaced_up} frame(s) is parallel to the \
             view; north is at the top of those"
        );
    }
    Ok(FlightPlan { path: args.path.clone(), span, times, cameras })
}
