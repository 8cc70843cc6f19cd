//! NumPy arrays in and out. Any array of real numbers (floats, signed or unsigned integers,
//! in C or Fortran order or a strided view) is read in its logical order, so a view and its
//! contiguous copy give the same result; anything else NumPy can turn into an array (a
//! nested list) is taken through `numpy.asarray` first.

use crate::errors::invalid;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::prelude::*;
use numpy::{PyArray1, PyArray2, PyArray3, PyReadonlyArray2, PyUntypedArray};
use pyo3::prelude::*;

/// A grid of samples as the caller gave it: row-major, row 0 the array's first row.
pub struct ArrayGrid {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` samples, NaN where the caller marked a void.
    pub samples: Vec<f32>,
}

/// The heights array `value`, as f32: two dimensions, at least one sample, every sample
/// finite or NaN (a void).
pub fn heights(value: &Bound<'_, PyAny>) -> PyResult<ArrayGrid> {
    let array = real_array(value, "heights", "float32")?;
    let shape = array.shape();
    if shape.len() != 2 {
        return Err(invalid(format!(
            "heights must be a 2-D array (rows, columns), got a {}-D array of shape {}",
            shape.len(),
            shape_text(shape)
        )));
    }
    let (height, width) = (shape[0], shape[1]);
    if width == 0 || height == 0 {
        return Err(invalid(format!("heights: raster of {width} x {height} samples is empty")));
    }
    let readonly: PyReadonlyArray2<'_, f32> = array.as_any().extract()?;
    let samples = logical_order(&readonly);
    if let Some(i) = samples.iter().position(|v| v.is_infinite()) {
        return Err(invalid(format!(
            "heights: sample at column {}, row {} is {}",
            i % width,
            i / width,
            samples[i]
        )));
    }
    Ok(ArrayGrid { width, height, samples })
}

/// The `(N, 3)` array `value` (ray origins or directions), named `name` in messages, as its
/// `3 N` values in row order. Only the copy happens here, with the GIL held; see
/// [`check_finite_rows`] for the check that follows without it.
pub fn vectors(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    let array = real_array(value, name, "float64")?;
    let shape = array.shape();
    if shape.len() != 2 || shape[1] != 3 {
        return Err(invalid(format!(
            "{name} must be an array of shape (N, 3), got shape {}",
            shape_text(shape)
        )));
    }
    let readonly: PyReadonlyArray2<'_, f64> = array.as_any().extract()?;
    Ok(logical_order(&readonly))
}

/// Refuses a row of the vectors `values` (three numbers a row) that is not finite, naming
/// the array `name` and the row.
pub fn check_finite_rows(values: &[f64], name: &str) -> Result<(), String> {
    match values.chunks_exact(3).position(|v| !v.iter().all(|x| x.is_finite())) {
        Some(k) => {
            let v = &values[3 * k..3 * k + 3];
            Err(format!("{name}: row {k} ({}, {}, {}) is not finite", v[0], v[1], v[2]))
        }
        None => Ok(()),
    }
}

/// The values of `array` in its logical (row-major) order, whatever its memory layout: one
/// copy of the memory when it is C-contiguous.
fn logical_order<T: numpy::Element + Copy>(array: &PyReadonlyArray2<'_, T>) -> Vec<T> {
    // `as_slice` also takes a Fortran-ordered array, in its memory order: C order only.
    match array.as_slice() {
        Ok(slice) if array.is_c_contiguous() => slice.to_vec(),
        _ => array.as_array().iter().copied().collect(),
    }
}

/// `value` as a NumPy array of `dtype` (`float32` or `float64`), converted from any other real
/// number type; booleans, complex numbers, strings and objects are refused.
fn real_array<'py>(
    value: &Bound<'py, PyAny>,
    name: &str,
    dtype: &str,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = value.py();
    let numpy = py.import("numpy")?;
    let array = match value.cast::<PyUntypedArray>() {
        Ok(array) => array.clone(),
        Err(_) => numpy
            .call_method1("asarray", (value,))
            .and_then(|a| Ok(a.cast_into::<PyUntypedArray>()?))
            .map_err(|e| invalid(format!("{name} is not an array of numbers: {e}")))?,
    };
    let descr = array.dtype();
    if !matches!(descr.kind(), b'f' | b'i' | b'u') {
        return Err(invalid(format!(
            "{name}: dtype {} is not a real number type (expected floats or integers)",
            descr
        )));
    }
    if descr.is_equiv_to(&numpy::dtype::<f32>(py)) && dtype == "float32"
        || descr.is_equiv_to(&numpy::dtype::<f64>(py)) && dtype == "float64"
    {
        return Ok(array);
    }
    Ok(array.call_method1("astype", (dtype,))?.cast_into::<PyUntypedArray>()?)
}

/// A shape as NumPy prints it: `(3,)`, `(2, 3)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", ")),
    }
}

/// A `(height, width)` float32 array of `values` (row-major).
pub fn image_f32(
    py: Python<'_>,
    height: usize,
    width: usize,
    values: Vec<f32>,
) -> PyResult<Bound<'_, PyArray2<f32>>> {
    let array = Array2::from_shape_vec((height, width), values)
        .map_err(|e| invalid(format!("image of {width} x {height}: {e}")))?;
    Ok(array.into_pyarray(py))
}

/// A `(bands, height, width)` float32 array of `values` (band by band, each row-major).
pub fn bands_f32(
    py: Python<'_>,
    bands: usize,
    height: usize,
    width: usize,
    values: Vec<f32>,
) -> PyResult<Bound<'_, PyArray3<f32>>> {
    let array = Array3::from_shape_vec((bands, height, width), values)
        .map_err(|e| invalid(format!("{bands} bands of {width} x {height}: {e}")))?;
    Ok(array.into_pyarray(py))
}

/// A `(height, width, 3)` uint8 array of the RGB bytes `rgb` (row-major).
pub fn image_rgb8(
    py: Python<'_>,
    height: usize,
    width: usize,
    rgb: Vec<u8>,
) -> PyResult<Bound<'_, PyArray3<u8>>> {
    let array = Array3::from_shape_vec((height, width, 3), rgb)
        .map_err(|e| invalid(format!("image of {width} x {height}: {e}")))?;
    Ok(array.into_pyarray(py))
}

/// A one-dimensional float64 array of `values`.
pub fn vector_f64(py: Python<'_>, values: Vec<f64>) -> Bound<'_, PyArray1<f64>> {
    Array1::from_vec(values).into_pyarray(py)
}
