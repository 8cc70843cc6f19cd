//! The files of a store under construction, opened at their final size.

use crate::TileError;
use std::fs::{File, OpenOptions};
use std::path::Path;

/// Opens (or creates) the store file at `path` for reading and writing, `len` bytes long: a
/// new file is zeros, an interrupted build's keeps what it holds.
pub(crate) fn open_sized(path: &Path, len: u64) -> Result<File, TileError> {
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .map_err(|e| TileError::io(path, e))?;
    let size = file.metadata().map_err(|e| TileError::io(path, e))?.len();
    if size != len {
        file.set_len(len).map_err(|e| TileError::io(path, e))?;
    }
    Ok(file)
}
