//! Scenes of the reference MLHM simulator: the real scene in ../shared/data/ngwm24-scene read
//! and checked against the figures of the reference notes, round trips in f32 and f16, and
//! refusal of broken files.
//! In a bare clone (no ../shared) a test that reads the shared data is reported ignored.

mod common;

use common::{clients, shared_data, TestDir};

use relief_core::{Mlhm, MlhmColumn, Precision};
use relief_io::mlhm::{
    read_mlhm_scene, read_mlhm_scene_from_bytes, read_mlhm_scene_header, write_mlhm_scene,
    MlhmScene,
};
use relief_io::{IoError, ReadOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

fn main() {
    clients::run(vec![
        clients::trial_reading!(
            the_real_scene_matches_the_reference_figures,
            "data/ngwm24-scene/scene.json"
        ),
        clients::trial_reading!(
            the_real_scene_round_trips_in_f32_and_f16,
            "data/ngwm24-scene/scene.json"
        ),
        clients::trial!(small_scenes_round_trip_in_both_precisions),
        clients::trial!(broken_files_are_refused_with_errors_naming_the_file),
        clients::trial!(truncated_and_corrupted_streams_never_panic),
        clients::trial!(half_precision_merges_gaps_it_cannot_resolve_and_resets_their_state),
    ]);
}

/// The real scene's JSON path, or `None` (with the reason printed) in a bare clone.
fn real_scene() -> Option<PathBuf> {
    shared_data("data/ngwm24-scene/scene.json")
}

/// Rounds to two decimals.
fn two_decimals(v: f32) -> f64 {
    (f64::from(v) * 100.0).round() / 100.0
}

fn the_real_scene_matches_the_reference_figures() {
    let Some(path) = real_scene() else { return };
    let header = read_mlhm_scene_header(&path).unwrap();
    assert_eq!((header.width, header.height, header.cell_size), (256, 256, 1.0));
    assert_eq!((header.max_layer_count, header.used_layer_count), (8, 4));
    assert_eq!(header.precision, Precision::F32);
    assert_eq!(header.data_file.as_deref(), Some(path.with_extension("dat").as_path()));
    let dat = std::fs::read(path.with_extension("dat")).unwrap();
    let mut raw = Vec::new();
    std::io::Read::read_to_end(&mut flate2::read::ZlibDecoder::new(&dat[..]), &mut raw).unwrap();
    assert_eq!(raw.len(), 11_599_872);

    let scene = read_mlhm_scene(&path, &ReadOptions::default()).unwrap();
    let map = &scene.mlhm;
    assert_eq!((map.width(), map.height(), map.max_layers(), map.cell_size()), (256, 256, 4, 1.0));
    let mut histogram = [0usize; 5];
    map.layer_counts().iter().for_each(|&n| histogram[usize::from(n)] += 1);
    assert_eq!(histogram, [0, 39_455, 25_967, 112, 2]);
    let (mut bedrock, mut sand, mut water) = ((f32::INFINITY, f32::NEG_INFINITY), 0f32, 0f32);
    for y in 0..256 {
        for x in 0..256 {
            for c in map.cell_columns(x, y) {
                bedrock = (bedrock.0.min(c.bedrock), bedrock.1.max(c.bedrock));
                sand = sand.max(c.sand);
                water = water.max(c.water);
            }
            assert_eq!(map.column(x, y, map.layer_count(x, y) - 1).ceiling, f32::INFINITY);
        }
    }
    assert_eq!((two_decimals(bedrock.0), two_decimals(bedrock.1)), (-2.50, 57.69));
    assert_eq!((two_decimals(sand), two_decimals(water)), (5.01, 11.26));
    // The simulator's f32 arithmetic leaves a few ulp-sized violations, closed on reading.
    assert!(scene.repaired > 0 && scene.repaired < 20, "{} repaired", scene.repaired);
    assert_eq!(scene.settings["Simulation/CurrentSimulationStep"], 1484);
    assert!(scene.settings.contains_key("Camera/Position"));
    assert!(!scene.settings.contains_key("Terrain/GridSize"));
    let state = scene.simulation.as_ref().unwrap();
    assert_eq!(state.fluxes.len(), 256 * 256 * 4);
}

fn the_real_scene_round_trips_in_f32_and_f16() {
    let Some(path) = real_scene() else { return };
    let scene = read_mlhm_scene(&path, &ReadOptions::default()).unwrap();
    let dir = TestDir::new("real");
    let out = dir.join("copy.json");
    write_mlhm_scene(&out, &scene).unwrap();
    let back = read_mlhm_scene(&out, &ReadOptions::default()).unwrap();
    assert_eq!(back.mlhm, scene.mlhm);
    assert_eq!(back.simulation, scene.simulation);
    assert_eq!(back.settings, scene.settings);
    assert_eq!(back.repaired, 0);
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(json["Terrain/File"], "copy.dat");
    assert_eq!(json["Terrain/MaxLayerCount"], 8);

    let half = MlhmScene { precision: Precision::F16, ..scene.clone() };
    let out16 = dir.join("half.json");
    write_mlhm_scene(&out16, &half).unwrap();
    let back16 = read_mlhm_scene(&out16, &ReadOptions::default()).unwrap();
    assert_eq!((back16.precision, back16.mlhm.precision()), (Precision::F16, Precision::F16));
    assert_eq!(back16.mlhm, scene.mlhm.to_precision(Precision::F16).unwrap());
    let dat16 = std::fs::metadata(dir.join("half.dat")).unwrap().len();
    let dat32 = std::fs::metadata(dir.join("copy.dat")).unwrap().len();
    assert!(dat16 < dat32, "{dat16} >= {dat32}");
    // Conservative: every column's tops only rise and its ceiling only falls.
    let (a, b) = (&scene.mlhm, &back16.mlhm);
    for y in 0..256 {
        for x in 0..256 {
            if a.layer_count(x, y) == b.layer_count(x, y) {
                for (o, r) in a.cell_columns(x, y).zip(b.cell_columns(x, y)) {
                    assert!(r.solid_top() >= o.solid_top() && r.water_top() >= o.water_top());
                    assert!(r.ceiling <= o.ceiling);
                }
            }
        }
    }
}

/// A small scene with an overhang and water.
fn small_scene() -> MlhmScene {
    let mut map = Mlhm::new(4, 3, 2, 0.25).unwrap();
    map.set_cell(
        1,
        2,
        &[MlhmColumn::new(0.5, 0.25, 1.0, 2.0), MlhmColumn::new(3.0, 0.5, 0.0, f32::INFINITY)],
    )
    .unwrap();
    map.set_cell(3, 0, &[MlhmColumn::new(-2.0, 0.0, 0.125, f32::INFINITY)]).unwrap();
    let mut scene = MlhmScene::new(map);
    scene.settings.insert("Rendering/VisualScale".into(), 1.0.into());
    scene
}

fn small_scenes_round_trip_in_both_precisions() {
    let dir = TestDir::new("small");
    for precision in [Precision::F32, Precision::F16] {
        let scene = MlhmScene { precision, ..small_scene() };
        let path = dir.join("s.json");
        write_mlhm_scene(&path, &scene).unwrap();
        let back = read_mlhm_scene(&path, &ReadOptions::default()).unwrap();
        // Every value above is exactly an f16, so both precisions keep it.
        assert_eq!(back.mlhm.raw_columns(), scene.mlhm.raw_columns());
        assert_eq!(back.mlhm.layer_counts(), scene.mlhm.layer_counts());
        assert_eq!(back.settings, scene.settings);
        assert_eq!(back.precision, precision);
    }
}

/// Writes `json` as `s.json` in `dir` and `dat` as `s.dat`; reads them.
fn read_files(dir: &TestDir, json: &[u8], dat: &[u8]) -> Result<MlhmScene, IoError> {
    std::fs::write(dir.join("s.json"), json).unwrap();
    std::fs::write(dir.join("s.dat"), dat).unwrap();
    read_mlhm_scene(&dir.join("s.json"), &ReadOptions::default())
}

/// The zlib stream of `bytes`.
fn zlib(bytes: &[u8]) -> Vec<u8> {
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
    z.write_all(bytes).unwrap();
    z.finish().unwrap()
}

fn broken_files_are_refused_with_errors_naming_the_file() {
    let dir = TestDir::new("broken");
    write_mlhm_scene(&dir.join("s.json"), &small_scene()).unwrap();
    let json = std::fs::read(dir.join("s.json")).unwrap();
    let dat = std::fs::read(dir.join("s.dat")).unwrap();
    let mut raw = Vec::new();
    std::io::Read::read_to_end(&mut flate2::read::ZlibDecoder::new(&dat[..]), &mut raw).unwrap();
    assert_eq!(raw.len(), 12 + 24 * 44);

    // Wrong decompressed sizes.
    for bad in [&raw[..raw.len() - 1], &[raw.as_slice(), &[0]].concat()[..]] {
        let err = read_files(&dir, &json, &zlib(bad)).unwrap_err();
        assert!(matches!(err, IoError::Format { .. }), "{err}");
        let msg = err.to_string();
        assert!(msg.contains("s.dat") && msg.contains("decompresses to"), "{msg}");
    }
    // Not zlib at all.
    let err = read_files(&dir, &json, b"not a zlib stream").unwrap_err().to_string();
    assert!(err.contains("s.dat") && err.contains("zlib"), "{err}");
    // An invalid MLHM: a layer count of 3 in a 2-layer scene; negative sand in cell (3, 0).
    let mut bad = raw.clone();
    bad[5] = 3;
    let err = read_files(&dir, &json, &zlib(&bad)).unwrap_err();
    assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    assert!(err.to_string().contains("cell (1, 1)"), "{err}");
    let mut bad = raw.clone();
    let sand = 12 + 3 * 16 + 4;
    bad[sand..sand + 4].copy_from_slice(&(-1f32).to_le_bytes());
    let err = read_files(&dir, &json, &zlib(&bad)).unwrap_err().to_string();
    assert!(err.contains("s.dat") && err.contains("cell (3, 0), column 0"), "{err}");
    // A missing .dat, a procedural scene, bad keys.
    std::fs::remove_file(dir.join("s.dat")).unwrap();
    let err = read_mlhm_scene(&dir.join("s.json"), &ReadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }) && err.to_string().contains("s.dat"), "{err}");
    let text = String::from_utf8(json.clone()).unwrap();
    let procedural = text.replace("\"s.dat\"", "\"\"");
    let err = read_files(&dir, procedural.as_bytes(), &dat).unwrap_err();
    assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
    assert!(err.to_string().contains("procedural"), "{err}");
    let err = read_files(&dir, text.replace("0.25", "-1").as_bytes(), &dat).unwrap_err();
    assert!(err.to_string().contains("Terrain/GridScale") && err.to_string().contains("s.json"));
    // The memory budget is checked before anything is allocated.
    let huge = text.replace(
        "\"Terrain/GridSize\": [\n    4,\n    3\n  ]",
        "\"Terrain/GridSize\": [1000000, 1000000]",
    );
    assert_ne!(huge, text, "the test's GridSize pattern must match the writer's output");
    let err = read_files(&dir, huge.as_bytes(), &dat).unwrap_err();
    assert!(matches!(err, IoError::Limits { .. }), "{err}");
}

