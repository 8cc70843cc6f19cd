//! The JSON of the reference MLHM simulator's scenes: flat settings, of which relief reads the
//! terrain keys (`Terrain/GridSize`, `Terrain/GridScale`, `Terrain/MaxLayerCount`,
//! `Terrain/UsedLayerCount`, `Terrain/File`, `Terrain/IsHalfPrecision`) and keeps the others
//! untouched in [`MlhmSceneHeader::settings`].

use crate::format_error::FormatError;
use crate::input_file::open_input;
use crate::IoError;
use relief_core::Precision;
use serde_json::{Map, Value};
use std::io::Read;
use std::path::{Path, PathBuf};

/// `[W, H]`: cells along x and y.
pub(crate) const KEY_SIZE: &str = "Terrain/GridSize";
/// The cell size in metres.
pub(crate) const KEY_SCALE: &str = "Terrain/GridScale";
/// The simulator's layer capacity.
pub(crate) const KEY_MAX_LAYERS: &str = "Terrain/MaxLayerCount";
/// The layer planes stored in the `.dat`.
pub(crate) const KEY_USED_LAYERS: &str = "Terrain/UsedLayerCount";
/// The `.dat`, relative to the JSON's folder; empty for a procedural scene.
pub(crate) const KEY_FILE: &str = "Terrain/File";
/// Whether the `.dat` holds f16 values.
pub(crate) const KEY_HALF: &str = "Terrain/IsHalfPrecision";

/// Largest scene JSON read (the reference's are a few KiB).
const MAX_JSON_BYTES: u64 = 16 << 20;

/// Largest layer count the `.dat`'s int8 layer counts can hold.
pub(crate) const MAX_FILE_LAYERS: usize = 127;

/// What a scene's JSON says about its terrain.
#[derive(Debug, Clone, PartialEq)]
pub struct MlhmSceneHeader {
    /// Cells along x and y (`Terrain/GridSize`).
    pub width: usize,
    /// Cells along y.
    pub height: usize,
    /// Cell size in metres (`Terrain/GridScale`).
    pub cell_size: f64,
    /// `Terrain/MaxLayerCount`: the simulator's layer capacity.
    pub max_layer_count: usize,
    /// `Terrain/UsedLayerCount`: the layer planes stored in the `.dat` (L of the MLHM).
    pub used_layer_count: usize,
    /// How the `.dat` stores its values (`Terrain/IsHalfPrecision`).
    pub precision: Precision,
    /// The `.dat` file, resolved against the JSON's folder; `None` for a procedural scene
    /// (an empty `Terrain/File`).
    pub data_file: Option<PathBuf>,
    /// Every other key of the JSON, as found.
    pub settings: Map<String, Value>,
}

/// Reads the JSON of a scene: its terrain keys, the `.dat` it names and its other settings.
///
/// Errors: [`IoError::Io`] when the file cannot be read, [`IoError::Format`] for JSON that is
/// not an object or a missing or ill-typed terrain key (naming the key).
pub fn read_mlhm_scene_header(path: &Path) -> Result<MlhmSceneHeader, IoError> {
    let (file, len) = open_input(path)?;
    read_header_from(file, len, path).map_err(|e| e.at(path))
}

