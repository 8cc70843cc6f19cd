//! The camera of `render` and `Scene.render`: a dict of `eye`, `target`, `up` and `fov` as the
//! command line's `--eye`, `--target`, `--up` and `--fov` (and, for a scene, `view`, `ortho`
//! and `ortho_height` as `--view`, `--ortho` and `--ortho-height`), or relief's automatic
//! three-quarter framing; placed by the scene layer as `relief render` places it.

use crate::errors::{argument, invalid};
use crate::options::{fov, readable, MAX_COORDINATE};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::{Aabb, Camera, DVec3};
use relief_render::{place_camera, CameraOptions, ViewAngles};

/// The keys the camera dict of `relief.render` may have.
pub const ARRAY_KEYS: &[&str] = &["eye", "target", "up", "fov"];

/// The keys the camera dict of `Scene.render` may have.
pub const SCENE_KEYS: &[&str] = &["eye", "target", "up", "fov", "view", "ortho", "ortho_height"];

/// A camera as the caller described it, before the terrain is known.
pub struct CameraSpec {
    /// The camera's position, with `target`.
    eye: Option<DVec3>,
    /// The point looked at (with `eye`, or with `view`).
    target: Option<DVec3>,
    /// The up vector (default `0, 0, 1`).
    up: Option<DVec3>,
    /// Vertical field of view in degrees (default 45).
    fov: Option<f64>,
    /// The framing's direction: azimuth, elevation and distance.
    view: Option<ViewAngles>,
    /// An orthographic camera.
    ortho: bool,
    /// The orthographic image's height, metres.
    ortho_height: Option<f64>,
}

impl CameraSpec {
    /// Reads the camera dict `camera` (`None`: framed automatically with a 45 degree field of
    /// view), refusing keys not in `keys`, an eye without a target and values out of range.
    pub fn from_dict(camera: Option<&Bound<'_, PyDict>>, keys: &[&str]) -> PyResult<Self> {
        let mut spec = CameraSpec {
            eye: None,
            target: None,
            up: None,
            fov: None,
            view: None,
            ortho: false,
            ortho_height: None,
        };
        let Some(camera) = camera else { return Ok(spec) };
        for key in camera.keys() {
            let key: String = key.extract().unwrap_or_else(|_| key.to_string());
            if !keys.contains(&key.as_str()) {
                return Err(invalid(format!(
                    "camera: unknown key '{key}' (expected {})",
                    keys.join(", ")
                )));
            }
        }
        let item = |key: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
            Ok(camera.get_item(key)?.filter(|v| !v.is_none()))
        };
        let vector = |key: &str| -> PyResult<Option<DVec3>> {
            let Some(v) = item(key)? else { return Ok(None) };
            let [x, y, z]: [f64; 3] = v
                .extract()
                .map_err(|_| invalid(format!("camera['{key}'] must be three numbers (x, y, z)")))?;
            Ok(Some(DVec3::new(x, y, z)))
        };
        (spec.eye, spec.target, spec.up) = (vector("eye")?, vector("target")?, vector("up")?);
        for (key, point) in [("eye", spec.eye), ("target", spec.target)] {
            if let Some(p) = point {
                if !p.is_finite() || p.abs().max_element() > MAX_COORDINATE {
                    return Err(invalid(format!(
                        "camera['{key}'] ({}, {}, {}) is farther than {} m from the origin on \
                         an axis",
                        p.x,
                        p.y,
                        p.z,
                        readable(MAX_COORDINATE)
                    )));
                }
            }
        }
        if let Some(u) = spec.up {
            if u.length() == 0.0 || !u.length().is_finite() {
                return Err(invalid(format!(
                    "camera['up'] ({}, {}, {}) is not a direction (its length must be finite \
                     and not 0)",
                    u.x, u.y, u.z
                )));
            }
        }
        if let Some(v) = item("view")? {
            let angles: Vec<f64> = v.extract().map_err(|_| {
                invalid(
                    "camera['view'] must be (azimuth, elevation) or (azimuth, elevation, distance)",
                )
            })?;
            spec.view = Some(view_angles(&angles)?);
        }
        if let Some(v) = item("ortho")? {
            spec.ortho =
                v.extract().map_err(|_| invalid("camera['ortho'] must be True or False"))?;
        }
        if let Some(v) = item("ortho_height")? {
            let h: f64 = v
                .extract()
                .map_err(|_| invalid("camera['ortho_height'] must be a number of metres"))?;
            if !(h > 0.0 && h <= 2.0 * MAX_COORDINATE) {
                return Err(invalid(format!(
                    "orthographic height {} must be more than 0 and at most {} m",
                    readable(h),
                    readable(2.0 * MAX_COORDINATE)
                )));
            }
            spec.ortho_height = Some(h);
        }
        match (spec.eye, spec.target) {
            (Some(_), Some(_)) => {}
            (None, None) if spec.up.is_some() => {
                return Err(invalid("camera: 'up' needs 'eye' and 'target'"))
            }
            (None, None) => {}
            (None, Some(_)) if spec.view.is_some() && spec.up.is_none() => {}
            _ => return Err(invalid("camera: 'eye' and 'target' go together")),
        }
        if let Some(v) = item("fov")? {
            let degrees =
                v.extract().map_err(|_| invalid("camera['fov'] must be a number of degrees"))?;
            spec.fov = Some(fov(degrees)?);
        }
        if spec.ortho && spec.fov.is_some() {
            return Err(invalid("camera['fov'] applies to perspective cameras, not to 'ortho'"));
        }
        if !spec.ortho && spec.ortho_height.is_some() {
            return Err(invalid("camera['ortho_height'] applies to 'ortho' cameras only"));
        }
        Ok(spec)
    }

    /// The scene layer's camera options for a `width x height` image.
    pub fn options(&self, width: u32, height: u32) -> CameraOptions {
        CameraOptions {
            size: (width, height),
            eye: self.eye,
            target: self.target,
            up: self.up,
            view: self.view,
            ortho: self.ortho,
            ortho_height: self.ortho_height,
            fov_deg: self.fov,
        }
    }

    /// The camera for a `width x height` image of a scene within `bounds`, placed as `relief
    /// render` places it: the given one, or the three-quarter view from the south-west at 30
    /// degrees. An up parallel to the view is replaced by north with a `UserWarning` saying
    /// so, as the command line's note does.
    pub fn camera(
        &self,
        py: Python<'_>,
        bounds: &Aabb,
        width: u32,
        height: u32,
    ) -> PyResult<Camera> {
        let placed = place_camera(&self.options(width, height), bounds).map_err(argument)?;
        warn_note(py, placed.note.as_deref())?;
        Ok(placed.camera)
    }
}

