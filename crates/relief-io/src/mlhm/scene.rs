//! The reference MLHM simulator's scene files: a JSON of flat settings and a zlib `.dat`.
//!
//! The JSON holds flat keys: `Terrain/GridSize` `[W, H]`, `Terrain/GridScale` (metres),
//! `Terrain/MaxLayerCount`, `Terrain/UsedLayerCount` (the layer planes stored, default
//! `MaxLayerCount`), `Terrain/File` (the `.dat`, relative to the JSON's folder; empty means a
//! procedural scene; absent means the JSON's own name with `.dat`) and
//! `Terrain/IsHalfPrecision`, beside `Camera/*`, `Rendering/*`, `Simulation/*` and other keys
//! that relief keeps untouched.
//!
//! The `.dat` is one zlib stream (RFC 1950) of little-endian values, N = W * H * UsedLayerCount:
//! `int8 layerCounts[W*H]`, then per column slot (layer-major, index `x + y*W + k*W*H`)
//! `heights[N]` (bedrock, sand, water, ceiling), `fluxes[N]` (right, up, left, down),
//! `stability[N]`, `sediment[N]`, `damage[N]`: 44 bytes per slot in f32, 22 in f16.

use crate::atomic_write::write_atomically;
use crate::format_error::FormatError;
use crate::input_file::open_input;
use crate::mlhm::scene_header::{
    parse_mlhm_scene_header, read_mlhm_scene_header, MlhmSceneHeader, KEY_FILE, KEY_HALF,
    KEY_MAX_LAYERS, KEY_SCALE, KEY_SIZE, KEY_USED_LAYERS, MAX_FILE_LAYERS,
};
use crate::{IoError, ReadOptions};
use flate2::read::ZlibDecoder;
use flate2::write::ZlibEncoder;
use flate2::Compression;
use half::f16;
use relief_core::{Mlhm, MlhmColumn, Precision};
use serde_json::{Map, Value};
use std::borrow::Cow;
use std::io::{BufReader, Read, Write};
use std::path::Path;

/// Violations of the ordering invariants up to this many metres, left by f32 arithmetic, are
/// closed on reading an f32 scene (see [`Mlhm::from_parts_with_slack`]).
pub const F32_SLACK: f32 = 1e-3;

/// As [`F32_SLACK`] for scenes stored (and simulated) in half precision, whose resolution is
/// 1/32 m at heights of 32 to 64 m.
pub const F16_SLACK: f32 = 0.125;

/// The simulator's per-column state, stored beside the heights; each vector has one entry per
/// column slot, in the MLHM's layer-major order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SimulationState {
    /// Outflow of the virtual pipes: right, up, left, down.
    pub fluxes: Vec<[f32; 4]>,
    /// Stability of the support check.
    pub stability: Vec<f32>,
    /// Suspended sediment.
    pub sediment: Vec<f32>,
    /// Horizontal-erosion damage.
    pub damage: Vec<f32>,
}

impl SimulationState {
    /// All zeros for `slots` column slots: the state of a scene not yet simulated.
    pub fn zeros(slots: usize) -> Self {
        SimulationState {
            fluxes: vec![[0.0; 4]; slots],
            stability: vec![0.0; slots],
            sediment: vec![0.0; slots],
            damage: vec![0.0; slots],
        }
    }
}

/// A scene of the reference simulator: its terrain, its simulation state and its settings.
#[derive(Debug, Clone, PartialEq)]
pub struct MlhmScene {
    /// The terrain; its max layer count is the scene's `UsedLayerCount`.
    pub mlhm: Mlhm,
    /// `Terrain/MaxLayerCount` (written as at least the MLHM's layer count).
    pub max_layer_count: usize,
    /// How the `.dat` stores (or is to store) its values.
    pub precision: Precision,
    /// The simulator's per-column state; `None` writes zeros.
    pub simulation: Option<SimulationState>,
    /// The JSON's other keys (camera, rendering, simulation, ...), kept for writing back.
    pub settings: Map<String, Value>,
    /// How many values reading changed to close float slack (see [`F32_SLACK`]).
    pub repaired: usize,
}

