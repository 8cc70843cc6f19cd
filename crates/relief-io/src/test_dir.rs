//! A scratch directory for tests, removed when dropped.

use std::path::{Path, PathBuf};

/// A fresh, empty directory under the system's temporary directory.
pub(crate) struct TestDir(PathBuf);

impl TestDir {
    /// Creates `relief-io-<name>-<pid>` afresh.
    pub(crate) fn new(name: &str) -> Self {
        let path = std::env::temp_dir().join(format!("relief-io-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap();
        TestDir(path)
    }

    /// The directory.
    pub(crate) fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TestDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
