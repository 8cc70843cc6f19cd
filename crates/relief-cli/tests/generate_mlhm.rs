//! End-to-end tests of `relief generate mlhm`: every scene is written in the reference
//! simulator's format and reads back to the map the library generates; bad input is refused.

mod common;

use common::{assert_refused, relief, scratch};
use relief_core::{Mlhm, Precision};
use relief_io::{read_mlhm_scene, MlhmScene, ReadOptions};
use relief_sim::{carved_scene, rivers_rain, CarvedScene, RIVERS_RAIN_SEED};
use std::path::Path;

/// Runs `relief generate mlhm` with `args` and the output `json`; it must succeed.
fn generate(json: &Path, args: &[&str]) {
    let mut all = vec!["generate", "mlhm", "-o", json.to_str().unwrap()];
    all.extend(args);
    let out = relief(&all);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "relief {all:?}: {stderr}");
    assert!(stderr.contains("wrote"), "{stderr}");
}

fn read_back(json: &Path) -> MlhmScene {
    read_mlhm_scene(json, &ReadOptions::default()).unwrap()
}

#[test]
fn every_scene_reads_back_to_the_generated_map() {
    let mut expected: Vec<(&str, Mlhm)> =
        vec![("rivers-rain", rivers_rain(24, 4, RIVERS_RAIN_SEED).unwrap())];
    for scene in CarvedScene::ALL {
        expected.push((scene.name(), carved_scene(scene, 24, 4).unwrap()));
    }
    for (name, map) in expected {
        let json = scratch(&format!("{name}.json"));
        generate(&json, &["--scene", name, "--size", "24"]);
        assert!(json.with_extension("dat").is_file(), "{name}: no .dat");
        let scene = read_back(&json);
        assert_eq!(scene.repaired, 0, "{name}");
        assert_eq!(scene.precision, Precision::F32, "{name}");
        assert_eq!(scene.mlhm, map, "{name}");
        if name != "rivers-rain" {
            assert!(scene.mlhm.layer_counts().iter().any(|&n| n >= 2), "{name}: no overhang");
        }
    }
}

#[test]
fn options_reach_the_scene() {
    let json = scratch("options.json");
    generate(&json, &["--scene", "combined", "--size", "20", "--max-layers", "2", "--half"]);
    let scene = read_back(&json);
    assert_eq!(scene.precision, Precision::F16);
    let expected = carved_scene(CarvedScene::Combined, 20, 2).unwrap();
    assert_eq!(scene.mlhm, expected.to_precision(Precision::F16).unwrap());

    let json = scratch("seeded.json");
    generate(&json, &["--scene", "rivers-rain", "--size", "16", "--seed", "9"]);
    assert_eq!(read_back(&json).mlhm, rivers_rain(16, 4, 9).unwrap());
}

#[test]
fn bad_input_is_refused_with_exit_code_2_and_writes_nothing() {
    let cases: [(&[&str], &str); 7] = [
        (&["--scene", "volcano", "--size", "16"], "unknown scene 'volcano'"),
        (&["--scene", "cave", "--size", "0"], "between 1 and 65536"),
        (&["--scene", "cave", "--size", "2000000"], "between 1 and 65536"),
        (&["--scene", "cave", "--size", "60000"], "memory limit"),
        (&["--scene", "arches", "--size", "512", "--max-memory", "1M"], "memory limit"),
        (&["--scene", "arches", "--size", "16", "--max-layers", "0"], "between 1 and 127"),
        (&["--scene", "rivers-rain", "--size", "16", "--max-layers", "200"], "between 1 and 127"),
    ];
    let missing = scratch("no-such-folder").join("scene.json");
    let outputs = (0..cases.len()).map(|i| scratch(&format!("refused-{i}.json")));
    for ((args, mentions), json) in cases
        .into_iter()
        .chain([(&["--scene", "chasm", "--size", "16"][..], "does not exist")])
        .zip(outputs.chain([missing.clone()]))
    {
        let mut all = vec!["generate", "mlhm", "-o", json.to_str().unwrap()];
        all.extend(args);
        let out = relief(&all);
        assert_refused(&out, mentions);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr}");
        assert!(!json.exists() && !json.with_extension("dat").exists(), "{args:?} wrote");
    }
    assert!(!missing.parent().unwrap().exists());
}