impl MlhmScene {
    /// A scene of `mlhm` with no simulation state and no other settings, stored in f32.
    pub fn new(mlhm: Mlhm) -> Self {
        let max_layer_count = mlhm.max_layers();
        MlhmScene {
            mlhm,
            max_layer_count,
            precision: Precision::F32,
            simulation: None,
            settings: Map::new(),
            repaired: 0,
        }
    }
}

/// Reads the scene whose JSON is at `path` and the `.dat` it names.
///
/// The MLHM is checked as [`Mlhm::validate`] does, after closing float slack of at most
/// [`F32_SLACK`] ([`F16_SLACK`] for half precision); the top column's ceiling, stored as
/// `f32::MAX`, becomes `+inf`. A half-precision scene read without repairs has
/// [`Precision::F16`].
///
/// Errors: those of [`read_mlhm_scene_header`]; [`IoError::Unsupported`] for a procedural
/// scene (empty `Terrain/File`: generate its terrain instead); [`IoError::Limits`] when the
/// scene would need more than `options.max_memory`; [`IoError::Format`] naming the `.dat`
/// for a corrupt zlib stream or a decompressed size other than the JSON's grid needs;
/// [`IoError::InvalidData`] naming the `.dat`, the cell and the column for an invalid MLHM.
pub fn read_mlhm_scene(path: &Path, options: &ReadOptions) -> Result<MlhmScene, IoError> {
    let header = read_mlhm_scene_header(path)?;
    let Some(dat) = header.data_file.clone() else {
        return Err(procedural().at(path));
    };
    check_memory(&header, options).map_err(|e| e.at(&dat))?;
    let (file, _) = open_input(&dat)?;
    decode_dat(BufReader::new(file), header).map_err(|e| e.at(&dat))
}

/// [`read_mlhm_scene`] from the JSON text `json` and the compressed `.dat` bytes `dat`;
/// `path` names the JSON in errors (the `.dat` is named as the JSON would name it). Used by
/// tests and fuzzing.
pub fn read_mlhm_scene_from_bytes(
    json: &[u8],
    dat: &[u8],
    path: &Path,
    options: &ReadOptions,
) -> Result<MlhmScene, IoError> {
    let header = parse_mlhm_scene_header(json, path)?;
    let Some(dat_path) = header.data_file.clone() else {
        return Err(procedural().at(path));
    };
    check_memory(&header, options)
        .and_then(|()| decode_dat(dat, header))
        .map_err(|e| e.at(&dat_path))
}

