//! Rasters read in bands of rows, never whole: the input of builds that must stay within a
//! memory bound whatever the raster's size (the tile pyramid of relief-tiles).

use crate::{IoError, Raster, RasterInfo};
use relief_core::GridGeometry;

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
    /// What the file (for a mosaic, its first file) said about itself.
    fn info(&self) -> &RasterInfo;
    /// Reads the `out.len() / width()` grid rows from `first_row` on into `out`, row-major.
    /// Fails when the rows run past the raster, when `out` is not whole rows, or when the file
    /// cannot be read or decoded (the error names the file).
    fn read_rows(&mut self, first_row: usize, out: &mut [f32]) -> Result<(), IoError>;
}

/// A raster already in memory, served as rows (for small inputs and tests).
pub struct InMemoryRows {
    raster: Raster,
}

impl InMemoryRows {
    /// Serves the rows of `raster`.
    pub fn new(raster: Raster) -> Self {
        InMemoryRows { raster }
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
        let width = self.raster.width;
        let rows = out.len() / width;
        assert!(
            out.len().is_multiple_of(width) && first_row + rows <= self.raster.height,
            "rows {first_row}..{} of a raster of {} rows, or a buffer of partial rows",
            first_row + rows,
            self.raster.height
        );
        out.copy_from_slice(&self.raster.samples[first_row * width..(first_row + rows) * width]);
        Ok(())
    }
}
