//! Writing f32 arrays and height fields as NumPy `.npy` files.

use crate::atomic_write::write_atomically;
use crate::npy_header::f32_header;
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
    let header = f32_header(shape).ok_or_else(|| {
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
