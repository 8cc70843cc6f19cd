//! Helpers shared by the end-to-end tests: running the binary and scratch files.
#![allow(dead_code)]

use std::path::PathBuf;
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
