//! `relief view --frames N` without a display (issue 35): the scripted frames are drawn
//! headless, with no window and no X server (DISPLAY is removed for every run here), for any
//! input `relief render` takes, a tile store included; its --output-dir is made; and the
//! pinhole-only viewer's help shows no --ortho.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh folder for the test `name`.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-headless-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `relief` with `args` in `dir` without a display: exit code and stderr.
fn relief(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_relief"));
    command.current_dir(dir).args(args).env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY");
    let out: Output = command.output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// A small .npy DEM in `dir`.
fn dem(dir: &Path) -> &'static str {
    let values: Vec<f32> = (0..32 * 32).map(|i| ((i % 32) as f32 * 0.3).sin() * 4.0).collect();
    relief_io::write_npy_f32(&dir.join("dem.npy"), &[32, 32], &values).unwrap();
    "dem.npy"
}

/// The width and height of the PNG at `path`.
fn png_size(path: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let info = decoder.read_info().unwrap();
    (info.info().width, info.info().height)
}

#[test]
fn frames_are_drawn_headless_without_a_display() {
    let dir = folder("frames");
    let dem = dem(&dir);
    let args = ["view", dem, "--size", "48x32", "--frames", "3", "--screenshot", "v.png"];
    let extra = ["--script", "2:W", "--output-dir", "shots/new", "--stats", "frames.json"];
    let (code, stderr) = relief(&dir, &[&args[..], &extra[..]].concat());
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains("headless"), "{stderr}");
    assert_eq!(png_size(&dir.join("v.png")), (48, 32));
    assert!(dir.join("shots/new").is_dir(), "--output-dir is made");
    let stats = std::fs::read_to_string(dir.join("frames.json")).unwrap();
    assert!(stats.matches("render_ms").count() >= 3, "{stats}");
}

/// The RGB bytes of the PNG at `path`.
fn png_pixels(path: &Path) -> Vec<u8> {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    pixels.truncate(info.buffer_size());
    pixels
}

#[test]
fn a_headless_view_at_rest_is_relief_render_of_the_same_camera() {
    let dir = folder("equals-render");
    let dem = dem(&dir);
    let args = ["view", dem, "--size", "64x36", "--frames", "2", "--screenshot", "v.png"];
    let (code, stderr) = relief(&dir, &args);
    assert_eq!(code, Some(0), "{stderr}");
    let (code, stderr) =
        relief(&dir, &["render", dem, "--size", "64x36", "--aa", "off", "-o", "r.png"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(png_pixels(&dir.join("v.png")) == png_pixels(&dir.join("r.png")));
}

#[test]
fn an_interactive_view_still_needs_a_display() {
    let dir = folder("interactive");
    let dem = dem(&dir);
    let (code, stderr) = relief(&dir, &["view", dem, "--size", "48x32"]);
    assert_eq!(code, Some(2));
    assert!(stderr.contains("DISPLAY"), "{stderr}");
}

#[test]
fn a_tile_store_is_viewed() {
    let dir = folder("store");
    let dem = dem(&dir);
    let (code, stderr) = relief(&dir, &["tile", dem, "-o", "dem.store", "--tile", "16"]);
    assert_eq!(code, Some(0), "{stderr}");
    let args = ["view", "dem.store", "--size", "40x24", "--frames", "1", "--screenshot", "s.png"];
    let (code, stderr) = relief(&dir, &[&args[..], &["--cache-mb", "16"][..]].concat());
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains("32x32 tile store"), "{stderr}");
    assert_eq!(png_size(&dir.join("s.png")), (40, 24));
    // At rest, the store's frame is relief render's picture of it.
    let render = [
        "render",
        "dem.store",
        "--size",
        "40x24",
        "--cache-mb",
        "16",
        "--aa",
        "off",
        "-o",
        "r.png",
    ];
    let (code, stderr) = relief(&dir, &render);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(png_pixels(&dir.join("s.png")) == png_pixels(&dir.join("r.png")));
    // The tile-store options do nothing for other inputs.
    let (code, stderr) = relief(&dir, &["view", dem, "--frames", "1", "--cache-mb", "16"]);
    assert_eq!(code, Some(2));
    assert!(stderr.contains("--cache-mb applies to tile stores"), "{stderr}");
}

#[test]
fn the_viewer_shows_and_takes_no_orthographic_camera() {
    let dir = folder("ortho");
    let out = Command::new(env!("CARGO_BIN_EXE_relief")).args(["view", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && help.contains("--frames"), "{help}");
    assert!(!help.contains("--ortho"), "{help}");
    let dem = dem(&dir);
    for extra in [&["--ortho"][..], &["--ortho", "--ortho-height", "10"][..]] {
        let (code, stderr) = relief(&dir, &[&["view", dem, "--frames", "1"][..], extra].concat());
        assert_eq!(code, Some(2), "{stderr}");
        assert!(stderr.contains("--ortho"), "{stderr}");
    }
}
