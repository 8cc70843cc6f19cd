//! The project's shared data for tests, one helper for every crate's tests (relief-cli's
//! include this file too).

use std::path::{Path, PathBuf};

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
