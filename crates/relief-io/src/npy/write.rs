//! Writing f32 arrays and height fields as NumPy `.npy` files.

use crate::atomic_write::write_atomically;
use crate::npy::header::{header_bytes, Dtype, ScalarKind};
use crate::sample_type::SampleType;
use crate::IoError;
use relief_core::HeightField;
use std::io::Write;
use std::path::Path;

/// Writes `data` as a little-endian f32 (`<f4`), C-order `.npy` array of `shape` (version 1.0
/// header padded to 64 bytes), e.g. `(H, W)` for a depth image or `(H, W, 3)` for normals.
///
/// The file is written atomically. [`IoError::InvalidData`] when the product of `shape` is not
/// `data.len()`; [`IoError::Io`] when the file cannot be written.
pub fn write_npy_f32(path: &Path, shape: &[usize], data: &[f32]) -> Result<(), IoError> {
    let count = shape.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
    if count != Some(data.len()) {
        return Err(IoError::invalid_data(
            path,
            format!("shape {shape:?} does not hold the {} values given", data.len()),
        ));
    }
    let dtype = Dtype::little_endian(ScalarKind::Sample(SampleType::F32));
    let header = header_bytes(dtype, shape).ok_or_else(|| {
        IoError::invalid_data(path, format!("shape {shape:?} is too long for a .npy header"))
    })?;
    write_atomically(path, |w| {
        w.write_all(&header).map_err(|e| IoError::io(path, e))?;
        let mut bytes = Vec::with_capacity(1 << 16);
        for chunk in data.chunks(1 << 14) {
            bytes.clear();
            bytes.extend(chunk.iter().flat_map(|v| v.to_le_bytes()));
            w.write_all(&bytes).map_err(|e| IoError::io(path, e))?;
        }
        Ok(())
    })
}

/// Writes `field`'s samples as a float32 `.npy` array of shape `(height, width)`; array row `r`
/// is grid row `r`, so [`read_npy_height_field`](crate::read_npy_height_field) reads it back.
pub fn write_height_field_npy(path: &Path, field: &HeightField) -> Result<(), IoError> {
    write_npy_f32(path, &[field.height(), field.width()], field.samples())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::npy::read_npy_height_field;
    use crate::test_dir::TestDir;
    use relief_core::GridGeometry;

    #[test]
    fn height_field_round_trips_exactly() {
        let dir = TestDir::new("npy-write");
        let path = dir.path().join("field.npy");
        let samples = vec![0.5, -1.0, 3.25, 1e-7, 2.0, 1e20];
        let field = HeightField::new(2, 3, samples, GridGeometry::unit()).unwrap();
        write_height_field_npy(&path, &field).unwrap();
        let back = read_npy_height_field(&path).unwrap();
        assert_eq!((back.width(), back.height()), (2, 3));
        assert_eq!(back.samples(), field.samples());
        let bytes = std::fs::read(&path).unwrap();
        let start = 10 + usize::from(u16::from_le_bytes([bytes[8], bytes[9]]));
        assert_eq!((start % 64, bytes.len()), (0, start + 6 * 4));
        assert_eq!(&bytes[start..start + 4], &0.5f32.to_le_bytes());
    }

    #[test]
    fn three_dimensional_arrays_are_written_with_their_shape() {
        let dir = TestDir::new("npy-write-3d");
        let path = dir.path().join("normals.npy");
        let data: Vec<f32> = (0..12).map(|v| v as f32).collect();
        write_npy_f32(&path, &[2, 2, 3], &data).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let start = 10 + usize::from(u16::from_le_bytes([bytes[8], bytes[9]]));
        let header = String::from_utf8_lossy(&bytes[10..start]).into_owned();
        assert!(header.contains("'shape': (2, 2, 3)"), "{header}");
        assert_eq!(&bytes[start + 11 * 4..], &11f32.to_le_bytes());
    }

    #[test]
    fn shape_that_does_not_match_the_data_is_refused_and_nothing_written() {
        let dir = TestDir::new("npy-write-bad");
        let path = dir.path().join("bad.npy");
        let err = write_npy_f32(&path, &[2, 3], &[0.0; 5]).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        let err = write_npy_f32(&path, &[usize::MAX, 3], &[0.0; 5]).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn writing_into_a_missing_directory_is_an_io_error() {
        let dir = TestDir::new("npy-write-missing");
        let err = write_npy_f32(&dir.path().join("no/such.npy"), &[1], &[0.0]).unwrap_err();
        assert!(matches!(err, IoError::Io { .. }), "{err}");
    }
}
