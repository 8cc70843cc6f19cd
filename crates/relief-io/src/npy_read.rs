//! Reading a 2D NumPy `.npy` array as a height field.

use crate::input_file::open_input;
use crate::npy_header::{read_header, Dtype, ScalarKind};
use crate::IoError;
use relief_core::{GridGeometry, HeightField};
use std::io::{BufReader, ErrorKind, Read};
use std::path::Path;

/// Bytes decoded at a time; a multiple of every element size.
const CHUNK: usize = 1 << 16;

/// Reads the 2D `.npy` array at `path` as a height field with [`GridGeometry::unit`].
///
/// Array row `r` becomes grid row `r` (no flip) and array column `c` grid column `c`.
/// Elements may be int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32 or
/// float64, little- or big-endian, in C or Fortran order; they are converted to f32.
///
/// Errors: [`IoError::Io`] when the file cannot be read, [`IoError::Format`] for a malformed or
/// truncated file, an empty array, or a shape that disagrees with the data length,
/// [`IoError::Unsupported`] for other dtypes or a number of dimensions other than 2, and
/// [`IoError::InvalidData`] naming the first NaN or infinite sample.
pub fn read_npy_height_field(path: &Path) -> Result<HeightField, IoError> {
    let (file, file_len) = open_input(path)?;
    let mut reader = BufReader::new(file);
    let header = read_header(path, &mut reader, file_len)?;
    let (rows, cols) = match header.shape[..] {
        [rows, cols] => (rows, cols),
        ref shape => {
            return Err(IoError::unsupported(
                path,
                format!("{}-dimensional array of shape {shape:?}; need 2 dimensions", shape.len()),
            ))
        }
    };
    if rows == 0 || cols == 0 {
        return Err(IoError::format(path, format!("array of shape ({rows}, {cols}) is empty")));
    }
    let size = header.dtype.size();
    let data_len = file_len - header.data_offset;
    let needed = rows.checked_mul(cols).and_then(|n| n.checked_mul(size as u64));
    if needed != Some(data_len) {
        return Err(IoError::format(
            path,
            format!(
                "shape ({rows}, {cols}) of {size}-byte elements needs {} data bytes, the file has {data_len}",
                needed.map_or("more than 2^64".into(), |n| n.to_string())
            ),
        ));
    }
    let (Ok(rows), Ok(cols)) = (usize::try_from(rows), usize::try_from(cols)) else {
        return Err(IoError::unsupported(path, format!("shape ({rows}, {cols}) on this machine")));
    };
    let Some(count) = rows.checked_mul(cols) else {
        return Err(IoError::unsupported(path, format!("shape ({rows}, {cols}) on this machine")));
    };
    let mut samples = decode(path, &mut reader, header.dtype, count)?;
    if header.fortran_order {
        samples = transpose(&samples, rows, cols);
    }
    if let Some(i) = samples.iter().position(|v| !v.is_finite()) {
        return Err(IoError::invalid_data(
            path,
            format!("sample at column {}, row {} is {} as f32", i % cols, i / cols, samples[i]),
        ));
    }
    HeightField::new(cols, rows, samples, GridGeometry::unit())
        .map_err(|e| IoError::invalid_data(path, e.to_string()))
}

/// Reads `count` elements of `dtype` from `reader` as f32, in file order.
fn decode(
    path: &Path,
    reader: &mut impl Read,
    dtype: Dtype,
    count: usize,
) -> Result<Vec<f32>, IoError> {
    let size = dtype.size();
    let mut samples = vec![0f32; count];
    let mut bytes = vec![0u8; CHUNK];
    for out in samples.chunks_mut(CHUNK / size) {
        let chunk = &mut bytes[..out.len() * size];
        reader.read_exact(chunk).map_err(|e| match e.kind() {
            ErrorKind::UnexpectedEof => IoError::format(path, "truncated in the data"),
            _ => IoError::io(path, e),
        })?;
        convert(chunk, dtype, out);
    }
    Ok(samples)
}

/// Converts the elements in `bytes` to f32 into `out`.
fn convert(bytes: &[u8], dtype: Dtype, out: &mut [f32]) {
    macro_rules! each {
        ($t:ty) => {{
            const N: usize = std::mem::size_of::<$t>();
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(N)) {
                let mut raw = [0u8; N];
                raw.copy_from_slice(b);
                let v = if dtype.big_endian { <$t>::from_be_bytes(raw) } else { <$t>::from_le_bytes(raw) };
                *o = v as f32;
            }
        }};
    }
    match dtype.kind {
        ScalarKind::I8 => each!(i8),
        ScalarKind::U8 => each!(u8),
        ScalarKind::I16 => each!(i16),
        ScalarKind::U16 => each!(u16),
        ScalarKind::I32 => each!(i32),
        ScalarKind::U32 => each!(u32),
        ScalarKind::I64 => each!(i64),
        ScalarKind::U64 => each!(u64),
        ScalarKind::F32 => each!(f32),
        ScalarKind::F64 => each!(f64),
    }
}

/// Reorders column-major samples of a `rows x cols` array into row-major order.
fn transpose(column_major: &[f32], rows: usize, cols: usize) -> Vec<f32> {
    let mut row_major = vec![0f32; column_major.len()];
    for (c, column) in column_major.chunks_exact(rows).enumerate() {
        for (r, &v) in column.iter().enumerate() {
            row_major[c + r * cols] = v;
        }
    }
    row_major
}