/// [`read_mlhm_scene_header`] from `file` holding the `len` bytes of the JSON at `path`,
/// before the file is named; `path` only locates the `.dat`.
fn read_header_from(
    file: impl Read,
    len: u64,
    path: &Path,
) -> Result<MlhmSceneHeader, FormatError> {
    if len > MAX_JSON_BYTES {
        return Err(FormatError::Format(format!("{len} bytes is too large for a scene JSON")));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(MAX_JSON_BYTES).read_to_end(&mut bytes).map_err(FormatError::Io)?;
    decode_header(&bytes, path)
}

/// [`read_mlhm_scene_header`] of JSON text in `bytes`; `path` locates the `.dat` and names
/// the file in errors.
pub fn parse_mlhm_scene_header(bytes: &[u8], path: &Path) -> Result<MlhmSceneHeader, IoError> {
    decode_header(bytes, path).map_err(|e| e.at(path))
}

/// The header of the JSON text `bytes` at `path`, before the file is named; `path` only
/// locates the `.dat`.
fn decode_header(bytes: &[u8], path: &Path) -> Result<MlhmSceneHeader, FormatError> {
    let value: Value = serde_json::from_slice(bytes)
        .map_err(|e| FormatError::Format(format!("not valid JSON: {e}")))?;
    let Value::Object(mut settings) = value else {
        return Err(FormatError::Format("the scene JSON is not an object of settings".into()));
    };
    let bad = |key: &str, want: &str, got: Option<&Value>| {
        FormatError::Format(match got {
            None => format!("missing key {key} ({want})"),
            Some(v) => format!("key {key} is {v}, expected {want}"),
        })
    };
    let count = |v: Option<&Value>| v.and_then(Value::as_u64).filter(|&n| n > 0);
    let size = settings.remove(KEY_SIZE);
    let dims = size.as_ref().and_then(Value::as_array).filter(|a| a.len() == 2);
    let (width, height) = match dims.map(|a| (count(a.first()), count(a.get(1)))) {
        Some((Some(w), Some(h))) => (w, h),
        _ => return Err(bad(KEY_SIZE, "[W, H] of positive integers", size.as_ref())),
    };
    let (width, height) = match (usize::try_from(width), usize::try_from(height)) {
        (Ok(w), Ok(h)) => (w, h),
        _ => return Err(bad(KEY_SIZE, "a grid that fits in memory", size.as_ref())),
    };
    let scale = settings.remove(KEY_SCALE);
    let cell_size = match scale.as_ref().and_then(Value::as_f64) {
        Some(s) if s.is_finite() && s > 0.0 => s,
        _ => return Err(bad(KEY_SCALE, "a number > 0", scale.as_ref())),
    };
    let max = settings.remove(KEY_MAX_LAYERS);
    let layers = |n: u64| usize::try_from(n).ok().filter(|&n| n <= MAX_FILE_LAYERS);
    let max_layer_count = count(max.as_ref())
        .and_then(layers)
        .ok_or_else(|| bad(KEY_MAX_LAYERS, "an integer in 1..=127", max.as_ref()))?;
    let used = settings.remove(KEY_USED_LAYERS);
    let used_layer_count = match used.as_ref() {
        None => max_layer_count,
        Some(v) => count(Some(v))
            .and_then(layers)
            .filter(|&n| n <= max_layer_count)
            .ok_or_else(|| bad(KEY_USED_LAYERS, "an integer in 1..=MaxLayerCount", Some(v)))?,
    };
    let half = settings.remove(KEY_HALF);
    let precision = match half.as_ref() {
        None | Some(Value::Bool(false)) => Precision::F32,
        Some(Value::Bool(true)) => Precision::F16,
        Some(v) => return Err(bad(KEY_HALF, "true or false", Some(v))),
    };
    let folder = path.parent().unwrap_or(Path::new(""));
    let file = settings.remove(KEY_FILE);
    let data_file = match file.as_ref() {
        None => Some(path.with_extension("dat")),
        Some(Value::String(s)) if s.is_empty() => None,
        Some(Value::String(s)) => Some(folder.join(s)),
        Some(v) => return Err(bad(KEY_FILE, "a file name", Some(v))),
    };
    Ok(MlhmSceneHeader {
        width,
        height,
        cell_size,
        max_layer_count,
        used_layer_count,
        precision,
        data_file,
        settings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_keys_are_parsed_and_the_rest_kept() {
        let json = br#"{"Terrain/GridSize": [4, 2], "Terrain/GridScale": 0.5,
            "Terrain/MaxLayerCount": 8, "Camera/FieldOfView": 1.0}"#;
        let h = parse_mlhm_scene_header(json, Path::new("/a/b/scene.json")).unwrap();
        assert_eq!((h.width, h.height, h.cell_size), (4, 2, 0.5));
        assert_eq!((h.max_layer_count, h.used_layer_count), (8, 8));
        assert_eq!(h.data_file.as_deref(), Some(Path::new("/a/b/scene.dat")));
        assert_eq!(h.settings.len(), 1);
        let json = br#"{"Terrain/GridSize": [4, 2], "Terrain/GridScale": 1,
            "Terrain/MaxLayerCount": 8, "Terrain/File": "", "Terrain/IsHalfPrecision": true}"#;
        let h = parse_mlhm_scene_header(json, Path::new("/a/scene.json")).unwrap();
        assert_eq!((h.data_file, h.precision), (None, Precision::F16));
    }

    #[test]
    fn bad_keys_are_refused_naming_the_key() {
        let base = r#""Terrain/GridScale": 1, "Terrain/MaxLayerCount": 4"#;
        for (json, key) in [
            (format!(r#"{{"Terrain/GridSize": [4], {base}}}"#), KEY_SIZE),
            (format!(r#"{{"Terrain/GridSize": [0, 2], {base}}}"#), KEY_SIZE),
            (r#"{"Terrain/GridSize": [4, 2], "Terrain/MaxLayerCount": 4}"#.to_owned(), KEY_SCALE),
            (
                format!(r#"{{"Terrain/GridSize": [4, 2], {base}, "Terrain/UsedLayerCount": 5}}"#),
                KEY_USED_LAYERS,
            ),
            (format!(r#"{{"Terrain/GridSize": [4, 2], {base}, "Terrain/File": 3}}"#), KEY_FILE),
            ("[1, 2]".to_owned(), "not an object"),
            ("{".to_owned(), "not valid JSON"),
        ] {
            let err = parse_mlhm_scene_header(json.as_bytes(), Path::new("s.json"))
                .unwrap_err()
                .to_string();
            assert!(err.contains(key) && err.contains("s.json"), "{err}");
        }
    }
}
