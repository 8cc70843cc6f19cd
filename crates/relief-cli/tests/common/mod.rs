//! Helpers shared by the end-to-end tests: running the binary, scratch files, shared data.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `relief` with `args` and collects its output.
pub fn relief(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_relief")).args(args).output().expect("relief runs")
}

/// A path named `name` in this test process's own scratch folder.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-cli-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The standard output of a run that must have succeeded.
pub fn stdout_of(out: &Output) -> String {
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "{}\n{}", text, String::from_utf8_lossy(&out.stderr));
    text
}

/// Runs `relief render` with `args` plus a scratch PNG and depth file named after `name`;
/// the run must succeed. Returns the depth image's shape and values, and the stderr.
pub fn render_depth(name: &str, args: &[&str]) -> (Vec<usize>, Vec<f32>, String) {
    let (png, depth) = (scratch(&format!("{name}.png")), scratch(&format!("{name}-depth.npy")));
    let mut all = vec!["render"];
    all.extend(args);
    all.extend(["-o", png.to_str().unwrap(), "--depth", depth.to_str().unwrap()]);
    let out = relief(&all);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{args:?}: {stderr}");
    let (shape, values) = read_f32_npy(&depth);
    (shape, values, stderr)
}

/// The depth `relief render` writes for one pixel looking straight down from `(x, y, height)`
/// at the `boxes` surface of `input`, with the extra options `extra`.
pub fn depth_straight_down(input: &Path, x: f64, y: f64, height: f64, extra: &[&str]) -> f32 {
    let (eye, target) = (format!("{x},{y},{height}"), format!("{x},{y},0"));
    let mut args = vec![input.to_str().unwrap(), "--surface", "boxes", "--eye", &eye];
    args.extend(["--target", &target, "--up", "0,1,0", "--fov", "1", "--size", "1x1"]);
    args.extend(extra);
    // Named after the view, so that tests running at the same time do not share files.
    let name = format!("straight-down-{x}-{y}-{height}-{}", extra.join("_"));
    render_depth(&name, &args).1[0]
}

/// Reads a little-endian f32 .npy written by relief: (shape, values); infinities allowed.
pub fn read_f32_npy(path: &Path) -> (Vec<usize>, Vec<f32>) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..6], b"\x93NUMPY");
    let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + header_len]).unwrap();
    assert!(header.contains("'descr': '<f4'"), "{header}");
    let shape_text = header.split("'shape': (").nth(1).unwrap().split(')').next().unwrap();
    let shape = shape_text
        .split(',')
        .filter(|s| !s.trim().is_empty())
        .map(|s| s.trim().parse().unwrap())
        .collect();
    let values = bytes[10 + header_len..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    (shape, values)
}

/// Fails with a readable message unless the command failed with code 2 and one line on stderr.
pub fn assert_refused(out: &Output, mentions: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(stderr.contains(mentions), "stderr should mention '{mentions}': {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[path = "../../../relief-io/tests/common/python_client.rs"]
mod python_client;
#[allow(unused_imports)]
pub use python_client::python;

#[path = "../../../relief-io/tests/common/clients.rs"]
pub mod clients;

#[path = "../../../relief-io/tests/common/shared_data.rs"]
mod shared_data_lookup;
#[allow(unused_imports)]
pub use shared_data_lookup::shared_data;

mod x_server;
#[allow(unused_imports)]
pub use x_server::{x_server, XServer};