fn truncated_and_corrupted_streams_never_panic() {
    let path = Path::new("mem/s.json");
    let dir = TestDir::new("trunc");
    write_mlhm_scene(&dir.join("s.json"), &small_scene()).unwrap();
    let json = std::fs::read(dir.join("s.json")).unwrap();
    let dat = std::fs::read(dir.join("s.dat")).unwrap();
    let options = ReadOptions::default();
    let good = read_mlhm_scene_from_bytes(&json, &dat, path, &options).unwrap();
    for cut in 0..dat.len() {
        assert!(read_mlhm_scene_from_bytes(&json, &dat[..cut], path, &options).is_err());
    }
    for cut in 0..json.len() {
        assert!(read_mlhm_scene_from_bytes(&json[..cut], &dat, path, &options).is_err());
    }
    // The .dat is a zlib stream: its Adler-32 sees every change to the decoded bytes, so a
    // changed stream is refused with a format error, unless the change left the stream as it
    // was (a byte overwritten with its own value, the padding bits after the final block)
    // and the scene reads back unchanged.
    let (mut state, mut refused, mut unchanged) = (0x2545_f491_4f6c_dd1du64, 0, 0);
    for _ in 0..2000 {
        let mut bad = dat.clone();
        for _ in 0..2 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let at = (state % bad.len() as u64) as usize;
            bad[at] = (state >> 24) as u8;
        }
        match read_mlhm_scene_from_bytes(&json, &bad, path, &options) {
            Err(err) => {
                assert!(matches!(err, IoError::Format { .. }), "{err}");
                refused += 1;
            }
            Ok(scene) => {
                assert_eq!(scene, good, "a changed stream read as another scene");
                unchanged += 1;
            }
        }
    }
    assert!(refused >= 1900, "only {refused} of 2000 corrupted streams refused");
    println!("{refused} refused, {unchanged} read back unchanged");
}

