//! `relief view` end to end: refused without a display, and under a real X server (Xvfb) it
//! opens its window, renders frames progressively, plays a script (switching an MLHM scene's
//! mode and preset too), records a camera path, and saves each screenshot once, exactly
//! `relief render` of the same camera; an MLHM scene's simulation stepped in the viewer is
//! `relief simulate` rendered, and run with its rain switched it changes the picture. Where Xvfb
//! (or xdotool) is missing, the tests that need it are reported ignored, with the reason
//! (tests/common/clients.rs).

mod common;

use common::{assert_refused, clients, relief, scratch, x_server};
use relief_viewer::CameraPath;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn main() {
    clients::run(vec![
        clients::trial!(without_a_display_it_says_so_in_one_line_and_exits_2),
        clients::trial!(bad_viewer_options_are_refused_before_any_window),
        clients::trial!(a_screenshot_at_rest_is_relief_render_of_the_same_camera, Xvfb),
        clients::trial!(
            mlhm_mode_and_preset_switched_at_run_time_render_as_relief_render_does,
            Xvfb
        ),
        clients::trial!(a_scripted_flight_moves_switches_records_and_replays_as_render, Xvfb),
        clients::trial!(an_mlhm_simulation_stepped_in_the_viewer_is_relief_simulate_rendered, Xvfb),
        clients::trial!(
            an_mlhm_simulation_run_and_its_rain_switched_by_keys_changes_the_picture,
            Xvfb
        ),
        clients::trial!(
            keys_and_the_mouse_typed_into_the_window_fly_it_save_and_close_it,
            Xvfb,
            Xdotool
        ),
        clients::trial!(the_readme_and_the_viewer_docs_list_every_key_as_f1_does),
        clients::accounting_trial(
            "a_screenshot_at_rest_is_relief_render_of_the_same_camera",
            clients::Client::Xvfb,
        ),
    ]);
}