/// Writes `scene` as a JSON at `path` and a `.dat` beside it (the JSON's name with `.dat`,
/// named in `Terrain/File`), in the scene's precision. Both are written atomically, the
/// `.dat` first, compressed at zlib's fastest level.
///
/// In half precision the MLHM is rounded by [`Mlhm::to_precision`] (conservatively; cells
/// whose columns merge get a zero simulation state) and the simulation state to nearest. The
/// top column's ceiling is written as `f32::MAX` in f32 and `+inf` in f16, as the reference
/// does.
///
/// Errors: [`IoError::InvalidData`] for simulation state of the wrong length, an MLHM with
/// more than 127 layers or values outside f16's range in half precision; [`IoError::Io`] when
/// a file cannot be written.
pub fn write_mlhm_scene(path: &Path, scene: &MlhmScene) -> Result<(), IoError> {
    let map = &scene.mlhm;
    let slots = map.raw_columns().len();
    if map.max_layers() > MAX_FILE_LAYERS {
        return Err(IoError::invalid_data(
            path,
            format!("{} layers: the .dat's int8 layer counts hold at most 127", map.max_layers()),
        ));
    }
    let mut state = match &scene.simulation {
        Some(state) => Cow::Borrowed(state),
        None => Cow::Owned(SimulationState::zeros(slots)),
    };
    let lengths =
        [state.fluxes.len(), state.stability.len(), state.sediment.len(), state.damage.len()];
    if lengths.iter().any(|&n| n != slots) {
        return Err(IoError::invalid_data(
            path,
            format!("simulation state of {lengths:?} values for {slots} column slots"),
        ));
    }
    let rounded;
    let map = match scene.precision {
        Precision::F32 => map,
        Precision::F16 => {
            rounded = map
                .to_precision(Precision::F16)
                .map_err(|e| IoError::invalid_data(path, e.to_string()))?;
            if rounded.layer_counts() != map.layer_counts() {
                reset_merged_cells(map, &rounded, state.to_mut());
            }
            &rounded
        }
    };
    let name = path
        .file_stem()
        .map(|s| format!("{}.dat", s.to_string_lossy()))
        .ok_or_else(|| IoError::invalid_data(path, "the path names no file"))?;
    let dat = path.with_file_name(&name);
    write_atomically(&dat, |w| {
        let mut z = ZlibEncoder::new(w, Compression::fast());
        encode_dat(&mut z, map, state.as_ref(), scene.precision)
            .map_err(|e| IoError::io(&dat, e))?;
        z.finish().map_err(|e| IoError::io(&dat, e))?;
        Ok(())
    })?;
    let mut json = scene.settings.clone();
    json.insert(KEY_SIZE.into(), Value::from(vec![map.width() as u64, map.height() as u64]));
    json.insert(KEY_SCALE.into(), Value::from(map.cell_size()));
    json.insert(KEY_MAX_LAYERS.into(), Value::from(scene.max_layer_count.max(map.max_layers())));
    json.insert(KEY_USED_LAYERS.into(), Value::from(map.max_layers()));
    json.insert(KEY_FILE.into(), Value::from(name));
    json.insert(KEY_HALF.into(), Value::from(scene.precision == Precision::F16));
    let text = serde_json::to_vec_pretty(&Value::Object(json))
        .map_err(|e| IoError::invalid_data(path, e.to_string()))?;
    write_atomically(path, |w| w.write_all(&text).map_err(|e| IoError::io(path, e)))
}

/// The error for reading the terrain of a procedural scene.
fn procedural() -> FormatError {
    FormatError::Unsupported(
        "procedural scene (empty Terrain/File): there is no .dat to read; generate the terrain \
         (RiversRain) instead"
            .into(),
    )
}

/// Bytes per column slot in the `.dat`.
fn slot_bytes(precision: Precision) -> u64 {
    match precision {
        Precision::F32 => 44,
        Precision::F16 => 22,
    }
}

/// The `.dat`'s decompressed size: layer counts and `slot_bytes` per slot.
fn dat_size(header: &MlhmSceneHeader) -> u64 {
    let cells = (header.width as u64).saturating_mul(header.height as u64);
    let slots = cells.saturating_mul(header.used_layer_count as u64);
    cells.saturating_add(slots.saturating_mul(slot_bytes(header.precision)))
}

/// Refuses a scene whose decoding would exceed the memory budget: the decompressed `.dat`,
/// the MLHM (16 bytes a slot, 1 a cell) and the f32 simulation state (28 bytes a slot).
fn check_memory(header: &MlhmSceneHeader, options: &ReadOptions) -> Result<(), FormatError> {
    let cells = (header.width as u64).saturating_mul(header.height as u64);
    let slots = cells.saturating_mul(header.used_layer_count as u64);
    let needed =
        dat_size(header).saturating_add(cells).saturating_add(slots.saturating_mul(16 + 28));
    if needed > options.max_memory || usize::try_from(needed).is_err() {
        return Err(FormatError::Limits {
            width: header.width as u64,
            height: header.height as u64,
            needed,
            limit: options.max_memory,
        });
    }
    Ok(())
}

