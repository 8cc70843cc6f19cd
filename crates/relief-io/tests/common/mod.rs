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

#[path = "python_client.rs"]
mod python_client;
#[allow(unused_imports)]
pub use python_client::python;

pub mod clients;
