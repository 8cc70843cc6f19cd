//! Camera paths: the viewer records them (R) as JSON, in the format docs/camera-path.md
//! describes, for a fly-through (`relief flythrough`, Python's `relief.dask.flythrough`) to
//! replay, each frame's camera made here.

use crate::RenderError;
use relief_core::{Camera, DVec3};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The `format` value every camera-path file carries.
pub const CAMERA_PATH_FORMAT: &str = "relief-camera-path";
/// The version of the format written.
pub const CAMERA_PATH_VERSION: u32 = 1;

/// One recorded camera: when, where from, where to, which way is up, how wide.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CameraKey {
    /// Seconds since the recording started.
    pub time_s: f64,
    /// The eye, world coordinates in metres.
    pub eye: [f64; 3],
    /// The point looked at.
    pub target: [f64; 3],
    /// The up vector.
    pub up: [f64; 3],
    /// Vertical field of view, degrees.
    pub fov_deg: f64,
}

impl CameraKey {
    /// The `width x height` pinhole camera of this key; an error for a camera that cannot be
    /// (its eye on its target, its up vector along the view).
    pub fn camera(&self, width: u32, height: u32) -> Result<Camera, relief_core::CoreError> {
        let (eye, target, up) =
            (DVec3::from(self.eye), DVec3::from(self.target), DVec3::from(self.up));
        Camera::look_at(eye, target, up, self.fov_deg, width, height)
    }
}

/// A recorded flight: keys in time order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CameraPath {
    /// Always [`CAMERA_PATH_FORMAT`].
    pub format: String,
    /// [`CAMERA_PATH_VERSION`].
    pub version: u32,
    /// The keys, at strictly increasing times.
    pub keys: Vec<CameraKey>,
}

impl Default for CameraPath {
    fn default() -> Self {
        CameraPath { format: CAMERA_PATH_FORMAT.into(), version: CAMERA_PATH_VERSION, keys: vec![] }
    }
}

impl CameraPath {
    /// Appends `key` unless it repeats the last camera or goes back in time.
    pub fn push(&mut self, key: CameraKey) {
        if let Some(last) = self.keys.last() {
            let same = last.eye == key.eye && last.target == key.target && last.up == key.up;
            if same || key.time_s <= last.time_s {
                return;
            }
        }
        self.keys.push(key);
    }

    /// Writes the path as JSON to `path` (through a temporary file, renamed into place).
    pub fn write(&self, path: &Path) -> Result<(), RenderError> {
        let text = serde_json::to_string_pretty(self).expect("a camera path serialises");
        let temp = path.with_extension("json.partial");
        let io = |source| RenderError::CameraPathFile { path: path.to_path_buf(), source };
        std::fs::write(&temp, text + "\n").map_err(io)?;
        std::fs::rename(&temp, path).map_err(io)
    }

    /// Reads and checks a path written by [`CameraPath::write`] (or by hand).
    pub fn read(path: &Path) -> Result<CameraPath, RenderError> {
        let bad = |reason: String| RenderError::CameraPath { path: path.to_path_buf(), reason };
        let text = std::fs::read_to_string(path)
            .map_err(|source| RenderError::CameraPathFile { path: path.to_path_buf(), source })?;
        let parsed: CameraPath = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
        if parsed.format != CAMERA_PATH_FORMAT || parsed.version != CAMERA_PATH_VERSION {
            return Err(bad(format!(
                "not a {CAMERA_PATH_FORMAT} version {CAMERA_PATH_VERSION} file (format '{}', \
                 version {})",
                parsed.format, parsed.version
            )));
        }
        for (k, key) in parsed.keys.iter().enumerate() {
            let finite = key.eye.iter().chain(&key.target).chain(&key.up).all(|v| v.is_finite());
            if !(finite && key.fov_deg > 0.0 && key.fov_deg < 180.0 && key.time_s.is_finite()) {
                return Err(bad(format!(
                    "key {k}: a coordinate, time or field of view is invalid"
                )));
            }
            let view = DVec3::from(key.target) - DVec3::from(key.eye);
            if view.cross(DVec3::from(key.up)).length_squared() == 0.0 {
                return Err(bad(format!(
                    "key {k}: its eye is its target, or its up is parallel to the view"
                )));
            }
            if k > 0 && key.time_s <= parsed.keys[k - 1].time_s {
                return Err(bad(format!("key {k}: its time is not after the key before")));
            }
        }
        Ok(parsed)
    }

