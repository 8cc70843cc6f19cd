//! `relief flythrough` end to end: a camera path over a raster writes one PNG a frame, each
//! the picture `relief render` makes of the interpolated camera, the same every run; an MLHM
//! scene flies through the same code; a stacks flight with a node budget catches up, once
//! the camera holds still, with the still render; a tile store's flight writes its frames and the
//! per-frame figures of `--stats`; bad paths, outputs and options are refused, exit 2, with
//! no frame written.

mod common;

use common::{assert_refused, relief, scratch, stdout_of};
use std::path::{Path, PathBuf};

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// One camera key: time, eye, target, up, field of view.
type Key = (f64, [f64; 3], [f64; 3], [f64; 3], f64);

/// The flight of every test over the 64 x 64 fBm terrain: round its south-west corner,
/// dipping the field of view. Every coordinate halfway between two keys is exact in binary.
const KEYS: [Key; 3] = [
    (0.0, [-40.0, -40.0, 80.0], [32.0, 32.0, 0.0], [0.0, 0.0, 1.0], 45.0),
    (1.0, [-20.0, -60.0, 70.0], [32.0, 32.0, 0.0], [0.0, 0.0, 1.0], 50.0),
    (2.0, [10.0, -70.0, 60.0], [40.0, 24.0, 4.0], [0.0, 0.5, 1.0], 40.0),
];

/// The camera halfway between the first two keys (t = 0.5), by the documented interpolation.
const HALFWAY: Key = (0.5, [-30.0, -50.0, 75.0], [32.0, 32.0, 0.0], [0.0, 0.0, 1.0], 47.5);

