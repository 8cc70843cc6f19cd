//! `relief.write_png`: a picture `render` returns saved as a PNG, with no other package.

use crate::errors::{file, invalid};
use numpy::{PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;
use relief_io::PngCompression;
use std::path::PathBuf;

/// Writes ``rgb``, a uint8 array of shape (height, width, 3) such as ``render`` returns, to
/// ``path`` as an 8-bit RGB PNG (row 0 the top row), the file written whole or not at all,
/// compressed as ``compression`` says: ``"none"``, ``"fast"`` (the default), ``"balanced"``
/// or ``"high"``, as ``relief render --png-compression`` (the same bytes for the same
/// picture).
///
/// Raises ``relief.ReliefError`` for an array of another dtype or shape or an unknown
/// compression, ``OSError`` when the file cannot be written.
#[pyfunction]
#[pyo3(signature = (path, rgb, *, compression="fast"))]
pub fn write_png(path: PathBuf, rgb: &Bound<'_, PyAny>, compression: &str) -> PyResult<()> {
    let compression: PngCompression = compression.parse().map_err(invalid)?;
    let wrong =
        || invalid("rgb must be a uint8 array of shape (height, width, 3), as render returns");
    let array: PyReadonlyArray3<'_, u8> = rgb.extract().map_err(|_| wrong())?;
    let shape = array.shape();
    let (height, width) = (shape[0], shape[1]);
    if shape[2] != 3 || width == 0 || height == 0 {
        return Err(wrong());
    }
    let (Ok(w), Ok(h)) = (u32::try_from(width), u32::try_from(height)) else {
        return Err(invalid(format!("{width} x {height} pixels is too large for a PNG")));
    };
    // Logical order, whatever the strides.
    let bytes: Vec<u8> = array.as_array().iter().copied().collect();
    let py = rgb.py();
    py.detach(|| relief_io::write_png_rgb8_compressed(&path, w, h, &bytes, compression))
        .map_err(file)
}
