//! A 2D NumPy `.npy` array as a [`Raster`]: no georeference, no flip, no nodata.

use crate::format_error::FormatError;
use crate::input_file::open_input;
use crate::npy::read::{read_npy_array_from, NpyArray};
use crate::raster::{mark_voids, Format, Raster, RasterInfo, ReadOptions, VoidPolicy};
use crate::IoError;
use relief_core::{GridGeometry, HeightField};
use std::io::{BufReader, Read};
use std::path::Path;

/// Reads the 2D `.npy` array at `path` as a raster.
///
/// Array row `r` is grid row `r` (a `.npy` grid has no georeference, so it is not flipped),
/// array column `c` grid column `c`; the geometry is [`GridGeometry::unit`]. Elements may be
/// any integer type of 1 to 8 bytes, float16, float32 or float64, either byte order, C or
/// Fortran order; they are converted to f32. A `.npy` file has no nodata value, so the raster
/// has no voids.
///
/// The shape is checked against the file length and `options` before the samples are
/// allocated, and the data is decoded chunk by chunk.
///
/// Errors: [`IoError::Io`] when the file cannot be read (or is a directory),
/// [`IoError::Format`] for a malformed or truncated file, an empty array or a shape that
/// disagrees with the data length, [`IoError::Unsupported`] for other dtypes or a number of
/// dimensions other than 2, [`IoError::Limits`] for an array over the memory budget, and
/// [`IoError::InvalidData`] naming the first NaN or infinite sample (or a finite float64
/// beyond f32's range).
pub fn read_npy(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let (file, len) = open_input(path)?;
    read_npy_from(BufReader::new(file), len, options).map_err(|e| e.at(path))
}

/// [`read_npy`] from `reader` holding the `len` bytes of a `.npy` file, before the file is
/// named.
pub(crate) fn read_npy_from<R: Read>(
    reader: R,
    len: u64,
    options: &ReadOptions,
) -> Result<Raster, FormatError> {
    let array = read_npy_array_from(reader, len, options)?;
    npy_raster(array, Format::Npy)
}

/// Reads the 2D `.npy` array at `path` as a height field with [`GridGeometry::unit`].
///
/// Array row `r` becomes grid row `r` (no flip) and array column `c` grid column `c`.
/// Elements may be int8, uint8, int16, uint16, int32, uint32, int64, uint64, float16, float32
/// or float64, little- or big-endian, in C or Fortran order; they are converted to f32. The
/// default [`ReadOptions`] apply (see [`read_npy`] for the raster with options).
///
/// Errors: [`IoError::Io`] when the file cannot be read, [`IoError::Format`] for a malformed or
/// truncated file, an empty array, or a shape that disagrees with the data length,
/// [`IoError::Unsupported`] for other dtypes or a number of dimensions other than 2,
/// [`IoError::Limits`] for an array over the memory budget, and [`IoError::InvalidData`]
/// naming the first NaN or infinite sample.
///
/// [`GridGeometry::unit`]: relief_core::GridGeometry::unit
pub fn read_npy_height_field(path: &Path) -> Result<HeightField, IoError> {
    read_npy(path, &ReadOptions::default())?.into_height_field(path, VoidPolicy::Fill)
}

/// The raster of a decoded array (read from a file of `format`): refuses non-finite samples.
pub(crate) fn npy_raster(array: NpyArray, format: Format) -> Result<Raster, FormatError> {
    let NpyArray { rows, cols, mut samples, dtype } = array;
    mark_voids(&mut samples, cols, None, false)?;
    Ok(Raster {
        width: cols,
        height: rows,
        samples,
        geometry: GridGeometry::unit(),
        info: RasterInfo {
            format,
            sample_type: dtype.kind.name().to_owned(),
            georeferenced: false,
            height_unit: crate::HeightUnit::default(),
            from_degrees: None,
            georeference: None,
            nodata: None,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::npy::write_npy_f32;
    use crate::test_dir::TestDir;

    #[test]
    fn rows_are_not_flipped_and_info_names_the_dtype() {
        let dir = TestDir::new("npy-raster");
        let path = dir.path().join("grid.npy");
        write_npy_f32(&path, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]).unwrap();
        let raster = read_npy(&path, &ReadOptions::default()).unwrap();
        assert_eq!((raster.width, raster.height), (3, 2));
        assert_eq!(raster.samples, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(raster.geometry, GridGeometry::unit());
        assert_eq!(raster.info.format, Format::Npy);
        assert_eq!(raster.info.sample_type, "float32");
        assert!(!raster.info.georeferenced && raster.info.nodata.is_none());
    }

    #[test]
    fn size_is_checked_against_the_budget_before_reading_the_data() {
        let dir = TestDir::new("npy-raster-limits");
        let path = dir.path().join("grid.npy");
        write_npy_f32(&path, &[20, 30], &[1.0; 600]).unwrap();
        let options = ReadOptions { max_memory: 599 * 5, ..ReadOptions::default() };
        let err = read_npy(&path, &options).unwrap_err();
        assert!(matches!(err, IoError::Limits { width: 30, height: 20, .. }), "{err}");
        let options = ReadOptions { max_memory: 600 * 5, ..ReadOptions::default() };
        assert!(read_npy(&path, &options).is_ok());
    }

    #[test]
    fn nan_and_infinity_are_refused() {
        let dir = TestDir::new("npy-raster-nan");
        let path = dir.path().join("grid.npy");
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            write_npy_f32(&path, &[2, 2], &[1.0, 2.0, bad, 4.0]).unwrap();
            let err = read_npy(&path, &ReadOptions::default()).unwrap_err();
            assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
            assert!(err.to_string().contains("column 0, row 1"), "{err}");
        }
    }

    #[test]
    fn reads_from_memory() {
        let dir = TestDir::new("npy-raster-mem");
        let path = dir.path().join("grid.npy");
        write_npy_f32(&path, &[1, 2], &[7.0, 8.0]).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let raster =
            read_npy_from(&bytes[..], bytes.len() as u64, &ReadOptions::default()).unwrap();
        assert_eq!(raster.samples, [7.0, 8.0]);
    }
}
