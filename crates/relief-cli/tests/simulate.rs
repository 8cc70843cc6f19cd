//! `relief simulate` end to end: a generated RiversRain scene simulated, written with its
//! state and step count, continued by a second run exactly as one unbroken run, and the real
//! scene the reference simulator saved (../shared/data/ngwm24-scene) simulated further.
//! In a bare clone (no ../shared) a test that reads the shared data is reported ignored.

mod common;

use common::{clients, relief, scratch, shared_data};
use relief_io::{read_mlhm_scene, ReadOptions};
use std::path::Path;

fn main() {
    clients::run(vec![
        clients::trial!(a_generated_scene_simulates_and_continues_exactly),
        clients::trial!(a_truncated_dat_is_refused),
        clients::trial_reading!(
            the_reference_scene_simulates_further,
            "data/ngwm24-scene/scene.json"
        ),
        clients::trial!(frames_are_rendered_every_k_steps_with_their_times),
        clients::trial!(frame_options_out_of_place_are_refused),
    ]);
}

fn run(args: &[&str]) -> String {
    let out = relief(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {stderr}");
    stderr
}

fn scene(path: &Path) -> relief_io::MlhmScene {
    read_mlhm_scene(path, &ReadOptions::default()).unwrap()
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn a_generated_scene_simulates_and_continues_exactly() {
    let input = scratch("sim-rivers.json");
    run(&["generate", "mlhm", "--scene", "rivers-rain", "--size", "32", "-o", p(&input)]);
    let (whole, half, resumed, stats) = (
        scratch("sim-20.json"),
        scratch("sim-10.json"),
        scratch("sim-10-10.json"),
        scratch("sim.json.stats.json"),
    );
    let message = run(&[
        "simulate",
        p(&input),
        "--steps",
        "20",
        "--seed",
        "7",
        "-o",
        p(&whole),
        "--stats",
        p(&stats),
    ]);
    assert!(message.contains("after 20 steps (now at step 20)"), "{message}");
    run(&["simulate", p(&input), "--steps", "10", "--seed", "7", "-o", p(&half)]);
    run(&["simulate", p(&half), "--steps", "10", "--seed", "7", "-o", p(&resumed)]);

    let (a, b) = (scene(&whole), scene(&resumed));
    a.mlhm.validate().unwrap();
    assert_eq!(a.settings["Simulation/CurrentSimulationStep"], 20);
    assert_eq!(b.settings["Simulation/CurrentSimulationStep"], 20);
    assert_eq!(a.mlhm, b.mlhm, "10 + 10 steps equal 20");
    assert_eq!(a.simulation, b.simulation);
    let state = a.simulation.as_ref().unwrap();
    assert!(state.sediment.iter().any(|&s| s > 0.0), "water carries sediment");
    assert_ne!(a.mlhm, scene(&input).mlhm);

    let stats: serde_json::Value = serde_json::from_slice(&std::fs::read(&stats).unwrap()).unwrap();
    assert_eq!(stats["steps"], 20);
    assert!(stats["median_step_ms"].as_f64().unwrap() > 0.0);
    for key in [
        "rain_m3",
        "evaporation_m3",
        "split_sand_m3",
        "split_bedrock_m3",
        "collapse_damage_m3",
        "damage_recovery_m3",
        "horizontal_erosion_sand_m3",
    ] {
        assert!(stats[key].as_f64().is_some(), "{key} in {stats}");
    }
    assert!(stats["rain_m3"].as_f64().unwrap() > 0.0);
}

fn a_truncated_dat_is_refused() {
    let input = scratch("sim-cut.json");
    run(&["generate", "mlhm", "--scene", "arches", "--size", "16", "-o", p(&input)]);
    let dat = input.with_extension("dat");
    let bytes = std::fs::read(&dat).unwrap();
    std::fs::write(&dat, &bytes[..bytes.len() / 2]).unwrap();
    let out =
        relief(&["simulate", p(&input), "--steps", "1", "-o", p(&scratch("sim-cut-out.json"))]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!scratch("sim-cut-out.json").exists());
}

fn the_reference_scene_simulates_further() {
    let Some(input) = shared_data("data/ngwm24-scene/scene.json") else { return };
    let output = scratch("ngwm24-simulated.json");
    let stats = scratch("ngwm24-stats.json");
    let message =
        run(&["simulate", p(&input), "--steps", "4", "-o", p(&output), "--stats", p(&stats)]);
    assert!(message.contains("(now at step 1488)"), "{message}");
    let out = scene(&output);
    out.mlhm.validate().unwrap();
    assert_eq!((out.mlhm.width(), out.mlhm.height()), (256, 256));
    assert!(out.simulation.is_some());
    assert_eq!(out.settings["Simulation/CurrentSimulationStep"], 1488);
    // The scene's own settings are kept (its evaporation is 0.01 m/s).
    assert!((out.settings["Simulation/Evaporation"].as_f64().unwrap() - 0.01).abs() < 1e-6);
}

fn frames_are_rendered_every_k_steps_with_their_times() {
    let input = scratch("sim-frames-in.json");
    run(&["generate", "mlhm", "--scene", "rivers-rain", "--size", "24", "-o", p(&input)]);
    let dir = scratch("sim-frames");
    let _ = std::fs::remove_dir_all(&dir);
    let stats = scratch("sim-frames-stats.json");
    let message = run(&[
        "simulate",
        p(&input),
        "--steps",
        "7",
        "--render-every",
        "3",
        "--frames",
        p(&dir.join("new")),
        "--size",
        "64x36",
        "--preset",
        "mid",
        "--view",
        "30,40",
        "-o",
        p(&scratch("sim-frames-out.mlhm")),
        "--stats",
        p(&stats),
    ]);
    // 7 steps every 3: frames at steps 3 and 6, one line each with every stage's time.
    for (frame, step) in [(1, 3), (2, 6)] {
        let line = message
            .lines()
            .find(|l| l.starts_with(&format!("frame {frame} (step {step}): simulate ")))
            .unwrap_or_else(|| panic!("frame {frame}: {message}"));
        for stage in ["ms (3 steps), convert ", " ms, rebuild ", " ms, render ", " ms, write "] {
            assert!(line.contains(stage), "{line}");
        }
        let png = dir.join("new").join(format!("frame-{frame:05}.png"));
        let image = relief_io::read_png_rgb(&png).unwrap();
        assert_eq!((image.width, image.height), (64, 36));
        let first = image.pixels[0];
        assert!(image.pixels.iter().any(|&px| px != first), "{}: blank", png.display());
    }
    assert!(!dir.join("new/frame-00003.png").exists());

    let stats: serde_json::Value = serde_json::from_slice(&std::fs::read(&stats).unwrap()).unwrap();
    assert_eq!(stats["steps"], 7);
    assert_eq!(stats["frames"], 2);
    assert_eq!(stats["preset"], "mid");
    for key in ["median_step_ms", "rebuild_ms", "render_ms", "convert_ms", "write_ms"] {
        assert!(stats[key].as_f64().is_some_and(|v| v >= 0.0), "{key} in {stats}");
    }
    for key in ["rebuild_ms_each", "render_ms_each", "frame_simulate_ms_each"] {
        assert_eq!(stats[key].as_array().map(Vec::len), Some(2), "{key} in {stats}");
    }
}

fn frame_options_out_of_place_are_refused() {
    let input = scratch("sim-frames-bad.json");
    run(&["generate", "mlhm", "--scene", "arches", "--size", "16", "-o", p(&input)]);
    let out = scratch("sim-frames-bad-out.mlhm");
    let file = scratch("sim-frames-a-file");
    std::fs::write(&file, b"not a folder").unwrap();
    let dir = scratch("sim-frames-bad");
    let not_creatable = file.join("frames");
    let cases: [(&[&str], &str); 6] = [
        (&["--frames", p(&dir)], "--frames needs --render-every"),
        (&["--render-every", "2"], "--render-every needs --frames"),
        (&["--render-every", "0", "--frames", p(&dir)], "between 1 and"),
        (&["--render-every", "1", "--frames", p(&not_creatable)], "cannot create the folder"),
        (&["--preset", "low"], "--preset applies to --frames only"),
        (&["--size", "64x36"], "--size applies to --frames only"),
    ];
    for (extra, text) in cases {
        let mut args = vec!["simulate", p(&input), "--steps", "2", "-o", p(&out)];
        args.extend_from_slice(extra);
        let result = relief(&args);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{extra:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{extra:?}: one line: {stderr}");
        assert!(stderr.contains(text), "{extra:?}: {stderr}");
        assert!(!out.exists(), "{extra:?} wrote the output");
    }
}