/// Runs `relief` with `args` on the X server `display`.
fn relief_on(display: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .env("DISPLAY", display)
        .output()
        .expect("relief runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A fresh scratch folder.
fn folder(name: &str) -> PathBuf {
    let dir = scratch(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The decoded RGB pixels of a PNG.
fn pixels(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// Fails unless the picture at `path` has at least `n` distinct colours (it is no blank).
fn assert_not_blank(path: &Path, n: usize) {
    let (_, _, rgb) = pixels(path);
    let mut colours: Vec<&[u8]> = rgb.chunks_exact(3).collect();
    colours.sort();
    colours.dedup();
    assert!(colours.len() >= n, "{}: only {} colours", path.display(), colours.len());
}

fn without_a_display_it_says_so_in_one_line_and_exits_2() {
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["view", "--fbm-size", "16"])
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    assert_refused(&out, "DISPLAY is not set");
    assert_eq!(stderr(&out).lines().count(), 1, "{}", stderr(&out));
    // A display that names no server.
    let out = relief_on(":7391", &["view", "--fbm-size", "16", "--size", "32x18"]);
    assert_refused(&out, "cannot connect to the X server");
}

fn bad_viewer_options_are_refused_before_any_window() {
    let dir = folder("view-refused");
    let shot = dir.join("s.jpg");
    let cases: [(Vec<&str>, &str); 5] = [
        (vec!["--frames", "2", "--screenshot", shot.to_str().unwrap()], "written as .png"),
        (vec!["--frames", "2", "--script", "5:W+Nope"], "unknown key 'Nope'"),
        (vec!["--frames", "2", "--script", "0:W"], "COUNT must be 1 to 100000"),
        (
            vec!["--output-dir", concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml")],
            "is not a folder",
        ),
        (vec!["--frame-budget", "2"], "between 5 and 1000"),
    ];
    for (extra, message) in cases {
        let mut args = vec!["view", "--fbm-size", "16"];
        args.extend(extra);
        // Refused whether or not there is a display.
        assert_refused(&relief(&args), message);
    }
    assert_refused(&relief(&["view", "--screenshot", "a.png"]), "--frames");
}

fn a_screenshot_at_rest_is_relief_render_of_the_same_camera() {
    let x = x_server().expect("Xvfb starts");
    let dir = folder("view-equals-render");
    let scene = dir.join("arches scene.mlhm");
    let run = relief(&["generate", "mlhm", "--scene", "arches", "--size", "32"]);
    assert!(!run.status.success(), "generate mlhm needs -o");
    let run =
        relief(&["generate", "mlhm", "--scene", "arches", "--size", "32", "-o", path(&scene)]);
    assert!(run.status.success(), "{}", stderr(&run));
    let camera = ["--eye", "-40,-60,90", "--target", "16,16,0", "--size", "160x90"];
    let views: [(&str, Vec<&str>); 4] = [
        ("fbm", vec!["--fbm-size", "64"]),
        ("fbm-boxes-naive", vec!["--fbm-size", "64", "--surface", "boxes", "--tracer", "naive"]),
        ("mlhm", vec![path(&scene)]),
        ("mlhm-smooth", vec![path(&scene), "--mode", "smooth", "--preset", "high"]),
    ];
    for (name, scene_args) in views {
        let (shot, picture) =
            (dir.join(format!("{name}-view.png")), dir.join(format!("{name}.png")));
        let mut view = vec!["view", "--frames", "3", "--screenshot", path(&shot)];
        view.extend(&scene_args);
        view.extend(camera);
        let out = relief_on(&x.display, &view);
        assert!(out.status.success(), "{view:?}: {}", stderr(&out));
        assert_saved_once(&out, &shot);
        let mut render = vec!["render", "--aa", "off", "-o", path(&picture)];
        render.extend(&scene_args);
        render.extend(camera);
        let out = relief(&render);
        assert!(out.status.success(), "{render:?}: {}", stderr(&out));
        assert_not_blank(&shot, 50);
        assert_eq!(pixels(&shot), pixels(&picture), "{name}: the view's frame at rest");
    }
}

fn mlhm_mode_and_preset_switched_at_run_time_render_as_relief_render_does() {
    let x = x_server().expect("Xvfb starts");
    let dir = folder("view-mlhm-switch");
    let scene = dir.join("s.mlhm");
    let run =
        relief(&["generate", "mlhm", "--scene", "combined", "--size", "64", "-o", path(&scene)]);
    assert!(run.status.success(), "{}", stderr(&run));
    let camera = ["--eye", "-50,-80,110", "--target", "32,32,0", "--size", "160x90"];
    // The scene opens in its own mode and preset (boxes, mid). Switch to smooth (M), rest
    // until the view is at full size and screenshot it (P), then switch to the max preset
    // (4) and rest again: the run ends with that view.
    let (last, script) = (dir.join("last.png"), "1:!M,8:-,1:!P,1:!4,8:-");
    let mut view = vec!["view", path(&scene), "--frames", "3", "--script", script];
    view.extend(["--output-dir", path(&dir), "--screenshot", path(&last)]);
    view.extend(camera);
    let out = relief_on(&x.display, &view);
    assert!(out.status.success(), "{view:?}: {}", stderr(&out));
    assert_eq!(saved(&out).len(), 2, "P and the run's end: {}", stderr(&out));

    let render = |name: &str, extra: &[&str]| {
        let picture = dir.join(format!("{name}.png"));
        let mut args = vec!["render", "--aa", "off", path(&scene), "-o", path(&picture)];
        args.extend(extra);
        args.extend(camera);
        let out = relief(&args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        pixels(&picture)
    };
    let opened = render("boxes-mid", &[]);
    let smooth = render("smooth-mid", &["--mode", "smooth"]);
    let max = render("smooth-max", &["--mode", "smooth", "--preset", "max"]);
    // Each switch changes the picture, so the equalities below see it made.
    assert_ne!(opened, smooth, "the mode changes the picture");
    assert_ne!(smooth, max, "the preset changes the picture");
    let shot = dir.join("relief-view-001.png");
    assert_not_blank(&shot, 50);
    assert_eq!(pixels(&shot), smooth, "after M: the smooth mode at the mid preset");
    assert_eq!(pixels(&last), max, "after M and 4: the smooth mode at the max preset");
}

fn a_scripted_flight_moves_switches_records_and_replays_as_render() {
    let x = x_server().expect("Xvfb starts");
    let dir = folder("view-script");
    let (stats, last) = (dir.join("frames.json"), dir.join("last.png"));
    // Orbit closer and round for 12 frames, start recording, fly (Tab) forward turning for
    // 8, switch tracer, surface, shadows, the sun and exposure, stop recording, screenshot.
    let script = "12:W+A,1:!R,1:!Tab,8:W+Left+Up,1:!T,1:!G,1:!H,1:!L,1:!Plus,1:!R,1:!P,3:-";
    let out = relief_on(
        &x.display,
        &[
            "view",
            "--fbm-size",
            "96",
            "--size",
            "384x216",
            "--frames",
            "30",
            "--script",
            script,
            "--frame-budget",
            "5",
            "--stats",
            path(&stats),
            "--output-dir",
            path(&dir),
            "--screenshot",
            path(&last),
        ],
    );
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("while moving:") && err.contains("at full size:"), "{err}");
    assert_eq!(saved(&out).len(), 3, "P, the path (R) and the run's end: {err}");

    // Moving frames are reduced; the last one is at full size.
    let text = std::fs::read_to_string(&stats).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let frames = json["frames"].as_array().unwrap();
    assert!(frames.len() >= 30, "{text}");
    let width = |f: &serde_json::Value| f["width"].as_u64().unwrap();
    let moving: Vec<u64> = frames.iter().filter(|f| f["moving"] == true).map(width).collect();
    assert!(moving.len() >= 20, "{text}");
    // (Which sizes fit the budget is the scheduler's unit tests' business; here, on any
    // machine, not every 384x216 frame fits 5 ms.)
    assert!(moving.iter().any(|&w| w < 384), "no reduced frame while moving: {moving:?}");
    assert!(frames.iter().all(|f| f["render_ms"].as_f64().unwrap() > 0.0), "{text}");
    assert_eq!(width(frames.last().unwrap()), 384);

    // P saved the frame shown; R wrote the path in the documented format.
    assert_not_blank(&dir.join("relief-view-001.png"), 20);
    let recorded = dir.join("relief-path-001.json");
    let json = std::fs::read_to_string(&recorded).unwrap();
    for key in ["\"format\": \"relief-camera-path\"", "\"version\": 1", "\"time_s\"", "\"fov_deg\""]
    {
        assert!(json.contains(key), "{key}: {json}");
    }
    let path_read = CameraPath::read(&recorded).unwrap();
    assert!(path_read.keys.len() >= 5, "{json}");
    assert!(path_read.keys.windows(2).all(|k| k[0].time_s < k[1].time_s));
    assert_eq!(path_read.keys[0].time_s, 0.0);

    // The last camera of the path, rendered with the tracer, surface and light the script
    // switched to, is the screenshot the run ended with.
    let key = path_read.keys.last().unwrap();
    let triple = |v: [f64; 3]| format!("{},{},{}", v[0], v[1], v[2]);
    let (eye, target, up, fov) =
        (triple(key.eye), triple(key.target), triple(key.up), key.fov_deg.to_string());
    let picture = dir.join("replayed.png");
    let out = relief(&[
        "render",
        "--aa",
        "off",
        "--fbm-size",
        "96",
        "--size",
        "384x216",
        "--eye",
        &eye,
        "--target",
        &target,
        "--up",
        &up,
        "--fov",
        &fov,
        "--tracer",
        "naive",
        "--surface",
        "boxes",
        "--no-shadows",
        "--sun",
        "330,35",
        "--exposure",
        "1.25",
        "-o",
        path(&picture),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(pixels(&last), pixels(&picture), "the replayed camera");
}

/// Generates the 32x32 rivers-rain scene in `dir` and renders it at `camera`: the scene and
/// its picture.
fn rivers_rain(dir: &Path, camera: &[&str]) -> (PathBuf, (u32, u32, Vec<u8>)) {
    let scene = dir.join("s.json");
    let generate = ["generate", "mlhm", "--scene", "rivers-rain", "--size", "32", "-o"];
    let run = relief(&[&generate[..], &[path(&scene)]].concat());
    assert!(run.status.success(), "{}", stderr(&run));
    let picture = render_picture(&scene, &dir.join("s.png"), camera);
    (scene, picture)
}

/// `relief render SCENE -o PICTURE` at `camera`, decoded.
fn render_picture(scene: &Path, picture: &Path, camera: &[&str]) -> (u32, u32, Vec<u8>) {
    let mut args = vec!["render", "--aa", "off", path(scene), "-o", path(picture)];
    args.extend(camera);
    let out = relief(&args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    pixels(picture)
}

fn an_mlhm_simulation_stepped_in_the_viewer_is_relief_simulate_rendered() {
    let x = x_server().expect("Xvfb starts");
    let dir = folder("view-simulation-steps");
    let camera = ["--eye", "-100,-150,200", "--target", "128,128,0", "--size", "160x90"];
    let (scene, opened) = rivers_rain(&dir, &camera);
    // Paused (as it opens): one step (N), rest, two more in one frame, rest.
    let (shot, script) = (dir.join("view.png"), "1:!N,2:-,1:!N+!N,3:-");
    let mut view = vec!["view", path(&scene), "--frames", "3", "--script", script];
    view.extend(["--screenshot", path(&shot)]);
    view.extend(camera);
    let out = relief_on(&x.display, &view);
    assert!(out.status.success(), "{view:?}: {}", stderr(&out));
    assert_saved_once(&out, &shot);

    let stepped = dir.join("t.json");
    let out = relief(&["simulate", path(&scene), "--steps", "3", "-o", path(&stepped)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let simulated = render_picture(&stepped, &dir.join("t.png"), &camera);
    assert_ne!(opened, simulated, "three steps change the picture");
    assert_not_blank(&shot, 50);
    assert_eq!(pixels(&shot), simulated, "3 steps in the viewer, at rest");
}

fn an_mlhm_simulation_run_and_its_rain_switched_by_keys_changes_the_picture() {
    let x = x_server().expect("Xvfb starts");
    let dir = folder("view-simulation-run");
    let camera = ["--eye", "-100,-150,200", "--target", "128,128,0", "--size", "160x90"];
    let (scene, opened) = rivers_rain(&dir, &camera);
    // Run (V) for 6 frames, rain off (B) for 6, rain on and pause (B, V), one step (N), rest.
    let (shot, stats) = (dir.join("view.png"), dir.join("frames.json"));
    let script = "1:!V,6:-,1:!B,6:-,1:!B+!V,2:-,1:!N,3:-";
    let mut view = vec!["view", path(&scene), "--frames", "3", "--script", script];
    view.extend(["--screenshot", path(&shot), "--stats", path(&stats)]);
    view.extend(camera);
    let out = relief_on(&x.display, &view);
    assert!(out.status.success(), "{view:?}: {}", stderr(&out));
    assert_saved_once(&out, &shot);
    assert_not_blank(&shot, 50);
    assert_ne!(pixels(&shot), opened, "the simulation ran");
    // Running, the frames are the moving ones; paused, the view refines to full size.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let frames = json["frames"].as_array().unwrap();
    assert!(frames.iter().filter(|f| f["moving"] == true).count() >= 12, "{json}");
    assert_eq!(frames.last().unwrap()["width"], 160, "{json}");
}

/// The lines of the run's stderr that say it saved a file.
fn saved(out: &Output) -> Vec<String> {
    stderr(out).lines().filter(|l| l.starts_with("saved ")).map(String::from).collect()
}

/// Fails unless the run's stderr says exactly once that it saved a file, and that file is
/// `shot`: a `--frames` run writes its screenshot once.
fn assert_saved_once(out: &Output, shot: &Path) {
    let saved = saved(out);
    assert_eq!(saved.len(), 1, "{}", stderr(out));
    assert!(saved[0].starts_with(&format!("saved {}", shot.display())), "{}", stderr(out));
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `xdotool` with `args` on `display`; whether it could (it is installed).
fn xdotool(display: &str, args: &[&str]) -> bool {
    Command::new("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Gives the keyboard to the viewer's window on `display` once it is mapped. The window
/// exists a moment before it is mapped, and focusing it then fails, so this tries again for
/// up to 30 s; if it never succeeds the viewer is killed and its stderr shown.
fn focus_viewer_window(display: &str, viewer: &mut std::process::Child) {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
    let visible = ["search", "--sync", "--onlyvisible", "--name", "relief view"];
    loop {
        let focus = [&visible[..], &["windowfocus", "--sync"]].concat();
        if xdotool(display, &focus) {
            return;
        }
        if std::time::Instant::now() > deadline || viewer.try_wait().unwrap().is_some() {
            let _ = viewer.kill();
            let mut err = String::new();
            if let Some(mut pipe) = viewer.stderr.take() {
                let _ = std::io::Read::read_to_string(&mut pipe, &mut err);
            }
            panic!("the viewer's window could not be given the keyboard in 30 s:\n{err}");
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
}

fn keys_and_the_mouse_typed_into_the_window_fly_it_save_and_close_it() {
    let x = x_server().expect("Xvfb starts");
    assert!(xdotool(&x.display, &["version"]), "xdotool runs");
    let dir = folder("view-typed");
    let stats = dir.join("frames.json");
    let mut viewer = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["view", "--fbm-size", "128", "--size", "320x180", "--output-dir", path(&dir)])
        .args(["--stats", path(&stats)])
        .env("DISPLAY", &x.display)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for the window, give it the keyboard, then type as a user does: fly forward,
    // drag the view, screenshot, quit.
    let d = x.display.as_str();
    focus_viewer_window(d, &mut viewer);
    let pause = |ms| std::thread::sleep(std::time::Duration::from_millis(ms));
    pause(300);
    assert!(xdotool(d, &["keydown", "w"]));
    pause(600);
    assert!(xdotool(d, &["keyup", "w"]));
    assert!(xdotool(d, &["mousemove", "100", "100", "mousedown", "1"]));
    for _ in 0..10 {
        assert!(xdotool(d, &["mousemove_relative", "6", "0"]));
        pause(20);
    }
    assert!(xdotool(d, &["mouseup", "1"]));
    pause(600);
    assert!(xdotool(d, &["key", "p"]));
    pause(300);
    assert!(xdotool(d, &["key", "Escape"]));
    let out = viewer.wait_with_output().unwrap();
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("while moving:"), "{err}");
    assert_not_blank(&dir.join("relief-view-001.png"), 50);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert!(json["frames"].as_array().unwrap().iter().any(|f| f["moving"] == true), "{json}");
}

fn the_readme_and_the_viewer_docs_list_every_key_as_f1_does() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for doc in ["README.md", "docs/viewer.md"] {
        let text = std::fs::read_to_string(root.join(doc)).unwrap();
        for (keys, what) in relief_viewer::KEY_HELP {
            let row = format!("| {keys} | {what} |");
            assert!(text.contains(&row), "{doc} lacks the row {row}");
        }
    }
}
