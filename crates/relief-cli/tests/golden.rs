//! Small golden images of the default pipeline, of an MLHM scene with water at the mid preset
//! as boxes and as a smooth surface, and of the real MLHM scene smoothed (its side walls show
//! no box edges), compared with a tolerance.
//!
//! Regenerate after an intended change of the pictures with:
//! `RELIEF_BLESS=1 cargo test -p relief-cli --test golden`
//! In a bare clone (no ../shared) a test that reads the shared data is reported ignored.

mod common;

use common::{clients, shared_data};
use std::path::Path;
use std::process::Command;

fn main() {
    clients::run(vec![
        clients::trial!(default_pipeline_matches_the_golden_image),
        clients::trial!(mlhm_scene_with_water_at_the_mid_preset_matches_the_golden_image),
        clients::trial!(mlhm_scene_smooth_at_the_mid_preset_matches_the_golden_image),
        clients::trial_reading!(
            the_real_scene_smoothed_matches_the_golden_image,
            "data/ngwm24-scene/scene.json"
        ),
    ]);
}

fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// Runs `relief` with `args` plus an output PNG and compares the picture with `golden` (a path
/// under the crate), or replaces `golden` with it when `RELIEF_BLESS` is set.
fn assert_matches_golden(args: &[&str], golden: &str) {
    let name = Path::new(golden).file_stem().unwrap().to_str().unwrap();
    let out_path =
        std::env::temp_dir().join(format!("relief-golden-{name}-{}.png", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .arg("-o")
        .arg(&out_path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let golden_path = Path::new(env!("CARGO_MANIFEST_DIR")).join(golden);
    if std::env::var_os("RELIEF_BLESS").is_some() {
        std::fs::copy(&out_path, &golden_path).unwrap();
        eprintln!("blessed {}", golden_path.display());
        return;
    }
    let (w, h, got) = decode(&out_path);
    let (gw, gh, want) = decode(&golden_path);
    assert_eq!((w, h), (gw, gh));
    let diffs: Vec<u32> = got.iter().zip(&want).map(|(a, b)| a.abs_diff(*b) as u32).collect();
    let mean = diffs.iter().sum::<u32>() as f64 / diffs.len() as f64;
    let max = diffs.iter().copied().max().unwrap_or(0);
    assert!(
        mean <= 0.5 && max <= 16,
        "image differs from {golden}: mean {mean:.2}, max {max} levels (RELIEF_BLESS=1 to regenerate)"
    );
}

fn default_pipeline_matches_the_golden_image() {
    let args = ["render", "--fbm-size", "64", "--seed", "7", "--size", "96x64"];
    assert_matches_golden(&args, "tests/golden/fbm-96x64.png");
}

fn mlhm_scene_with_water_at_the_mid_preset_matches_the_golden_image() {
    let scene = combined_scene("boxes");
    let args = ["render", &scene, "--preset", "mid", "--size", "96x64"];
    assert_matches_golden(&args, "tests/golden/mlhm-combined-mid-96x64.png");
}

/// The `combined` scene at 64 x 64 cells, written once per test.
fn combined_scene(name: &str) -> String {
    let scene =
        std::env::temp_dir().join(format!("relief-golden-{name}-{}.json", std::process::id()));
    let scene = scene.to_str().unwrap().to_string();
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["generate", "mlhm", "--scene", "combined", "--size", "64", "-o", &scene])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    scene
}

fn mlhm_scene_smooth_at_the_mid_preset_matches_the_golden_image() {
    let scene = combined_scene("smooth");
    let args = ["render", &scene, "--mode", "smooth", "--preset", "mid", "--size", "96x64"];
    assert_matches_golden(&args, "tests/golden/mlhm-combined-smooth-mid-96x64.png");
}

fn the_real_scene_smoothed_matches_the_golden_image() {
    let Some(json) = shared_data("data/ngwm24-scene/scene.json") else { return };
    // Low over the scene's north-east corner, looking at the side walls of its terraces.
    let args = [
        "render",
        json.to_str().unwrap(),
        "--mode",
        "smooth",
        "--preset",
        "high",
        "--eye",
        "230,250,70",
        "--target",
        "120,120,20",
        "--size",
        "128x72",
    ];
    assert_matches_golden(&args, "tests/golden/ngwm24-smooth-high-128x72.png");
}
