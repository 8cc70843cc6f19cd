//! End-to-end tests of relief's own `.mlhm` files: `relief generate mlhm -o scene.mlhm` writes
//! one, `relief render scene.mlhm` renders it to the same depth as the `.json` scene of the same
//! terrain, `relief convert` goes both ways, and broken files or outputs are refused with exit
//! code 2 before anything is written.

mod common;

use common::{assert_refused, relief, render_depth, scratch};
use relief_core::Precision;
use relief_io::{read_mlhm_native, read_mlhm_scene, ReadOptions};
use std::path::{Path, PathBuf};

/// Runs `relief generate mlhm` for the 32 x 32 cave scene into `name`, with `extra` options.
fn generate(name: &str, extra: &[&str]) -> PathBuf {
    let path = scratch(name);
    let mut args = vec!["generate", "mlhm", "--scene", "cave", "--size", "32"];
    args.extend(extra);
    args.extend(["-o", path.to_str().unwrap()]);
    let out = relief(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    path
}

/// The depth of a fixed 48 x 32 view of `scene` (a view into the cave's overhangs).
fn depth(scene: &Path, name: &str) -> Vec<f32> {
    let args =
        [scene.to_str().unwrap(), "--size", "48x32", "--eye=-40,-30,60", "--target=128,128,10"];
    let (shape, depth, _) = render_depth(name, &args);
    assert_eq!(shape, [32, 48]);
    depth
}

#[test]
fn a_generated_mlhm_file_renders_as_its_json_scene() {
    for (suffix, extra) in [("f32", &[][..]), ("f16", &["--half"][..])] {
        let native = generate(&format!("cave-{suffix}.mlhm"), extra);
        let json = generate(&format!("cave-{suffix}.json"), extra);
        let options = ReadOptions::default();
        let from_native = read_mlhm_native(&native, &options).unwrap();
        let from_json = read_mlhm_scene(&json, &options).unwrap().mlhm;
        assert_eq!(from_native, from_json, "{suffix}");
        let precision = if extra.is_empty() { Precision::F32 } else { Precision::F16 };
        assert_eq!(from_native.precision(), precision);
        let a = depth(&native, &format!("native-{suffix}"));
        let b = depth(&json, &format!("json-{suffix}"));
        assert!(a.iter().filter(|d| d.is_finite()).count() > a.len() / 4, "{suffix}: few hits");
        let same = a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same, "{suffix}: the .mlhm and the .json render different depths");
    }
}

#[test]
fn convert_goes_from_json_to_mlhm_and_back() {
    let json = generate("convert-source.json", &[]);
    let (native, back) = (scratch("converted.mlhm"), scratch("converted-back.json"));
    for (from, to) in [(&json, &native), (&native, &back)] {
        let out = relief(&["convert", from.to_str().unwrap(), to.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    let options = ReadOptions::default();
    let original = read_mlhm_scene(&json, &options).unwrap().mlhm;
    assert_eq!(read_mlhm_native(&native, &options).unwrap(), original);
    assert_eq!(read_mlhm_scene(&back, &options).unwrap().mlhm, original);
    // An MLHM converts to MLHM files only, and a height file to no MLHM file.
    let out = relief(&["convert", native.to_str().unwrap(), scratch("x.npy").to_str().unwrap()]);
    assert_refused(&out, "converts to a .json scene or a .mlhm file");
    let field = scratch("field.npy");
    let out = relief(&["generate", "fbm", "--size", "8", "-o", field.to_str().unwrap()]);
    assert!(out.status.success());
    let out = relief(&["convert", field.to_str().unwrap(), scratch("f.mlhm").to_str().unwrap()]);
    assert_refused(&out, "only an MLHM");
    assert!(!scratch("x.npy").exists() && !scratch("f.mlhm").exists());
}

#[test]
fn generate_refuses_other_extensions_and_writes_nothing() {
    for name in ["scene.npz", "scene", "scene.dat"] {
        let path = scratch(&format!("refused-{name}"));
        let out = relief(&[
            "generate",
            "mlhm",
            "--scene",
            "arches",
            "--size",
            "8",
            "-o",
            path.to_str().unwrap(),
        ]);
        assert_refused(&out, ".mlhm");
        assert!(!path.exists(), "{name} written");
    }
}

#[test]
fn a_corrupt_mlhm_file_is_refused_with_code_2_and_no_output() {
    let good = std::fs::read(generate("corrupt-source.mlhm", &[])).unwrap();
    let truncated = good[..good.len() / 2].to_vec();
    let mut flipped = good.clone();
    // The last member's data (the columns) lies before the central directory at the end.
    let at = good.len() - 400;
    flipped[at] ^= 0x55;
    let cases: [(&str, &[u8], &str); 3] = [
        ("truncated", &truncated, "malformed file"),
        ("flipped", &flipped, "broken-flipped.mlhm"),
        ("not-zip", b"{\"Terrain/GridSize\": [2, 2]}", "zip"),
    ];
    for (name, bytes, mention) in cases {
        let path = scratch(&format!("broken-{name}.mlhm"));
        std::fs::write(&path, bytes).unwrap();
        let (png, depth) =
            (scratch(&format!("broken-{name}.png")), scratch(&format!("b-{name}.npy")));
        let out = relief(&[
            "render",
            path.to_str().unwrap(),
            "--size",
            "16x8",
            "-o",
            png.to_str().unwrap(),
            "--depth",
            depth.to_str().unwrap(),
        ]);
        assert_refused(&out, mention);
        assert!(!png.exists() && !depth.exists(), "{name}: output written");
    }
}
