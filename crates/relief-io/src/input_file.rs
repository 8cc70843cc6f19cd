//! Opening an input file: refusing directories and other non-files, and knowing its length.

use crate::IoError;
use std::fs::File;
use std::io::{Error, ErrorKind};
use std::path::Path;

/// Opens `path` for reading and returns it with its length in bytes.
///
/// A directory or another non-regular file is refused with [`IoError::Io`].
pub(crate) fn open_input(path: &Path) -> Result<(File, u64), IoError> {
    let file = File::open(path).map_err(|e| IoError::io(path, e))?;
    let meta = file.metadata().map_err(|e| IoError::io(path, e))?;
    if meta.is_dir() {
        return Err(IoError::io(path, Error::from(ErrorKind::IsADirectory)));
    }
    if !meta.is_file() {
        return Err(IoError::io(path, Error::new(ErrorKind::InvalidInput, "not a regular file")));
    }
    Ok((file, meta.len()))
}
