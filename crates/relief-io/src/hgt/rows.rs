//! An SRTM `.hgt` tile read as rows: each request seeks to its rows and reads only them.

use crate::hgt::tile::{hgt_placement, hgt_side, hgt_tile_corner, HGT_VOID};
use crate::input_file::open_input;
use crate::rows::row_source::check_request;
use crate::{IoError, RasterInfo, RowSource};
use relief_core::GridGeometry;
use std::fs::File;
use std::io::{ErrorKind, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// The rows of an SRTM tile, read from the file on request; samples, geometry, info and
/// voids as [`read_hgt`](crate::read_hgt) gives them.
pub(crate) struct HgtRows {
    path: PathBuf,
    file: File,
    /// Samples per side.
    side: usize,
    /// The tile's south-west corner (latitude, longitude) from its name, if it gives one.
    corner: Option<(i32, i32)>,
    geometry: GridGeometry,
    info: RasterInfo,
    /// The bytes of the rows last read.
    bytes: Vec<u8>,
}

impl HgtRows {
    /// Opens the tile at `path`, checking its length; reads no sample.
    ///
    /// Errors: [`IoError::Io`] when the file cannot be opened (or is a directory),
    /// [`IoError::Format`] for a length that is no tile's.
    pub(crate) fn open(path: &Path) -> Result<Self, IoError> {
        let (file, len) = open_input(path)?;
        let side = hgt_side(path, len)?;
        let corner = hgt_tile_corner(path);
        let (geometry, info) = hgt_placement(corner, side);
        Ok(HgtRows {
            path: path.to_path_buf(),
            file,
            side,
            corner,
            geometry,
            info,
            bytes: Vec::new(),
        })
    }

    /// The tile's south-west corner (latitude, longitude) from its name, if it gives one.
    pub(crate) fn corner(&self) -> Option<(i32, i32)> {
        self.corner
    }

    /// The file's path.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }
}

impl RowSource for HgtRows {
    fn width(&self) -> usize {
        self.side
    }
    fn height(&self) -> usize {
        self.side
    }
    fn geometry(&self) -> GridGeometry {
        self.geometry
    }
    fn info(&self) -> &RasterInfo {
        &self.info
    }
    fn read_rows(&mut self, first_row: usize, out: &mut [f32]) -> Result<(), IoError> {
        let n = self.side;
        let rows = check_request(&self.path, (n, n), first_row, out.len())?;
        if rows == 0 {
            return Ok(());
        }
        // Grid rows first_row.. are file rows n - first_row - rows..n - first_row, north first.
        let first_file_row = n - first_row - rows;
        self.bytes.resize(rows * 2 * n, 0);
        let path = &self.path;
        self.file
            .seek(SeekFrom::Start((first_file_row * 2 * n) as u64))
            .and_then(|_| self.file.read_exact(&mut self.bytes))
            .map_err(|e| match e.kind() {
                ErrorKind::UnexpectedEof => IoError::format(path, "truncated"),
                _ => IoError::io(path, e),
            })?;
        for (values, bytes) in out.chunks_exact_mut(n).zip(self.bytes.chunks_exact(2 * n).rev()) {
            for (v, b) in values.iter_mut().zip(bytes.chunks_exact(2)) {
                let raw = i16::from_be_bytes([b[0], b[1]]);
                *v = if raw == HGT_VOID { f32::NAN } else { f32::from(raw) };
            }
        }
        Ok(())
    }
    fn release_cache(&mut self) {
        self.bytes = Vec::new();
    }
}
