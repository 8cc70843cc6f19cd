//! Opening any height file as a [`RowSource`]: streamed where the format allows it.

use crate::geotiff::rows::GeoTiffRows;
use crate::hgt::rows::HgtRows;
use crate::npy::rows::{NpyOpened, NpyRows};
use crate::{format_of, Format, InMemoryRows, IoError, RasterInfo, ReadOptions, RowSource};
use relief_core::GridGeometry;
use std::path::Path;

/// Opens the height file at `path` as rows read on request, in the format its extension
/// names. The rows are exactly those of [`read_raster`](crate::read_raster) for the same
/// file and options: the same samples, voids (NaN), geometry and info.
///
/// Streamed, whatever the file's size:
/// - GeoTIFF: only the strips or tiles covering the rows asked for are decoded (any
///   compression [`read_geotiff`](crate::geotiff::read_geotiff) reads), one row of strips or tiles
///   at a time; the last decoded row of them is kept for the next request. Memory: one row
///   of strips or tiles as f32 plus one stored strip or tile, which must fit in
///   `options.max_memory` ([`IoError::Limits`] otherwise, for a file of a single huge strip);
/// - SRTM `.hgt`: each request seeks to its rows and reads them;
/// - `.npy` in C order (and any single-row or single-column array): the same.
///
/// Other files (`.asc`, PNG, `.npz`, a Fortran-order `.npy`) are read whole with
/// [`read_raster`](crate::read_raster), refused beyond `options.max_memory` as it refuses
/// them, and served from memory ([`InMemoryRows`]).
///
/// Errors: those of the format's reader about the file's header and layout when opening;
/// those about samples (a NaN that is not the nodata value, a corrupt strip) come from
/// [`RowSource::read_rows`] when the rows holding them are read.
///
/// ```
/// use relief_core::{GridGeometry, HeightField};
/// let path = std::env::temp_dir().join(format!("relief-io-rows-doc-{}.npy", std::process::id()));
/// let field = HeightField::new(3, 2, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0], GridGeometry::unit())?;
/// relief_io::npy::write_height_field_npy(&path, &field)?;
/// let mut rows = relief_io::open_rows(&path, &relief_io::ReadOptions::default())?;
/// let mut second = [0f32; 3];
/// rows.read_rows(1, &mut second)?;
/// assert_eq!(second, [3.0, 4.0, 5.0]);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn open_rows(path: &Path, options: &ReadOptions) -> Result<Box<dyn RowSource>, IoError> {
    let streamed: Box<dyn RowSource> = match format_of(path, options)? {
        Format::GeoTiff => Box::new(GeoTiffRows::open(path, options)?),
        Format::Hgt => Box::new(HgtRows::open(path)?),
        Format::Npy => match NpyRows::open(path)? {
            NpyOpened::Rows(rows) => rows,
            NpyOpened::FortranOrder => {
                return Ok(Box::new(InMemoryRows::from_file(path, options)?))
            }
        },
        // Read whole by read_raster, which applies the height unit itself.
        Format::Npz | Format::Asc | Format::Png16 | Format::TerrainRgb | Format::Terrarium => {
            return Ok(Box::new(InMemoryRows::from_file(path, options)?))
        }
    };
    Ok(in_unit(streamed, options))
}

/// `rows` with its heights in [`ReadOptions::z_unit`] when the caller gave one (its z scale
/// that unit's length in metres, its info naming the unit and why), as
/// [`read_raster`](crate::read_raster) applies it; `rows` itself otherwise.
pub(crate) fn in_unit(rows: Box<dyn RowSource>, options: &ReadOptions) -> Box<dyn RowSource> {
    if options.z_unit.is_none() {
        return rows;
    }
    let mut info = rows.info().clone();
    info.height_unit = options.height_unit(std::mem::take(&mut info.height_unit));
    let geometry = GridGeometry { z_scale: info.height_unit.unit.metres(), ..rows.geometry() };
    Box::new(RowsInUnit { rows, geometry, info })
}

/// A row source whose heights the caller said are in another unit: the same rows, another z
/// scale and height unit.
struct RowsInUnit {
    rows: Box<dyn RowSource>,
    geometry: GridGeometry,
    info: RasterInfo,
}

impl RowSource for RowsInUnit {
    fn width(&self) -> usize {
        self.rows.width()
    }
    fn height(&self) -> usize {
        self.rows.height()
    }
    fn geometry(&self) -> GridGeometry {
        self.geometry
    }
    fn info(&self) -> &RasterInfo {
        &self.info
    }
    fn read_rows(&mut self, first_row: usize, out: &mut [f32]) -> Result<(), IoError> {
        self.rows.read_rows(first_row, out)
    }
    fn release_cache(&mut self) {
        self.rows.release_cache();
    }
}