    /// The times of the first and the last key, or `None` for a path without keys.
    pub fn time_span(&self) -> Option<(f64, f64)> {
        Some((self.keys.first()?.time_s, self.keys.last()?.time_s))
    }

    /// The camera at `time_s`, interpolated linearly between the keys on either side of it:
    /// with `s` the fraction of the way from the key before to the key after, `eye`, `target`,
    /// `up` and `fov_deg` are each `(1 - s) a + s b`, so that a key's own time gives that key
    /// exactly. Before the first key the first camera, after the last the last (held).
    /// `None` for a path without keys.
    ///
    /// The interpolated `up` is not normalised, and between two keys that turn the view
    /// around it may come out parallel to the view or zero: a camera built from it checks
    /// that, as it checks any up vector.
    pub fn key_at(&self, time_s: f64) -> Option<CameraKey> {
        let first = self.keys.first()?;
        // The keys at or before `time_s`; the segment starts at the last of them.
        let before = self.keys.partition_point(|k| k.time_s <= time_s);
        if before == 0 {
            return Some(CameraKey { time_s, ..first.clone() });
        }
        let a = &self.keys[before - 1];
        let Some(b) = self.keys.get(before) else {
            return Some(CameraKey { time_s, ..a.clone() });
        };
        let s = (time_s - a.time_s) / (b.time_s - a.time_s);
        let mix = |x: f64, y: f64| (1.0 - s) * x + s * y;
        let mix3 = |x: [f64; 3], y: [f64; 3]| [mix(x[0], y[0]), mix(x[1], y[1]), mix(x[2], y[2])];
        Some(CameraKey {
            time_s,
            eye: mix3(a.eye, b.eye),
            target: mix3(a.target, b.target),
            up: mix3(a.up, b.up),
            fov_deg: mix(a.fov_deg, b.fov_deg),
        })
    }

    /// The key of a frame at `time_s` ([`CameraPath::key_at`]), its up vector replaced by north
    /// where it is parallel to the view, as [`Camera::usable_up`] replaces it (the flag says
    /// whether it was); `None` for a path without keys. The frame's camera is
    /// [`CameraKey::camera`] of it, the camera `relief render` makes of those `--eye`,
    /// `--target`, `--up` and `--fov`.
    pub fn frame_key(&self, time_s: f64) -> Option<(CameraKey, bool)> {
        let key = self.key_at(time_s)?;
        let (eye, target) = (DVec3::from(key.eye), DVec3::from(key.target));
        let (up, replaced) = Camera::usable_up(eye, target, DVec3::from(key.up));
        Some((CameraKey { up: up.to_array(), ..key }, replaced))
    }

