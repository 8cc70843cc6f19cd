//! `relief.flight_plan`: the frames of a camera path as `relief flythrough` plays it, each
//! frame's time and camera made by the same code (relief_render's [`CameraPath`]), for
//! `relief.dask.flythrough` to render a frame a task.

use crate::errors::{argument, invalid};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyPermissionError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use relief_render::{CameraPath, RenderError};
use std::io::ErrorKind;
use std::path::PathBuf;

/// The most frames a fly-through renders, as ``relief flythrough --frames``.
const MAX_FRAMES: u32 = 100_000;

/// The frames of a ``frames``-frame fly-through of the camera path ``path`` (JSON, as
/// ``relief view`` records it; docs/camera-path.md), as ``relief flythrough`` plays it: a list
/// of dicts, one a frame, of its ``frame`` number, its ``time_s`` on the path and its
/// ``camera`` (``eye``, ``target``, ``up``, ``fov``), the camera dict ``Scene.render`` takes.
/// The times are spread evenly over the path's span, from its first key to its last, and each
/// camera is interpolated between the keys around it, an up vector parallel to the view
/// replaced by north.
///
/// Raises ``relief.ReliefError`` for ``frames`` outside 1 to 100000, a file that is not a
/// camera path, a path without keys, or a frame whose camera is unusable (naming it);
/// ``OSError`` when the file cannot be read.
#[pyfunction]
pub fn flight_plan(py: Python<'_>, path: PathBuf, frames: i64) -> PyResult<Bound<'_, PyList>> {
    let frames = u32::try_from(frames)
        .ok()
        .filter(|n| (1..=MAX_FRAMES).contains(n))
        .ok_or_else(|| invalid(format!("frames {frames} must be 1 to {MAX_FRAMES}")))?;
    let flight = CameraPath::read(&path).map_err(path_error)?;
    if flight.keys.is_empty() {
        return Err(invalid(format!("{}: the camera path has no keys", path.display())));
    }
    let list = PyList::empty(py);
    for (index, time_s) in flight.frame_times(frames).into_iter().enumerate() {
        let (key, _) = flight.frame_key(time_s).expect("a path with keys has a camera");
        key.camera(1, 1).map_err(|e| {
            invalid(format!(
                "{}: frame {index} (t = {time_s} s) interpolates an unusable camera: {e}",
                path.display()
            ))
        })?;
        let camera = PyDict::new(py);
        camera.set_item("eye", key.eye)?;
        camera.set_item("target", key.target)?;
        camera.set_item("up", key.up)?;
        camera.set_item("fov", key.fov_deg)?;
        let frame = PyDict::new(py);
        frame.set_item("frame", index)?;
        frame.set_item("time_s", time_s)?;
        frame.set_item("camera", camera)?;
        list.append(frame)?;
    }
    Ok(list)
}

/// A camera path that cannot be read as the `OSError` of its kind, one that is not a path as
/// a `ReliefError`.
fn path_error(error: RenderError) -> PyErr {
    let message = error.to_string();
    match error {
        RenderError::CameraPathFile { source, .. } => match source.kind() {
            ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
            ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
            _ => PyOSError::new_err(message),
        },
        other => argument(other),
    }
}