/// The scene layer's `note` on a camera (an up along the view replaced by north) as a
/// `UserWarning`, naming the dict's key where the command line's names its option.
pub fn warn_note(py: Python<'_>, note: Option<&str>) -> PyResult<()> {
    let Some(note) = note else { return Ok(()) };
    let message = note
        .trim_start_matches("note: ")
        .replace("set --up to choose another", "set camera['up'] to choose another");
    warn(py, &message)
}

/// A `UserWarning` with `message`.
pub fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    let category = py.get_type::<PyUserWarning>();
    PyErr::warn(py, category.as_any(), &std::ffi::CString::new(message)?, 1)
}

/// The view angles `(azimuth, elevation[, distance])`, held to the command line's `--view`
/// ranges, with its messages.
fn view_angles(angles: &[f64]) -> PyResult<ViewAngles> {
    let (azimuth_deg, elevation_deg, distance) = match *angles {
        [a, e] => (a, e, None),
        [a, e, d] => (a, e, Some(d)),
        _ => {
            return Err(invalid(
                "camera['view'] must be (azimuth, elevation) or (azimuth, elevation, distance)",
            ))
        }
    };
    if !(-360.0..=360.0).contains(&azimuth_deg) {
        return Err(invalid(format!(
            "view azimuth {} is outside -360..360 degrees",
            readable(azimuth_deg)
        )));
    }
    if !(elevation_deg > 0.0 && elevation_deg <= 90.0) {
        return Err(invalid(format!(
            "view elevation {} must be more than 0 and at most 90 degrees (90: straight down)",
            readable(elevation_deg)
        )));
    }
    if let Some(d) = distance {
        if !(d > 0.0 && d <= MAX_COORDINATE) {
            return Err(invalid(format!(
                "view distance {} must be more than 0 and at most {} m",
                readable(d),
                readable(MAX_COORDINATE)
            )));
        }
    }
    Ok(ViewAngles { azimuth_deg, elevation_deg, distance })
}
