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

/// `relative` (say `data/jacksboro_fault_dem.npy`) in the project's shared folder, ../shared
/// beside the repository; `None`, with the reason printed, where that folder is absent (a bare
/// clone). Where the folder is present, or `RELIEF_REQUIRE_SHARED_DATA=1`, a missing file
/// fails the test instead: a test must not skip silently where its data should be.
pub fn shared_data(relative: &str) -> Option<PathBuf> {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    let path = shared.join(relative);
    if path.is_file() {
        return Some(path);
    }
    let required = std::env::var("RELIEF_REQUIRE_SHARED_DATA").is_ok_and(|v| v == "1");
    assert!(
        !shared.is_dir() && !required,
        "{} is missing, though ../shared is present or RELIEF_REQUIRE_SHARED_DATA=1",
        path.display()
    );
    println!("skipped: {} is absent (../shared is not beside the repository)", path.display());
    None
}
