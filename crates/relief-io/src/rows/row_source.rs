//! Rasters read in bands of rows, never whole: the input of builds that must stay within a
//! memory bound whatever the raster's size (the tile pyramid of relief-tiles).

use crate::{IoError, Raster, RasterInfo, ReadOptions};
use relief_core::GridGeometry;
use std::path::{Path, PathBuf};

/// A raster whose rows are read on request, in any order.
///
/// Rows are grid rows as in [`Raster`]: row 0 southernmost (north-up files are flipped), voids
/// (the file's nodata, or the gaps of a mosaic) as NaN, every other sample finite.
pub trait RowSource: Send {
    /// Columns.
    fn width(&self) -> usize;
    /// Rows.
    fn height(&self) -> usize;
    /// Spacing and origin (metres when georeferenced), z scale 1, as [`Raster::geometry`].
    fn geometry(&self) -> GridGeometry;
    /// What the file said about itself; for a mosaic, what its first file said, with the
    /// placement ([`RasterInfo::georeference`]) of the whole mosaic.
    fn info(&self) -> &RasterInfo;
    /// Reads the `out.len() / width()` grid rows from `first_row` on into `out`, row-major.
    /// Fails with [`IoError::InvalidData`] when the rows run past the raster or `out` is not
    /// whole rows, and as the file's reader does when the file cannot be read or decoded
    /// (the error names the file).
    fn read_rows(&mut self, first_row: usize, out: &mut [f32]) -> Result<(), IoError>;
    /// Frees what the source keeps between reads to make the next one faster (a decoded
    /// row of strips or tiles); the next read decodes again. Does nothing by default.
    fn release_cache(&mut self) {}
}

/// Checks a [`RowSource::read_rows`] request of `len` samples from `first_row` on against a
/// `width x height` raster; returns the number of rows asked for. `path` names the source.
pub(crate) fn check_request(
    path: &Path,
    (width, height): (usize, usize),
    first_row: usize,
    len: usize,
) -> Result<usize, IoError> {
    if width == 0 || !len.is_multiple_of(width) {
        return Err(IoError::invalid_data(
            path,
            format!("a buffer of {len} samples is not whole rows of {width} samples"),
        ));
    }
    let rows = len / width;
    if first_row.checked_add(rows).is_none_or(|end| end > height) {
        return Err(IoError::invalid_data(
            path,
            format!(
                "rows {first_row}..{} asked of a raster of {height} rows",
                first_row.saturating_add(rows)
            ),
        ));
    }
    Ok(rows)
}

/// A raster already in memory, served as rows (for small inputs, formats that cannot be
/// read in parts, and tests).
pub struct InMemoryRows {
    raster: Raster,
    /// Names the source in errors.
    path: PathBuf,
}

impl InMemoryRows {
    /// Serves the rows of `raster`.
    pub fn new(raster: Raster) -> Self {
        InMemoryRows { raster, path: PathBuf::from("raster in memory") }
    }

    /// Reads the raster at `path` whole with [`read_raster`](crate::read_raster) (within
    /// `options.max_memory`) and serves its rows; errors name `path`.
    pub fn from_file(path: &Path, options: &ReadOptions) -> Result<Self, IoError> {
        let raster = crate::read_raster(path, options)?;
        Ok(InMemoryRows { raster, path: path.to_path_buf() })
    }

    /// The raster served.
    pub fn raster(&self) -> &Raster {
        &self.raster
    }
}

impl RowSource for InMemoryRows {
    fn width(&self) -> usize {
        self.raster.width
    }
    fn height(&self) -> usize {
        self.raster.height
    }
    fn geometry(&self) -> GridGeometry {
        self.raster.geometry
    }
    fn info(&self) -> &RasterInfo {
        &self.raster.info
    }
    fn read_rows(&mut self, first_row: usize, out: &mut [f32]) -> Result<(), IoError> {
        let (width, height) = (self.raster.width, self.raster.height);
        let rows = check_request(&self.path, (width, height), first_row, out.len())?;
        out.copy_from_slice(&self.raster.samples[first_row * width..(first_row + rows) * width]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Format, RasterInfo};

    #[test]
    fn bad_requests_are_errors_not_panics() {
        let raster = Raster {
            width: 3,
            height: 2,
            samples: vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
            geometry: GridGeometry::unit(),
            info: RasterInfo {
                format: Format::Npy,
                sample_type: "float32".into(),
                georeferenced: false,
                height_unit: crate::HeightUnit::default(),
                from_degrees: None,
                nodata: None,
                georeference: None,
            },
        };
        let mut rows = InMemoryRows::new(raster);
        let mut out = [0f32; 3];
        rows.read_rows(1, &mut out).unwrap();
        assert_eq!(out, [3.0, 4.0, 5.0]);
        for (first, len) in [(2, 3), (1, 6), (0, 4), (usize::MAX, 3), (0, 9)] {
            let mut out = vec![0f32; len];
            let err = rows.read_rows(first, &mut out).unwrap_err();
            assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        }
        // No rows at all is a valid request, up to the end.
        rows.read_rows(2, &mut []).unwrap();
    }
}
