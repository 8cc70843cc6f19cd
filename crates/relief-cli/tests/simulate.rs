//! `relief simulate` end to end: a generated RiversRain scene simulated, written with its
//! state and step count, continued by a second run exactly as one unbroken run; checkpoints
//! and the last valid state a failed run leaves; and the real scene the reference simulator
//! saved (../shared/data/ngwm24-scene) simulated further, past the step that once broke it.
//! In a bare clone (no ../shared) a test that reads the shared data is reported ignored.

mod common;

use common::{clients, relief, scratch, shared_data};
use relief_io::{read_mlhm_scene, ReadOptions};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

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
        clients::trial!(
            checkpoints_replace_each_other_and_a_failed_step_leaves_the_last_valid_state
        ),
        clients::trial!(a_finished_run_leaves_its_output_and_no_checkpoint),
        clients::trial!(a_killed_run_keeps_its_last_checkpoint),
        clients::trial!(a_frame_that_cannot_be_written_leaves_the_state_it_was_of),
        clients::trial_reading!(
            the_reference_scene_runs_past_the_step_that_broke_it,
            "data/ngwm24-scene/scene.json"
        ),
        clients::trial_reading!(
            the_reference_scene_is_valid_after_every_stage_and_the_same_with_1_and_2_threads,
            "data/ngwm24-scene/scene.json"
        ),
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
    // 7 steps every 3: frames at steps 3 and 6, one line each with every stage's time,
    // numbered from 0 as flythrough's.
    for (frame, step) in [(0, 3), (1, 6)] {
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
    assert!(!dir.join("new/frame-00002.png").exists());

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
    let cases: [(&[&str], &str); 8] = [
        (&["--frames", p(&dir)], "--frames needs --render-every"),
        (&["--render-every", "2"], "--render-every needs --frames"),
        (&["--render-every", "0", "--frames", p(&dir)], "between 1 and"),
        (&["--render-every", "1", "--frames", p(&not_creatable)], "cannot create the folder"),
        (&["--preset", "low"], "--preset applies to --frames only"),
        (&["--size", "64x36"], "--size applies to --frames only"),
        (&["--checkpoint", "0"], "--checkpoint"),
        (&["--checkpoint", "-3"], "--checkpoint"),
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

/// A generated 32 x 32 RiversRain scene named `name`.
fn rivers(name: &str) -> PathBuf {
    let input = scratch(name);
    run(&["generate", "mlhm", "--scene", "rivers-rain", "--size", "32", "-o", p(&input)]);
    input
}

/// The scene `input` simulated `steps` steps in one plain run, written as `name`.
fn plain_run(input: &Path, steps: u64, name: &str) -> relief_io::MlhmScene {
    let out = scratch(name);
    run(&["simulate", p(input), "--steps", &steps.to_string(), "-o", p(&out)]);
    scene(&out)
}

/// Asserts that the scene files `a` and `b` hold the same terrain, state and step count.
fn assert_same_state(a: &relief_io::MlhmScene, b: &relief_io::MlhmScene, what: &str) {
    let step = "Simulation/CurrentSimulationStep";
    assert_eq!(a.settings[step], b.settings[step], "{what}");
    assert!(a.mlhm == b.mlhm, "{what}: the terrains differ");
    assert!(a.simulation == b.simulation, "{what}: the simulation planes differ");
}

/// The `NAME.step-N.json` files in `dir` whose name starts with `stem`, by step.
fn checkpoints(dir: &Path, stem: &str) -> Vec<(u64, PathBuf)> {
    let prefix = format!("{stem}.step-");
    let mut found: Vec<(u64, PathBuf)> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| {
            let path = e.ok()?.path();
            let name = path.file_name()?.to_str()?.to_owned();
            let step = name.strip_prefix(&prefix)?.strip_suffix(".json")?.parse().ok()?;
            Some((step, path))
        })
        .collect();
    found.sort();
    found
}

fn checkpoints_replace_each_other_and_a_failed_step_leaves_the_last_valid_state() {
    let input = rivers("sim-ckpt-in.json");
    let output = scratch("sim-ckpt.json");
    let dir = output.parent().unwrap();
    // Step 8 reports a broken terrain (a failure injected for this test): the state before
    // it is replayed from the checkpoint at step 6 and written beside the output.
    let out = relief(&[
        "simulate",
        p(&input),
        "--steps",
        "10",
        "--checkpoint",
        "3",
        "--test-fail-at-step",
        "8",
        "-o",
        p(&output),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
    let last = dir.join("sim-ckpt.step-8.json");
    assert!(stderr.contains("simulation step 8 broke the terrain"), "{stderr}");
    assert!(stderr.contains(&format!("at step 8, is saved as {}", last.display())), "{stderr}");
    assert!(!output.exists(), "a failed run writes no output");
    // The checkpoint at step 3 gave way to the one at step 6.
    let saved: Vec<u64> = checkpoints(dir, "sim-ckpt").into_iter().map(|(s, _)| s).collect();
    assert_eq!(saved, [6, 8]);
    assert!(!dir.join("sim-ckpt.step-3.dat").exists());
    assert_same_state(&scene(&last), &plain_run(&input, 8, "sim-ckpt-8.json"), "step 8");
    let sixth = scene(&dir.join("sim-ckpt.step-6.json"));
    assert_same_state(&sixth, &plain_run(&input, 6, "sim-ckpt-6.json"), "checkpoint 6");
}

fn a_finished_run_leaves_its_output_and_no_checkpoint() {
    let input = rivers("sim-done-in.json");
    let output = scratch("sim-done.mlhm");
    let message =
        run(&["simulate", p(&input), "--steps", "7", "--checkpoint", "2", "-o", p(&output)]);
    assert!(message.contains("(now at step 7)"), "{message}");
    assert!(output.exists());
    assert!(checkpoints(output.parent().unwrap(), "sim-done").is_empty());
}

fn a_killed_run_keeps_its_last_checkpoint() {
    let input = rivers("sim-kill-in.json");
    let output = scratch("sim-kill.json");
    let dir = output.parent().unwrap().to_path_buf();
    let mut child = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["simulate", p(&input), "--steps", "10000000", "--checkpoint", "25", "-o"])
        .arg(&output)
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    // Until the second checkpoint (step 50) replaced the first.
    let newest = || checkpoints(&dir, "sim-kill").pop().map_or(0, |(step, _)| step);
    while newest() < 50 && started.elapsed() < Duration::from_secs(300) {
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    // The newest checkpoint is whole (its .dat is written before its .json appears).
    let (step, path) = checkpoints(&dir, "sim-kill").pop().expect("a checkpoint before the kill");
    assert!(step >= 50 && step.is_multiple_of(25), "step {step}");
    let kept = scene(&path);
    kept.mlhm.validate().unwrap();
    assert_same_state(&kept, &plain_run(&input, step, "sim-kill-plain.json"), "the checkpoint");
    assert!(!output.exists());
}

fn a_frame_that_cannot_be_written_leaves_the_state_it_was_of() {
    let input = rivers("sim-frame-fail-in.json");
    let dir = scratch("sim-frame-fail");
    let _ = std::fs::remove_dir_all(&dir);
    // The second frame's file is taken by a folder: the run fails after step 6.
    std::fs::create_dir_all(dir.join("frame-00001.png")).unwrap();
    let output = scratch("sim-frame-fail.mlhm");
    let out = relief(&[
        "simulate",
        p(&input),
        "--steps",
        "9",
        "--render-every",
        "3",
        "--frames",
        p(&dir),
        "--size",
        "32x18",
        "-o",
        p(&output),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    // The state goes to a .json scene (which holds it) whatever the output's format.
    let last = output.with_file_name("sim-frame-fail.step-6.json");
    assert!(stderr.contains("frame-00001.png"), "{stderr}");
    assert!(stderr.contains(&format!("at step 6, is saved as {}", last.display())), "{stderr}");
    assert!(!output.exists());
    assert_same_state(&scene(&last), &plain_run(&input, 6, "sim-frame-fail-6.json"), "step 6");
}

/// The real scene simulated `steps` steps with `threads` threads (and the extra options),
/// written as `name`; returns the output's path.
fn reference_run(input: &Path, steps: &str, threads: &str, name: &str, extra: &[&str]) -> PathBuf {
    let output = scratch(name);
    let mut args = vec!["simulate", p(input), "--steps", steps, "-o", p(&output)];
    args.extend_from_slice(extra);
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(&args)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{args:?} with {threads} threads: {stderr}");
    output
}

fn the_reference_scene_runs_past_the_step_that_broke_it() {
    let Some(input) = shared_data("data/ngwm24-scene/scene.json") else { return };
    // From its step 1484, with the scene's rain: step 3723 once split a column at another
    // column's window (cell (86, 239)) and stopped the run at its end (the terrain checked
    // only then). Every step is now checked; the run goes on.
    let output = reference_run(&input, "2241", "2", "ngwm24-3725.json", &[]);
    let out = scene(&output);
    out.mlhm.validate().unwrap();
    assert_eq!(out.settings["Simulation/CurrentSimulationStep"], 3725);
}

fn the_reference_scene_is_valid_after_every_stage_and_the_same_with_1_and_2_threads() {
    let Some(input) = shared_data("data/ngwm24-scene/scene.json") else { return };
    // Every stage of every step checked, with rain, 150 steps.
    let extra = ["--check-stages", "--rain", "0.07"];
    let one = reference_run(&input, "150", "1", "ngwm24-150-1.json", &extra);
    let two = reference_run(&input, "150", "2", "ngwm24-150-2.json", &extra);
    let bytes = |path: &Path| std::fs::read(path.with_extension("dat")).unwrap();
    assert!(bytes(&one) == bytes(&two), "1 and 2 threads give different states");
    let out = scene(&one);
    assert_same_state(&out, &scene(&two), "1 and 2 threads");
    out.mlhm.validate().unwrap();
    assert_eq!(out.settings["Simulation/CurrentSimulationStep"], 1634);
}
