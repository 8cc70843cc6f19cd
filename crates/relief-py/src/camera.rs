//! The camera of `render`: a dict of `eye`, `target`, `up` and `fov` as the command line's
//! `--eye`, `--target`, `--up` and `--fov`, or relief's automatic three-quarter framing.

use crate::errors::{argument, invalid};
use crate::options::{fov, readable, MAX_COORDINATE};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::{Aabb, Camera, DVec3};

/// The keys a camera dict may have.
const KEYS: [&str; 4] = ["eye", "target", "up", "fov"];

/// A camera as the caller described it, before the terrain is known.
pub struct CameraSpec {
    /// Eye and target, or `None` for the automatic framing.
    look: Option<(DVec3, DVec3)>,
    /// The up vector (default `0, 0, 1`).
    up: Option<DVec3>,
    /// Vertical field of view in degrees (default 45).
    fov: f64,
}

impl CameraSpec {
    /// Reads the camera dict `camera` (`None`: framed automatically with a 45 degree field of
    /// view), refusing unknown keys, an eye without a target and values out of range.
    pub fn from_dict(camera: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let Some(camera) = camera else {
            return Ok(CameraSpec { look: None, up: None, fov: 45.0 });
        };
        for key in camera.keys() {
            let key: String = key.extract().unwrap_or_else(|_| key.to_string());
            if !KEYS.contains(&key.as_str()) {
                return Err(invalid(format!(
                    "camera: unknown key '{key}' (expected eye, target, up, fov)"
                )));
            }
        }
        let vector = |key: &str| -> PyResult<Option<DVec3>> {
            match camera.get_item(key)? {
                None => Ok(None),
                Some(v) if v.is_none() => Ok(None),
                Some(v) => {
                    let [x, y, z]: [f64; 3] = v.extract().map_err(|_| {
                        invalid(format!("camera['{key}'] must be three numbers (x, y, z)"))
                    })?;
                    Ok(Some(DVec3::new(x, y, z)))
                }
            }
        };
        let (eye, target, up) = (vector("eye")?, vector("target")?, vector("up")?);
        for (key, point) in [("eye", eye), ("target", target)] {
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
        if let Some(u) = up {
            if u.length() == 0.0 || !u.length().is_finite() {
                return Err(invalid(format!(
                    "camera['up'] ({}, {}, {}) is not a direction (its length must be finite \
                     and not 0)",
                    u.x, u.y, u.z
                )));
            }
        }
        let look = match (eye, target) {
            (Some(eye), Some(target)) => Some((eye, target)),
            (None, None) if up.is_none() => None,
            (None, None) => return Err(invalid("camera: 'up' needs 'eye' and 'target'")),
            _ => return Err(invalid("camera: 'eye' and 'target' go together")),
        };
        let fov_deg = match camera.get_item("fov")? {
            Some(v) if !v.is_none() => fov(v
                .extract()
                .map_err(|_| invalid("camera['fov'] must be a number of degrees"))?)?,
            _ => 45.0,
        };
        Ok(CameraSpec { look, up, fov: fov_deg })
    }

    /// The camera for a `width x height` image: the given one, or the three-quarter view from
    /// the south-west at 30 degrees that frames `bounds`. An up parallel to the view is
    /// replaced by north with a `UserWarning` saying so, as the command line's note does.
    pub fn camera(
        &self,
        py: Python<'_>,
        bounds: &Aabb,
        width: u32,
        height: u32,
    ) -> PyResult<Camera> {
        let Some((eye, target)) = self.look else {
            return Camera::frame_from(bounds, 225.0, 30.0, self.fov, width, height)
                .map_err(argument);
        };
        let given = self.up.unwrap_or(DVec3::Z);
        let (up, replaced) = Camera::usable_up(eye, target, given);
        if replaced {
            let message = format!(
                "up {},{},{} is parallel to the view; using {},{},{} (north at the top of the \
                 image; set camera['up'] to choose another)",
                given.x, given.y, given.z, up.x, up.y, up.z
            );
            let category = py.get_type::<PyUserWarning>();
            PyErr::warn(py, category.as_any(), &std::ffi::CString::new(message)?, 1)?;
        }
        Camera::look_at(eye, target, up, self.fov, width, height).map_err(argument)
    }
}