/// Decompresses the `.dat` from `reader` and builds the scene of `header`, before the `.dat`
/// is named.
fn decode_dat(reader: impl Read, header: MlhmSceneHeader) -> Result<MlhmScene, FormatError> {
    let expected = dat_size(&header);
    // check_memory bounded the size, so it fits in usize.
    let mut bytes = Vec::with_capacity(expected as usize + 1);
    let mut decoder = ZlibDecoder::new(reader).take(expected + 1);
    decoder.read_to_end(&mut bytes).map_err(|e| {
        use std::io::ErrorKind::{InvalidData, InvalidInput, UnexpectedEof};
        if matches!(e.kind(), InvalidData | InvalidInput | UnexpectedEof) {
            FormatError::Format(format!("corrupt zlib stream: {e}"))
        } else {
            FormatError::Io(e)
        }
    })?;
    if bytes.len() as u64 != expected {
        let got =
            if bytes.len() as u64 > expected { "more".to_owned() } else { bytes.len().to_string() };
        return Err(FormatError::Format(format!(
            "decompresses to {got} bytes, but a {} x {} grid of {} layers in {} needs {expected}",
            header.width,
            header.height,
            header.used_layer_count,
            if header.precision == Precision::F16 { "f16" } else { "f32" }
        )));
    }
    let cells = header.width * header.height;
    let slots = cells * header.used_layer_count;
    let (counts, rest) = bytes.split_at(cells);
    let layer_counts = counts.to_vec();
    let mut values = Values { bytes: rest, precision: header.precision };
    let top_of = |i: usize| {
        let k = i / cells;
        usize::from(layer_counts[i % cells]) == k + 1
    };
    let mut columns = Vec::with_capacity(slots);
    for i in 0..slots {
        let mut c = MlhmColumn::from_array(values.array());
        // The reference stores +inf as f32::MAX (and f16 files as +inf; 65504 accepted too).
        let huge =
            c.ceiling == f32::MAX || (header.precision == Precision::F16 && c.ceiling == 65504.0);
        if top_of(i) && huge {
            c.ceiling = f32::INFINITY;
        }
        columns.push(c);
    }
    let fluxes = (0..slots).map(|_| values.array()).collect();
    let stability = (0..slots).map(|_| values.scalar()).collect();
    let sediment = (0..slots).map(|_| values.scalar()).collect();
    let damage = (0..slots).map(|_| values.scalar()).collect();
    let slack = match header.precision {
        Precision::F32 => F32_SLACK,
        Precision::F16 => F16_SLACK,
    };
    let (mut mlhm, repaired) = Mlhm::from_parts_with_slack(
        header.width,
        header.height,
        header.used_layer_count,
        header.cell_size,
        layer_counts,
        columns,
        slack,
    )
    .map_err(|e| FormatError::InvalidData(e.to_string()))?;
    if header.precision == Precision::F16 && repaired == 0 {
        // Exact f16 values of a valid map: the rounding changes nothing but the precision.
        mlhm = mlhm
            .to_precision(Precision::F16)
            .map_err(|e| FormatError::InvalidData(e.to_string()))?;
    }
    Ok(MlhmScene {
        mlhm,
        max_layer_count: header.max_layer_count,
        precision: header.precision,
        simulation: Some(SimulationState { fluxes, stability, sediment, damage }),
        settings: header.settings,
        repaired,
    })
}

/// A cursor over the `.dat`'s little-endian values of one precision. The caller has checked
/// the total size, so reads never run past the end.
struct Values<'a> {
    bytes: &'a [u8],
    precision: Precision,
}

impl Values<'_> {
    /// The next value as f32.
    fn scalar(&mut self) -> f32 {
        match self.precision {
            Precision::F32 => {
                let (v, rest) = self.bytes.split_at(4);
                self.bytes = rest;
                f32::from_le_bytes([v[0], v[1], v[2], v[3]])
            }
            Precision::F16 => {
                let (v, rest) = self.bytes.split_at(2);
                self.bytes = rest;
                f16::from_le_bytes([v[0], v[1]]).to_f32()
            }
        }
    }

    /// The next four values.
    fn array(&mut self) -> [f32; 4] {
        std::array::from_fn(|_| self.scalar())
    }
}