/// Writes a camera path of `keys` named `name`.
fn write_path(name: &str, keys: &[Key]) -> PathBuf {
    let keys: Vec<serde_json::Value> = keys
        .iter()
        .map(|(time_s, eye, target, up, fov_deg)| {
            serde_json::json!({
                "time_s": time_s, "eye": eye, "target": target, "up": up, "fov_deg": fov_deg
            })
        })
        .collect();
    let json = serde_json::json!({
        "format": "relief-camera-path", "version": 1, "keys": keys
    });
    let path = scratch(&format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    path
}

/// A 64 x 64 fBm GeoTIFF named after `name`.
fn raster(name: &str) -> PathBuf {
    let tif = scratch(&format!("{name} dem.tif"));
    stdout_of(&relief(&["generate", "fbm", "--size", "64", "-o", p(&tif)]));
    tif
}

/// A fresh folder path (removed if a run before left it).
fn fresh_dir(name: &str) -> PathBuf {
    let dir = scratch(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Runs `relief flythrough INPUT --path PATH --frames N -o DIR --size 96x64 EXTRA...`; it must
/// succeed. Returns its stderr.
fn fly(input: &Path, path: &Path, frames: u32, dir: &Path, extra: &[&str]) -> String {
    let n = frames.to_string();
    let mut args = vec!["flythrough", p(input), "--path", p(path), "--frames", &n, "-o", p(dir)];
    args.extend(["--size", "96x64"]);
    args.extend(extra);
    let out = relief(&args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{args:?}: {stderr}");
    stderr
}

/// The PNG `relief render INPUT` makes of `key`'s camera at 96 x 64, with `extra` options.
fn render_key(input: &Path, key: &Key, name: &str, extra: &[&str]) -> Vec<u8> {
    let triple = |v: [f64; 3]| format!("{},{},{}", v[0], v[1], v[2]);
    let (eye, target, up, fov) = (triple(key.1), triple(key.2), triple(key.3), key.4.to_string());
    let png = scratch(&format!("{name}.png"));
    // A fly-through's frames are not anti-aliased.
    let mut args = vec!["render", p(input), "-o", p(&png), "--size", "96x64", "--aa", "off"];
    args.extend(["--eye", &eye, "--target", &target, "--up", &up, "--fov", &fov]);
    args.extend(extra);
    stdout_of(&relief(&args));
    std::fs::read(png).unwrap()
}

/// The names of the files in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn frame(dir: &Path, k: usize) -> Vec<u8> {
    std::fs::read(dir.join(format!("frame-{k:05}.png"))).unwrap()
}

#[test]
fn a_path_over_a_raster_writes_each_frame_as_render_draws_its_camera() {
    let tif = raster("fly raster");
    let path = write_path("fly-raster-path", &KEYS);
    let dir = fresh_dir("fly raster frames");
    let options = ["--surface", "boxes", "--sun", "300,40", "--exposure", "1.5"];
    let stderr = fly(&tif, &path, 5, &dir, &options);
    let expected: Vec<String> = (0..5).map(|k| format!("frame-{k:05}.png")).collect();
    assert_eq!(names(&dir), expected);
    // One line a frame, with its time on the path and its time to draw.
    for (k, t) in ["0.000", "0.500", "1.000", "1.500", "2.000"].iter().enumerate() {
        assert!(stderr.contains(&format!("frame {k} (t {t} s): ")), "{stderr}");
    }
    assert!(stderr.contains("RSS"), "{stderr}");
    // Frames 0, 2 and 4 fall on the keys, frame 1 halfway between the first two.
    for (k, key) in [(0, &KEYS[0]), (1, &HALFWAY), (2, &KEYS[1]), (4, &KEYS[2])] {
        let rendered = render_key(&tif, key, &format!("fly-raster-render-{k}"), &options);
        assert!(frame(&dir, k) == rendered, "frame {k} differs from relief render of its camera");
    }
    // The same frames every run.
    let again = fresh_dir("fly raster frames again");
    fly(&tif, &path, 5, &again, &options);
    for k in 0..5 {
        assert!(frame(&dir, k) == frame(&again, k), "frame {k} changed between runs");
    }
    // One frame is the first key; its figures have no tiles.
    let one = fresh_dir("fly raster one frame");
    let stats = scratch("fly-raster-stats.json");
    let mut with_stats = options.to_vec();
    with_stats.extend(["--stats", p(&stats)]);
    fly(&tif, &path, 1, &one, &with_stats);
    assert_eq!(names(&one), ["frame-00000.png"]);
    assert!(frame(&one, 0) == frame(&dir, 0));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let frames = json["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 1, "{json}");
    assert!(frames[0]["time_ms"].as_f64().is_some(), "{json}");
    assert!(frames[0].get("tiles_drawn").is_none(), "{json}");
    assert!(json["summary"]["median_time_ms"].as_f64().is_some(), "{json}");
}

#[test]
fn an_mlhm_scene_flies_through_the_same_renderer() {
    let scene = scratch("fly arches.mlhm");
    stdout_of(&relief(&["generate", "mlhm", "--scene", "arches", "--size", "32", "-o", p(&scene)]));
    let keys: [Key; 2] = [
        (0.0, [-100.0, -100.0, 200.0], [128.0, 128.0, 20.0], [0.0, 0.0, 1.0], 45.0),
        (0.25, [-50.0, -150.0, 180.0], [128.0, 128.0, 20.0], [0.0, 0.0, 1.0], 45.0),
    ];
    let path = write_path("fly-mlhm-path", &keys);
    let dir = fresh_dir("fly mlhm frames");
    fly(&scene, &path, 2, &dir, &["--preset", "low"]);
    let rendered = render_key(&scene, &keys[1], "fly-mlhm-render", &["--preset", "low"]);
    assert!(frame(&dir, 1) == rendered, "the MLHM frame differs from relief render");
}

#[test]
fn a_tile_store_flight_writes_frames_and_per_frame_stats() {
    let tif = raster("fly store");
    let store = fresh_dir("fly store tiles");
    stdout_of(&relief(&["tile", p(&tif), "-o", p(&store), "--tile", "16"]));
    let path = write_path("fly-store-path", &KEYS);
    let dir = fresh_dir("fly store frames");
    let stats = scratch("fly-store-stats.json");
    let stderr = fly(&store, &path, 4, &dir, &["--stats", p(&stats), "--cache-mb", "16"]);
    assert_eq!(names(&dir).len(), 4);
    assert!(stderr.contains("tiles drawn") && stderr.contains("IO wait"), "{stderr}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let frames = json["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 4, "{json}");
    for (k, frame) in frames.iter().enumerate() {
        assert_eq!(frame["frame"], k, "{frame}");
        for key in ["time_ms", "io_wait_ms", "max_error_px"] {
            assert!(frame[key].as_f64().is_some_and(|v| v >= 0.0), "{key} in {frame}");
        }
        for key in ["tiles_drawn", "tiles_standing_in", "tiles_wanted", "resident_bytes"] {
            assert!(frame[key].as_u64().is_some(), "{key} in {frame}");
        }
        assert!(frame["tiles_drawn"].as_u64().unwrap() > 0, "{frame}");
        assert!(frame["resident_bytes"].as_u64().unwrap() <= 16 << 20, "{frame}");
        assert!(frame["rss_bytes"].as_u64().is_some_and(|b| b > 0), "{frame}");
    }
    // The first frame waits for its tiles: none stands in.
    assert_eq!(frames[0]["tiles_standing_in"], 0, "{json}");
    let summary = &json["summary"];
    for key in ["median_time_ms", "max_time_ms", "total_ms", "median_io_wait_ms"] {
        assert!(summary[key].as_f64().is_some(), "{key} in {summary}");
    }
    assert_eq!(summary["frames"], 4);
    assert_eq!(json["kind"], "tile store");

    // With --wait every frame is relief render STORE of its camera.
    let waited = fresh_dir("fly store waited");
    fly(&store, &path, 3, &waited, &["--wait", "--max-error-px", "0"]);
    let rendered = render_key(&store, &KEYS[1], "fly-store-render", &["--max-error-px", "0"]);
    assert!(frame(&waited, 1) == rendered, "the waited frame differs from relief render");
}

#[test]
fn an_amortised_stacks_flight_catches_up_to_the_still_render() {
    let stacks = scratch("fly terrain.stacks");
    let generate = ["generate", "stacks", "--width", "96", "--height", "96", "-o", p(&stacks)];
    stdout_of(&relief(&generate));
    // Closing in for a second, then holding the camera for three.
    let near = (1.0, [-20.0, -40.0, 90.0], [96.0, 96.0, 20.0], [0.0, 0.0, 1.0], 45.0);
    let keys: [Key; 3] = [
        (0.0, [-150.0, -150.0, 200.0], [96.0, 96.0, 20.0], [0.0, 0.0, 1.0], 45.0),
        near,
        (4.0, near.1, near.2, near.3, near.4),
    ];
    let path = write_path("fly-stacks-path", &keys);
    let dir = fresh_dir("fly stacks frames");
    let stats = scratch("fly-stacks-stats.json");
    let options = ["--tau", "2", "--node-budget", "16"];
    let mut with_stats = options.to_vec();
    with_stats.extend(["--stats", p(&stats)]);
    fly(&stacks, &path, 17, &dir, &with_stats);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let notes: Vec<&str> =
        json["frames"].as_array().unwrap().iter().map(|f| f["note"].as_str().unwrap()).collect();
    let waiting = |note: &str| -> usize {
        let before = note.split(" waiting").next().unwrap();
        before.rsplit(' ').next().unwrap().parse().unwrap()
    };
    // Frames 4 to 16 hold the camera: the first of them still draws stand-ins, the last none.
    assert!(waiting(notes[4]) > 0, "{}", notes[4]);
    assert_eq!(waiting(notes[16]), 0, "{}", notes[16]);
    let rendered = render_key(&stacks, &near, "fly-stacks-render", &options[..2]);
    assert!(frame(&dir, 4) != rendered, "frame 4 is amortised, not the still render");
    assert!(frame(&dir, 16) == rendered, "the caught-up frame differs from relief render");
    // Without a budget every frame is the still render of its camera.
    let all = fresh_dir("fly stacks frames, every node");
    fly(&stacks, &path, 17, &all, &["--tau", "2", "--node-budget", "all"]);
    assert!(frame(&all, 4) == rendered, "frame 4 without a budget differs from relief render");
}

#[test]
fn bad_paths_outputs_and_options_are_refused() {
    let tif = raster("fly refused");
    let path = write_path("fly-refused-path", &KEYS);
    let dir = fresh_dir("fly refused frames");
    let run = |path: &Path, frames: &str, out: &Path, extra: &[&str]| {
        let mut args =
            vec!["flythrough", p(&tif), "--path", p(path), "--frames", frames, "-o", p(out)];
        args.extend(["--size", "32x32"]);
        args.extend(extra);
        relief(&args)
    };
    let file = scratch("fly-refused-file.txt");
    std::fs::write(&file, "not a folder").unwrap();
    assert_refused(&run(&path, "3", &file, &[]), "not a folder");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a folder");
    assert_refused(&run(&path, "0", &dir, &[]), "--frames");
    let missing = scratch("fly-no-such-path.json");
    assert_refused(&run(&missing, "3", &dir, &[]), "fly-no-such-path.json");
    let broken = scratch("fly-broken-path.json");
    std::fs::write(&broken, "{\"format\": \"relief-camera-path\", \"version\": 1, \"ke").unwrap();
    assert_refused(&run(&broken, "3", &dir, &[]), "fly-broken-path.json");
    let empty = write_path("fly-empty-path", &[]);
    assert_refused(&run(&empty, "3", &dir, &[]), "no keys");
    // Halfway between these keys the eye is on the target.
    let swapped = write_path(
        "fly-swapped-path",
        &[
            (0.0, [0.0, 0.0, 50.0], [64.0, 64.0, 0.0], [0.0, 0.0, 1.0], 45.0),
            (1.0, [64.0, 64.0, 0.0], [0.0, 0.0, 50.0], [0.0, 0.0, 1.0], 45.0),
        ],
    );
    assert_refused(&run(&swapped, "3", &dir, &[]), "frame 1");
    assert_refused(&run(&path, "3", &dir, &["--eye", "1,2,3", "--target", "0,0,0"]), "--eye");
    assert_refused(&run(&path, "3", &dir, &["--wait"]), "--wait applies to tile stores");
    assert_refused(&run(&path, "3", &dir, &["--cache-mb", "64"]), "--cache-mb");
    assert_refused(&run(&path, "3", &dir, &["--tracer", "hybrid"]), "hybrid");
    assert_refused(&run(&path, "3", &dir, &["--node-budget", "8"]), "--node-budget");
    let stats = scratch("fly-refused-stats.txt");
    assert_refused(&run(&path, "3", &dir, &["--stats", p(&stats)]), ".json");
    assert!(!dir.exists(), "a refused flight made its folder");
}
