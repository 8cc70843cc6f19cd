//! The spill file of a cloud-optimised GeoTIFF being written: compressed tiles appended as
//! they come, read back to build the overviews and to copy them into the finished file.

use crate::IoError;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// An append-only file of compressed tiles, whose length is the end of the last append that
/// succeeded: an append that fails is overwritten by the next.
pub(crate) struct Spill {
    /// The spill file's own path (errors name it).
    path: PathBuf,
    file: File,
    len: u64,
}

impl Spill {
    /// Creates (or empties) the spill file at `path`.
    pub(crate) fn create(path: &Path) -> Result<Spill, IoError> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(path)
            .map_err(|e| IoError::io(path, e))?;
        Ok(Spill { path: path.to_path_buf(), file, len: 0 })
    }

    /// Opens the spill file an earlier writer left at `path`, whole; `None` when there is none.
    pub(crate) fn open(path: &Path) -> Result<Option<Spill>, IoError> {
        let file = match OpenOptions::new().read(true).write(true).open(path) {
            Ok(file) => file,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(IoError::io(path, e)),
        };
        let len = file.metadata().map_err(|e| IoError::io(path, e))?.len();
        Ok(Some(Spill { path: path.to_path_buf(), file, len }))
    }

    /// Bytes in the spill.
    pub(crate) fn len(&self) -> u64 {
        self.len
    }

    /// Appends `bytes`; returns their offset.
    pub(crate) fn append(&mut self, bytes: &[u8]) -> Result<u64, IoError> {
        let offset = self.len;
        self.file
            .seek(SeekFrom::Start(offset))
            .and_then(|_| self.file.write_all(bytes))
            .map_err(|e| IoError::io(&self.path, e))?;
        self.len += bytes.len() as u64;
        Ok(offset)
    }

    /// Forgets what was appended after its first `len` bytes (the next append overwrites it).
    pub(crate) fn rewind(&mut self, len: u64) {
        self.len = self.len.min(len);
    }

    /// Cuts the file to its first `len` bytes, on disk too.
    pub(crate) fn truncate(&mut self, len: u64) -> Result<(), IoError> {
        self.file.set_len(len).map_err(|e| IoError::io(&self.path, e))?;
        self.len = len;
        Ok(())
    }

    /// Waits until the spill's bytes are on disk.
    pub(crate) fn sync(&self) -> Result<(), IoError> {
        self.file.sync_data().map_err(|e| IoError::io(&self.path, e))
    }

    /// Reads the `count` bytes at `offset` into `out` (resized to hold them).
    pub(crate) fn read(
        &mut self,
        offset: u64,
        count: u32,
        out: &mut Vec<u8>,
    ) -> Result<(), IoError> {
        out.resize(count as usize, 0);
        if offset + u64::from(count) > self.len {
            return Err(IoError::format(
                &self.path,
                format!("{count} bytes at {offset} lie past the spill's end ({})", self.len),
            ));
        }
        self.file
            .seek(SeekFrom::Start(offset))
            .and_then(|_| self.file.read_exact(out))
            .map_err(|e| IoError::io(&self.path, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;

    #[test]
    fn appends_read_back_and_a_rewound_append_is_overwritten() {
        let dir = TestDir::new("cog-spill");
        let path = dir.path().join("spill");
        let mut spill = Spill::create(&path).unwrap();
        assert_eq!(spill.append(b"abc").unwrap(), 0);
        assert_eq!(spill.append(b"defg").unwrap(), 3);
        spill.rewind(3);
        assert_eq!(spill.append(b"XY").unwrap(), 3);
        let mut out = Vec::new();
        spill.read(2, 3, &mut out).unwrap();
        assert_eq!(out, b"cXY");
        assert!(spill
            .read(4, 2, &mut out)
            .unwrap_err()
            .to_string()
            .contains("past the spill's end"));
        spill.sync().unwrap();
        drop(spill);
        let mut again = Spill::open(&path).unwrap().unwrap();
        // The rewound byte is still on disk until truncated.
        assert_eq!(again.len(), 7);
        again.truncate(5).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"abcXY");
        assert!(Spill::open(&dir.path().join("none")).unwrap().is_none());
    }
}
