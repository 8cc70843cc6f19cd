//! Writing an exported file atomically: into a temporary file beside it, renamed into place.

use crate::MeshError;
use std::fs::OpenOptions;
use std::io::{Error, ErrorKind, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporary files made by concurrent writes in one process.
static NEXT_TEMP: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to `path`: into a new temporary file in the same directory, synced to disk,
/// then renamed over `path`. On any error the temporary file is removed and `path` is left as
/// it was.
pub(super) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), MeshError> {
    let temp = temp_path(path)?;
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(|e| MeshError::io(path, &e))?;
    let result = (&file)
        .write_all(bytes)
        .and_then(|()| file.sync_all())
        .and_then(|()| {
            drop(file);
            std::fs::rename(&temp, path)
        })
        .map_err(|e| MeshError::io(path, &e));
    if result.is_err() {
        // Best effort: the original error matters more than a failed clean-up.
        let _ = std::fs::remove_file(&temp);
    }
    result
}

/// A fresh hidden name beside `path`: `.<name>.<pid>.<n>.tmp`.
fn temp_path(path: &Path) -> Result<PathBuf, MeshError> {
    let name = path.file_name().ok_or_else(|| {
        MeshError::io(path, &Error::new(ErrorKind::InvalidInput, "path does not name a file"))
    })?;
    let n = NEXT_TEMP.fetch_add(1, Ordering::Relaxed);
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(name);
    temp_name.push(format!(".{}.{n}.tmp", std::process::id()));
    Ok(path.with_file_name(temp_name))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh, empty directory, removed by the caller.
    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("relief-mesh-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn writes_replace_the_file_and_leave_no_temporary() {
        let dir = scratch("replace");
        let path = dir.join("out.bin");
        write_atomically(&path, b"old").unwrap();
        write_atomically(&path, b"new!").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new!");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn failed_writes_are_io_errors_that_leave_nothing() {
        let dir = scratch("fail");
        // Over a directory: the rename fails, and the temporary file is removed.
        let err = write_atomically(&dir, b"x").unwrap_err();
        assert!(matches!(err, MeshError::Io { .. }), "{err}");
        assert!(dir.is_dir());
        // Into a missing directory, and to a path naming no file.
        let err = write_atomically(&dir.join("missing/out.glb"), b"x").unwrap_err();
        assert!(matches!(err, MeshError::Io { kind: ErrorKind::NotFound, .. }), "{err}");
        assert!(err.to_string().contains("out.glb"), "{err}");
        assert!(matches!(write_atomically(Path::new("/"), b"x"), Err(MeshError::Io { .. })));
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
