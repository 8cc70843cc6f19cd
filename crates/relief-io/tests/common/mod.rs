//! Shared test support: a scratch directory and the shared data.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// A fresh scratch directory under the system's temporary directory, removed when dropped.
pub struct TestDir(PathBuf);

impl TestDir {
    /// Creates `relief-io-test-<name>-<pid>` afresh.
    pub fn new(name: &str) -> Self {
        let path =
            std::env::temp_dir().join(format!("relief-io-test-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap();
        TestDir(path)
    }

    /// The directory.
    pub fn path(&self) -> &Path {
        &self.0
    }

    /// The path of `name` in the directory.
    pub fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// Writes `bytes` to `name` in the directory and returns its path.
    pub fn file(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let path = self.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for TestDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[path = "shared_data.rs"]
mod shared_data_lookup;
#[allow(unused_imports)]
pub use shared_data_lookup::shared_data;

/// Runs a Python snippet with the real client of a format (e.g. `rasterio`, GDAL's Python
/// binding) and returns what it printed; `None` (after saying so) when python3 cannot import
/// `module` and RELIEF_REQUIRE_CLIENTS is not 1 (.ci/run sets it and installs the clients).
/// A script that fails fails the test, with its error output.
pub fn python(module: &str, script: &str) -> Option<String> {
    use std::process::Command;
    let probe = Command::new("python3").args(["-c", &format!("import {module}")]).output();
    if !probe.is_ok_and(|o| o.status.success()) {
        assert!(
            std::env::var("RELIEF_REQUIRE_CLIENTS").as_deref() != Ok("1"),
            "python3 with {module} is required (RELIEF_REQUIRE_CLIENTS=1); .ci/run installs it"
        );
        println!("skipped: python3 cannot import {module}");
        return None;
    }
    let out = Command::new("python3").args(["-c", script]).output().unwrap();
    assert!(out.status.success(), "{script}\n{}", String::from_utf8_lossy(&out.stderr));
    Some(String::from_utf8_lossy(&out.stdout).trim().to_string())
}