    /// The times of `frames` frames spread evenly over the path's span `t0..=t1`: frame `i`
    /// at `t0 + i (t1 - t0) / (frames - 1)` (computed as `(1 - r) t0 + r t1` with
    /// `r = i / (frames - 1)`, so that the first and last frames fall exactly on the first and
    /// last keys); one frame is at `t0`. Empty for a path without keys.
    pub fn frame_times(&self, frames: u32) -> Vec<f64> {
        let Some((t0, t1)) = self.time_span() else { return Vec::new() };
        if frames == 1 {
            return vec![t0];
        }
        let last = f64::from(frames - 1);
        (0..frames)
            .map(|i| {
                let r = f64::from(i) / last;
                (1.0 - r) * t0 + r * t1
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(t: f64, x: f64) -> CameraKey {
        CameraKey {
            time_s: t,
            eye: [x, 0.0, 10.0],
            target: [0.0; 3],
            up: [0.0, 0.0, 1.0],
            fov_deg: 45.0,
        }
    }

    #[test]
    fn cameras_between_keys_are_interpolated_and_keys_hit_exactly() {
        let mut path = CameraPath::default();
        path.push(key(0.0, 1.0));
        path.push(CameraKey { fov_deg: 60.0, up: [0.0, 1.0, 1.0], ..key(0.5, 2.0) });
        path.push(key(1.5, 0.1));
        assert_eq!(path.time_span(), Some((0.0, 1.5)));
        for k in &path.keys {
            assert_eq!(path.key_at(k.time_s).as_ref(), Some(k));
        }
        let middle = path.key_at(0.25).unwrap();
        assert_eq!(middle.eye, [1.5, 0.0, 10.0]);
        assert_eq!(middle.up, [0.0, 0.5, 1.0]);
        assert_eq!(middle.fov_deg, 52.5);
        // Held at the ends.
        assert_eq!(path.key_at(-1.0).unwrap().eye, path.keys[0].eye);
        assert_eq!(path.key_at(9.0).unwrap().eye, path.keys[2].eye);
        assert_eq!(path.frame_times(4), [0.0, 0.5, 1.0, 1.5]);
        assert_eq!(path.frame_times(1), [0.0]);
        assert!(CameraPath::default().key_at(0.0).is_none());
        assert!(CameraPath::default().frame_times(3).is_empty());
        // Awkward spans still end on the last key.
        let mut odd = CameraPath::default();
        odd.push(key(0.1, 1.0));
        odd.push(key(0.3, 2.0));
        let times = odd.frame_times(7);
        assert_eq!((times[0], times[6]), (0.1, 0.3));
        assert_eq!(odd.key_at(times[6]).unwrap().eye, odd.keys[1].eye);
    }

    #[test]
    fn a_frame_key_has_a_usable_up_and_makes_the_keys_camera() {
        let mut path = CameraPath::default();
        path.push(key(0.0, 1.0));
        path.push(key(1.0, 2.0));
        let (first, replaced) = path.frame_key(0.0).unwrap();
        assert!(!replaced);
        assert_eq!(first, path.keys[0]);
        assert_eq!(path.frame_key(0.5).unwrap().0, path.key_at(0.5).unwrap());
        // Looking straight down, up along the view: north is at the top instead.
        path.keys[1].eye = [0.0, 0.0, 10.0];
        let (down, replaced) = path.frame_key(3.0).unwrap();
        assert!(replaced);
        assert_eq!((down.up, down.time_s), ([0.0, 1.0, 0.0], 3.0));
        let camera = down.camera(64, 48).unwrap();
        assert_eq!((camera.eye(), camera.up()), (DVec3::new(0.0, 0.0, 10.0), DVec3::Y));
        assert!(CameraKey { target: down.eye, ..down }.camera(64, 48).is_err());
        assert!(CameraPath::default().frame_key(0.0).is_none());
    }

    #[test]
    fn paths_round_trip_and_repeats_are_dropped() {
        let dir = std::env::temp_dir().join(format!("relief-viewer-path-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut path = CameraPath::default();
        path.push(key(0.0, 1.0));
        path.push(key(0.5, 1.0)); // the same camera
        path.push(key(0.4, 2.0)); // back in time
        path.push(key(1.0, 2.0));
        assert_eq!(path.keys.len(), 2);
        let file = dir.join("flight.json");
        path.write(&file).unwrap();
        assert_eq!(CameraPath::read(&file).unwrap(), path);
        std::fs::write(&file, r#"{"format":"x","version":1,"keys":[]}"#).unwrap();
        assert!(CameraPath::read(&file)
            .unwrap_err()
            .to_string()
            .contains("not a relief-camera-path"));
        let mut bad = path.clone();
        bad.keys[1].time_s = 0.0;
        std::fs::write(&file, serde_json::to_string(&bad).unwrap()).unwrap();
        assert!(CameraPath::read(&file).unwrap_err().to_string().contains("key 1"));
        let mut bad = path.clone();
        bad.keys[0].up = [2.0, 0.0, 20.0]; // along the view, from (1, 0, 10) to the origin
        std::fs::write(&file, serde_json::to_string(&bad).unwrap()).unwrap();
        assert!(CameraPath::read(&file).unwrap_err().to_string().contains("parallel"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
