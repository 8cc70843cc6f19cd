//! `relief render --stats F.json`: the stage timings of every tracer and input kind, read
//! back; written only after a render that succeeded, and refused before any work when its
//! path is bad.

mod common;

use common::{assert_refused, read_f32_npy, relief, scratch};
use serde_json::Value;
use std::path::Path;

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

const STAGES: [&str; 5] = ["load_ms", "build_ms", "trace_ms", "shade_ms", "write_ms"];

/// Renders with `args` and `--stats`, checks the stages and counts against the depth written
/// beside, and returns the stats.
fn render_stats(name: &str, args: &[&str]) -> Value {
    let (png, depth, stats) = (
        scratch(&format!("{name}.png")),
        scratch(&format!("{name}.npy")),
        scratch(&format!("{name}.json")),
    );
    let mut all = vec!["render"];
    all.extend(args);
    all.extend(["--size", "24x16", "-o", p(&png), "--depth", p(&depth), "--stats", p(&stats)]);
    let out = relief(&all);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let ms = |key: &str| v[key].as_f64().unwrap_or_else(|| panic!("{name}: no {key} in {v}"));
    let mut sum = 0.0;
    for key in STAGES {
        assert!(ms(key) >= 0.0, "{name}: {key} in {v}");
        sum += ms(key);
    }
    assert!(ms("total_ms") >= sum, "{name}: the stages add up to more than the total: {v}");
    assert_eq!((v["width"].clone(), v["height"].clone()), (24.into(), 16.into()), "{v}");
    let (_, depth) = read_f32_npy(&depth);
    let hits = depth.iter().filter(|d| d.is_finite()).count();
    assert_eq!(v["hits"].as_u64(), Some(hits as u64), "{name}: {v}");
    assert!(v["rays"].as_u64().unwrap() >= 24 * 16, "{name}: {v}");
    assert!(hits > 0, "{name}: the view shows no terrain");
    v
}

#[test]
fn every_height_field_tracer_writes_its_stages() {
    for tracer in ["naive", "mipmap", "safety"] {
        let v = render_stats(
            &format!("stats-{tracer}"),
            &["--fbm-size", "32", "--tracer", tracer, "--no-shadows"],
        );
        assert_eq!(v["tracer"], tracer, "{v}");
        assert_eq!(v["input"], "fbm");
        assert_eq!(v["kind"], "height field");
        assert_eq!(v["rays"], 24 * 16, "{v}");
        assert_eq!(v["terrain"], serde_json::json!([32, 32]));
    }
    let file = scratch("stats-input.npy");
    let heights: Vec<f32> = (0..400).map(|i| ((i % 20) as f32 * 0.4).sin() + 2.0).collect();
    relief_io::write_npy_f32(&file, &[20, 20], &heights).unwrap();
    let v = render_stats("stats-file", &[p(&file), "--surface", "boxes"]);
    assert_eq!(v["input"], p(&file));
    assert_eq!(v["surface"], "boxes");
}

#[test]
fn mlhm_scenes_write_their_stages() {
    let scene = scratch("stats-scene.mlhm");
    let out = relief(&["generate", "mlhm", "--scene", "arches", "--size", "16", "-o", p(&scene)]);
    assert!(out.status.success());
    for extra in [
        &["--tracer", "naive"][..],
        &["--tracer", "hierarchy"][..],
        &["--mode", "smooth", "--preset", "low"][..],
    ] {
        let name = format!("stats-mlhm-{}", extra.join("-").replace("--", ""));
        let mut args = vec![p(&scene)];
        args.extend(extra);
        let v = render_stats(&name, &args);
        assert_eq!(v["kind"], "mlhm", "{v}");
        assert_eq!(v["shading_in_trace"], true);
        assert_eq!(v["primary_rays"], 24 * 16, "{v}");
    }
}

#[test]
fn stats_come_only_after_success_and_bad_paths_are_refused_first() {
    let stats = scratch("stats-failed.json");
    let _ = std::fs::remove_file(&stats);
    let png = scratch("stats-failed.png");
    let _ = std::fs::remove_file(&png);
    let missing = scratch("stats-no-such-input.tif");
    let out = relief(&["render", p(&missing), "-o", p(&png), "--stats", p(&stats)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!stats.exists(), "a failed render wrote its stats");

    let scene = scratch("stats-scene.json");
    let out = relief(&["generate", "mlhm", "--scene", "cave", "--size", "8", "-o", p(&scene)]);
    assert!(out.status.success());
    let bad = [
        (None, scratch("stats.txt"), "written as .json"),
        (None, scratch("no-such-folder/s.json"), "does not exist"),
        (Some(&scene), scene.clone(), "would overwrite the input"),
    ];
    for (input, path, mentions) in bad {
        let mut all: Vec<&str> = vec!["render"];
        all.extend(input.iter().map(|i| p(i)));
        all.extend(["--size", "8x8", "-o", p(&png), "--stats", p(&path)]);
        let out = relief(&all);
        assert_refused(&out, mentions);
        assert!(!png.exists(), "{mentions}: the picture was rendered before the refusal");
    }
}