fn half_precision_merges_gaps_it_cannot_resolve_and_resets_their_state() {
    let dir = TestDir::new("merge");
    let mut map = Mlhm::new(2, 1, 2, 1.0).unwrap();
    // A 0.1 m gap at 1000 m, where f16 steps by 0.5 m.
    let thin = [
        MlhmColumn::new(1000.1, 0.0, 0.0, 1000.2),
        MlhmColumn::new(1000.3, 0.1, 0.0, f32::INFINITY),
    ];
    map.set_cell(0, 0, &thin).unwrap();
    map.set_cell(
        1,
        0,
        &[MlhmColumn::new(1.0, 0.5, 0.0, 2.0), MlhmColumn::new(3.0, 0.0, 0.0, f32::INFINITY)],
    )
    .unwrap();
    let mut state = relief_io::mlhm::SimulationState::zeros(4);
    state.sediment = vec![0.25, 0.5, 0.75, 1.0];
    let scene =
        MlhmScene { precision: Precision::F16, simulation: Some(state), ..MlhmScene::new(map) };
    let path = dir.join("m.json");
    write_mlhm_scene(&path, &scene).unwrap();
    let back = read_mlhm_scene(&path, &ReadOptions::default()).unwrap();
    assert_eq!(back.mlhm.layer_counts(), &[1, 2]);
    assert!(back.mlhm.column(0, 0, 0).solid_top() >= 1000.4);
    assert_eq!(back.simulation.unwrap().sediment, vec![0.0, 0.5, 0.0, 1.0]);
}
