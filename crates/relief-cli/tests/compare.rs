//! `relief compare` end to end: the metrics of hand-made depth images read back from its
//! JSON, R and the cell from --terrain (height files and MLHM scenes) or the defaults, two
//! exact tracers' depth images agreeing, and every bad input refused in one line, exit 2.

mod common;

use common::{assert_refused, relief, scratch, stdout_of};
use serde_json::Value;
use std::path::{Path, PathBuf};

const INF: f32 = f32::INFINITY;

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// A depth image of `rows` x `cols` written as relief writes depth.
fn depth_file(name: &str, rows: usize, cols: usize, depth: &[f32]) -> PathBuf {
    let path = scratch(name);
    relief_io::write_npy_f32(&path, &[rows, cols], depth).unwrap();
    path
}

fn compare_json(args: &[&str]) -> Value {
    let mut all = vec!["compare"];
    all.extend(args);
    all.push("--json");
    serde_json::from_str(stdout_of(&relief(&all)).trim()).unwrap()
}

fn f(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

#[test]
fn hand_computed_metrics_come_back_in_the_json() {
    // Rendered pixels err by 0.5, 3 (more than the cell of 2) and 0; one pixel each way is
    // terrain against sky; one is sky in both.
    let reference = depth_file("cmp-ref.npy", 2, 3, &[10.0, 6.0, 4.0, INF, 8.0, INF]);
    let test = depth_file("cmp-test.npy", 2, 3, &[10.5, 9.0, 4.0, 7.0, INF, INF]);
    let m = compare_json(&[p(&reference), p(&test), "--diagonal", "50", "--cell", "2"]);
    let mse: f64 = (0.25 + 9.0) / 3.0;
    assert!((f(&m, "psnr_db") - 10.0 * (2500.0 / mse).log10()).abs() < 1e-9, "{m}");
    assert_eq!(f(&m, "wrong_pixel_fraction"), 0.5);
    assert_eq!(f(&m, "max_rel_error"), 0.5);
    assert_eq!(m["wrong"], 3);
    assert_eq!(m["rendered"], 3);
    assert_eq!(m["reference_only"], 1);
    assert_eq!(m["test_only"], 1);
    assert_eq!(m["off_by_more_than_a_cell"], 1);
    assert_eq!(m["pixels"], 6);
    assert_eq!((m["width"].clone(), m["height"].clone()), (3.into(), 2.into()));
    assert_eq!(m["diagonal_from"], "given");

    // Without a terrain or options: R is the largest finite reference depth, the cell 1, so
    // the error of 3 is wrong and so is nothing else new.
    let m = compare_json(&[p(&reference), p(&test)]);
    assert_eq!(f(&m, "diagonal"), 10.0);
    assert_eq!(f(&m, "cell"), 1.0);
    assert_eq!(m["cell_from"], "default");
    assert!((f(&m, "psnr_db") - 10.0 * (100.0 / mse).log10()).abs() < 1e-9, "{m}");

    // The human-readable report says the same.
    let text = stdout_of(&relief(&["compare", p(&reference), p(&test), "--diagonal", "50"]));
    assert!(text.contains("PSNR 29.09 dB"), "{text}");
    assert!(text.contains("wrong pixels 3 of 6"), "{text}");
}

#[test]
fn identical_images_have_null_psnr_and_no_wrong_pixel() {
    let d = depth_file("cmp-same.npy", 3, 2, &[1.0, INF, 2.5, 3.0, INF, 0.5]);
    let m = compare_json(&[p(&d), p(&d)]);
    assert!(m["psnr_db"].is_null(), "{m}");
    assert_eq!(f(&m, "wrong_pixel_fraction"), 0.0);
    assert_eq!(f(&m, "max_rel_error"), 0.0);
    let text = stdout_of(&relief(&["compare", p(&d), p(&d)]));
    assert!(text.contains("PSNR infinite"), "{text}");
}

#[test]
fn the_terrain_gives_the_diagonal_and_the_cell() {
    let terrain = scratch("cmp-terrain.npy");
    // A 6 x 4 grid, heights 0 at row 0 up to 12 at row 3: the boxes' solid spans 6 x 4 x 12
    // cells and samples at spacing 1, or 12 x 12 x 24 at --spacing 2,3 --z-scale 2.
    let heights: Vec<f32> = (0..24).map(|i| (i / 6) as f32 * 4.0).collect();
    relief_io::write_npy_f32(&terrain, &[4, 6], &heights).unwrap();
    let d = depth_file("cmp-t-depth.npy", 1, 2, &[5.0, 6.0]);
    let m = compare_json(&[p(&d), p(&d), "--terrain", p(&terrain)]);
    assert!((f(&m, "diagonal") - (36.0f64 + 16.0 + 144.0).sqrt()).abs() < 1e-12, "{m}");
    assert_eq!(f(&m, "cell"), 1.0);
    assert_eq!(m["diagonal_from"], "terrain");
    let m = compare_json(&[
        p(&d),
        p(&d),
        "--terrain",
        p(&terrain),
        "--spacing",
        "2,3",
        "--z-scale",
        "2",
    ]);
    assert!((f(&m, "diagonal") - (144.0f64 + 144.0 + 576.0).sqrt()).abs() < 1e-12, "{m}");
    assert_eq!(f(&m, "cell"), 3.0);
    // Explicit values win over the terrain's.
    let m = compare_json(&[p(&d), p(&d), "--terrain", p(&terrain), "--cell", "0.5"]);
    assert_eq!((f(&m, "cell"), m["cell_from"].clone()), (0.5, "given".into()));
    assert_eq!(m["diagonal_from"], "terrain");

    // An MLHM scene: its cells' size, and a diagonal at least its footprint's.
    let scene = scratch("cmp-scene.mlhm");
    let out = relief(&["generate", "mlhm", "--scene", "arches", "--size", "16", "-o", p(&scene)]);
    assert!(out.status.success());
    let map = relief_io::read_mlhm_native(&scene, &relief_io::ReadOptions::default()).unwrap();
    let m = compare_json(&[p(&d), p(&d), "--terrain", p(&scene)]);
    assert_eq!(f(&m, "cell"), map.cell_size());
    assert!(f(&m, "diagonal") > 16.0 * map.cell_size() * 2f64.sqrt());
}

#[test]
fn two_exact_tracers_agree() {
    let (a, b) = (scratch("cmp-mipmap.npy"), scratch("cmp-naive.npy"));
    for (tracer, depth) in [("mipmap", &a), ("naive", &b)] {
        let png = scratch(&format!("cmp-{tracer}.png"));
        let args = ["render", "--fbm-size", "48", "--size", "40x24", "--tracer", tracer];
        let mut args = args.to_vec();
        args.extend(["-o", p(&png), "--depth", p(depth)]);
        assert!(relief(&args).status.success());
    }
    let m = compare_json(&[p(&a), p(&b)]);
    assert_eq!(m["wrong"], 0, "{m}");
    assert!(f(&m, "max_rel_error") < 1e-4, "{m}");
    assert!(m["rendered"].as_u64().unwrap() > 100, "{m}");
}

#[test]
fn bad_inputs_are_refused_in_one_line() {
    let a = depth_file("cmp-bad-a.npy", 2, 3, &[1.0; 6]);
    let b = depth_file("cmp-bad-b.npy", 3, 2, &[1.0; 6]);
    let nan = depth_file("cmp-bad-nan.npy", 2, 3, &[1.0, 1.0, f32::NAN, 1.0, 1.0, 1.0]);
    let missing = scratch("cmp-missing.npy");
    let png = scratch("cmp-not.png");
    std::fs::write(&png, b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec![p(&a), p(&b)], "different shapes"),
        (vec![p(&a), p(&missing)], "cmp-missing.npy"),
        (vec![p(&png), p(&a)], "not a .npy file"),
        (vec![p(&a), p(&nan)], "pixel (2, 0)"),
        (vec![p(&a), p(&a), "--diagonal", "0"], "positive length"),
        (vec![p(&a), p(&a), "--cell", "-2"], "positive length"),
        (vec![p(&a), p(&a), "--spacing", "2"], "--terrain"),
        (vec![p(&a), p(&a), "--terrain", p(&missing)], "cmp-missing.npy"),
        (vec![p(&a)], "TEST"),
    ];
    for (args, mentions) in cases {
        let mut all = vec!["compare"];
        all.extend(&args);
        let out = relief(&all);
        assert_refused(&out, mentions);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
    }
}