/// Writes the `.dat`'s uncompressed content to `w`.
fn encode_dat(
    w: &mut impl Write,
    map: &Mlhm,
    state: &SimulationState,
    precision: Precision,
) -> std::io::Result<()> {
    let counts = map.layer_counts();
    w.write_all(counts)?;
    let cells = counts.len();
    let mut buf = Vec::with_capacity(1 << 16);
    for (i, c) in map.raw_columns().iter().enumerate() {
        let top = usize::from(counts[i % cells]) == i / cells + 1;
        let mut v = c.to_array();
        if top && v[3] == f32::INFINITY && precision == Precision::F32 {
            v[3] = f32::MAX;
        }
        for x in v {
            put(w, x, precision, &mut buf)?;
        }
    }
    for f in &state.fluxes {
        for &x in f {
            put(w, x, precision, &mut buf)?;
        }
    }
    for plane in [&state.stability, &state.sediment, &state.damage] {
        for &x in plane.iter() {
            put(w, x, precision, &mut buf)?;
        }
    }
    w.write_all(&buf)
}

/// Appends `v` to `buf` in `precision`, little-endian, passing full buffers on to `w`.
fn put(w: &mut impl Write, v: f32, precision: Precision, buf: &mut Vec<u8>) -> std::io::Result<()> {
    match precision {
        Precision::F32 => buf.extend_from_slice(&v.to_le_bytes()),
        Precision::F16 => buf.extend_from_slice(&f16::from_f32(v).to_le_bytes()),
    }
    if buf.len() >= 1 << 16 {
        w.write_all(buf)?;
        buf.clear();
    }
    Ok(())
}

/// Zeroes the simulation state of the cells whose layer count changed from `before` to
/// `after` (columns merged by f16 rounding).
fn reset_merged_cells(before: &Mlhm, after: &Mlhm, state: &mut SimulationState) {
    let cells = before.layer_counts().len();
    for (i, (a, b)) in before.layer_counts().iter().zip(after.layer_counts()).enumerate() {
        if a != b {
            for k in 0..before.max_layers() {
                let s = i + k * cells;
                state.fluxes[s] = [0.0; 4];
                state.stability[s] = 0.0;
                state.sediment[s] = 0.0;
                state.damage[s] = 0.0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_corruption::corrupted_copies;
    use crate::test_dir::TestDir;

    const INF: f32 = f32::INFINITY;

    fn small_scene() -> MlhmScene {
        let mut map = Mlhm::new(3, 2, 3, 0.5).unwrap();
        map.set_cell(
            1,
            1,
            &[MlhmColumn::new(1.0, 0.5, 0.25, 2.0), MlhmColumn::new(3.0, 0.0, 0.0, INF)],
        )
        .unwrap();
        map.set_cell(2, 0, &[MlhmColumn::new(-1.5, 0.1, 2.0, INF)]).unwrap();
        let mut scene = MlhmScene::new(map);
        scene.settings.insert("Camera/FarPlane".into(), Value::from(1000.0));
        scene
    }

    #[test]
    fn files_round_trip_and_corrupted_streams_are_refused() {
        let dir = TestDir::new("mlhm-scene");
        let path = dir.path().join("small.json");
        let scene = small_scene();
        write_mlhm_scene(&path, &scene).unwrap();
        let back = read_mlhm_scene(&path, &ReadOptions::default()).unwrap();
        assert_eq!(back.mlhm, scene.mlhm);
        assert_eq!(back.settings, scene.settings);
        let json = std::fs::read(&path).unwrap();
        let dat = std::fs::read(dir.path().join("small.dat")).unwrap();
        let options = ReadOptions::default();
        // The .dat is a zlib stream whose Adler-32 sees any change to the decoded bytes: a
        // changed stream is a format error, unless the change left it as it was (a byte set
        // to its own value, padding bits after the last block) and the scene is the same.
        let mut refused = 0;
        for bad in corrupted_copies(&dat, 200, 3) {
            match read_mlhm_scene_from_bytes(&json, &bad, &path, &options) {
                Err(err) => {
                    assert!(matches!(err, IoError::Format { .. }), "{err}");
                    refused += 1;
                }
                Ok(read) => assert_eq!(read, back, "a corrupted stream read as another scene"),
            }
        }
        assert!(refused >= 190, "only {refused} of 200 corrupted streams refused");
        for cut in 0..dat.len() {
            assert!(read_mlhm_scene_from_bytes(&json, &dat[..cut], &path, &options).is_err());
        }
    }
}
