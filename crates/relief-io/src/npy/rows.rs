//! A C-order `.npy` array read as rows: each request seeks to its rows and reads only them.

use crate::input_file::open_input;
use crate::npy::header::{read_header, Dtype};
use crate::npy::read::convert;
use crate::raster::mark_row_voids;
use crate::rows::row_source::check_request;
use crate::{Format, IoError, RasterInfo, RowSource};
use relief_core::GridGeometry;
use std::fs::File;
use std::io::{BufReader, ErrorKind, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// The rows of a 2D C-order `.npy` array, read from the file on request; samples, geometry
/// and info as [`read_npy`](crate::read_npy) gives them (array row r is grid row r).
pub(crate) struct NpyRows {
    path: PathBuf,
    file: File,
    rows: usize,
    cols: usize,
    dtype: Dtype,
    /// Where the data starts in the file.
    data_offset: u64,
    info: RasterInfo,
    /// The bytes of the rows last read.
    bytes: Vec<u8>,
}

/// What opening a `.npy` file as rows found.
pub(crate) enum NpyOpened {
    /// A C-order array, read as rows.
    Rows(Box<NpyRows>),
    /// A Fortran-order array, whose rows are not contiguous in the file.
    FortranOrder,
}

impl NpyRows {
    /// Opens the `.npy` file at `path`: reads its header and checks its shape against the
    /// file's length; reads no sample.
    ///
    /// Errors: those of [`read_npy`](crate::read_npy) about the header and the length.
    pub(crate) fn open(path: &Path) -> Result<NpyOpened, IoError> {
        let (file, len) = open_input(path)?;
        let mut reader = BufReader::new(file);
        let header = read_header(&mut reader, len).map_err(|e| e.at(path))?;
        let (rows, cols) = match header.shape[..] {
            [rows, cols] => (rows, cols),
            ref shape => {
                return Err(IoError::unsupported(
                    path,
                    format!(
                        "{}-dimensional array of shape {shape:?}; need 2 dimensions",
                        shape.len()
                    ),
                ))
            }
        };
        if rows == 0 || cols == 0 {
            return Err(IoError::format(path, format!("array of shape ({rows}, {cols}) is empty")));
        }
        let size = header.dtype.size() as u64;
        let data_len = len.saturating_sub(header.data_offset);
        let needed = rows.checked_mul(cols).and_then(|n| n.checked_mul(size));
        if needed != Some(data_len) {
            return Err(IoError::format(
                path,
                format!(
                    "shape ({rows}, {cols}) of {size}-byte elements needs {} data bytes, the file \
                     has {data_len}",
                    needed.map_or("more than 2^64".into(), |n| n.to_string())
                ),
            ));
        }
        let (Ok(rows), Ok(cols)) = (usize::try_from(rows), usize::try_from(cols)) else {
            return Err(IoError::unsupported(
                path,
                format!("shape ({rows}, {cols}) on this machine"),
            ));
        };
        if header.fortran_order && rows > 1 && cols > 1 {
            return Ok(NpyOpened::FortranOrder);
        }
        let info = RasterInfo {
            format: Format::Npy,
            sample_type: header.dtype.kind.name().to_owned(),
            georeferenced: false,
            height_unit: crate::HeightUnit::default(),
            from_degrees: None,
            georeference: None,
            nodata: None,
        };
        Ok(NpyOpened::Rows(Box::new(NpyRows {
            path: path.to_path_buf(),
            file: reader.into_inner(),
            rows,
            cols,
            dtype: header.dtype,
            data_offset: header.data_offset,
            info,
            bytes: Vec::new(),
        })))
    }
}

impl RowSource for NpyRows {
    fn width(&self) -> usize {
        self.cols
    }
    fn height(&self) -> usize {
        self.rows
    }
    fn geometry(&self) -> GridGeometry {
        GridGeometry::unit()
    }
    fn info(&self) -> &RasterInfo {
        &self.info
    }
    fn read_rows(&mut self, first_row: usize, out: &mut [f32]) -> Result<(), IoError> {
        let cols = self.cols;
        let rows = check_request(&self.path, (cols, self.rows), first_row, out.len())?;
        let size = self.dtype.size();
        let path = &self.path;
        self.bytes.resize(rows * cols * size, 0);
        let start = self.data_offset + (first_row * cols * size) as u64;
        self.file
            .seek(SeekFrom::Start(start))
            .and_then(|_| self.file.read_exact(&mut self.bytes))
            .map_err(|e| match e.kind() {
                ErrorKind::UnexpectedEof => IoError::format(path, "truncated in the data"),
                _ => IoError::io(path, e),
            })?;
        convert(&self.bytes, self.dtype, out);
        for (row, values) in (first_row..).zip(out.chunks_exact_mut(cols)) {
            mark_row_voids(values, row, None).map_err(|e| e.at(path))?;
        }
        Ok(())
    }
    fn release_cache(&mut self) {
        self.bytes = Vec::new();
    }
}
