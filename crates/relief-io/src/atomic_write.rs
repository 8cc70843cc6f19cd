//! Writing an output file atomically: into a temporary file beside it, renamed into place.

use crate::IoError;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Error, ErrorKind, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporary files made by concurrent writes in one process.
static NEXT_TEMP: AtomicU64 = AtomicU64::new(0);

/// Writes `path` through `write`, which receives a buffered writer on a temporary file in the
/// same directory. Only when `write` and the final flush succeed is the temporary file renamed
/// over `path`; on any error it is removed and `path` is left as it was.
pub(crate) fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&File>) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let temp = temp_path(path)?;
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(|e| IoError::io(path, e))?;
    let result = fill(path, &file, write).and_then(|()| {
        drop(file);
        std::fs::rename(&temp, path).map_err(|e| IoError::io(path, e))
    });
    if result.is_err() {
        // Best effort: the original error matters more than a failed clean-up.
        let _ = std::fs::remove_file(&temp);
    }
    result
}

/// Writes `bytes` to `path` atomically: into a temporary file beside it, synced, then renamed
/// over `path`; on any error the temporary file is removed and `path` is left as it was. For
/// outputs another crate encodes, such as relief-mesh's exported meshes.
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomically(path, |w| w.write_all(bytes).map_err(|e| IoError::io(path, e)))
}

/// Runs `write` on `file`, flushes it and syncs it to disk.
fn fill(
    path: &Path,
    file: &File,
    write: impl FnOnce(&mut BufWriter<&File>) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let mut buffered = BufWriter::with_capacity(1 << 16, file);
    write(&mut buffered)?;
    buffered.flush().map_err(|e| IoError::io(path, e))?;
    drop(buffered);
    file.sync_all().map_err(|e| IoError::io(path, e))
}

/// A fresh hidden name beside `path`: `.<name>.<pid>.<n>.tmp`.
pub(crate) fn temp_path(path: &Path) -> Result<PathBuf, IoError> {
    let name = path.file_name().ok_or_else(|| {
        IoError::io(path, Error::new(ErrorKind::InvalidInput, "path does not name a file"))
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
    use crate::test_dir::TestDir;

    #[test]
    fn failed_write_keeps_the_old_file_and_leaves_no_temporary() {
        let dir = TestDir::new("atomic");
        let path = dir.path().join("out.bin");
        write_atomically(&path, |w| w.write_all(b"old").map_err(|e| IoError::io(&path, e)))
            .unwrap();
        let err = write_atomically(&path, |w| {
            w.write_all(b"half").map_err(|e| IoError::io(&path, e))?;
            Err(IoError::invalid_data(&path, "stop"))
        })
        .unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }));
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn writing_over_a_directory_is_an_io_error() {
        let dir = TestDir::new("atomic-dir");
        let err = write_atomically(dir.path(), |_| Ok(())).unwrap_err();
        assert!(matches!(err, IoError::Io { .. }), "{err}");
        assert!(dir.path().is_dir());
    }
}
