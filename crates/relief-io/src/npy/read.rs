//! Reading a 2D NumPy `.npy` array: the streaming decoder shared by `.npy` and `.npz` readers.

use crate::format_error::FormatError;
use crate::npy::header::{read_header, Dtype, ScalarKind};
use crate::raster::ReadOptions;
use crate::sample_type::SampleOrder;
use crate::IoError;
use half::f16;
use std::io::{ErrorKind, Read};
use std::path::Path;

/// Bytes decoded at a time; a multiple of every element size.
const CHUNK: usize = 1 << 16;

/// Reads the 2D `.npy` array at `path` as f32 values, row-major, without judging them:
/// how a depth image (`+inf` where a ray missed) is read back. Returns (rows, columns,
/// values). The elements and errors are those of [`read_npy`](crate::npy::read_npy), except that
/// no value is refused.
pub fn read_npy_f32_array(
    path: &Path,
    options: &ReadOptions,
) -> Result<(usize, usize, Vec<f32>), IoError> {
    let (file, len) = crate::input_file::open_input(path)?;
    let array =
        read_npy_array_from(std::io::BufReader::new(file), len, options).map_err(|e| e.at(path))?;
    Ok((array.rows, array.cols, array.samples))
}

/// A 2D array decoded to f32, row-major whatever the file's memory order.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct NpyArray {
    /// Rows (the first dimension).
    pub rows: usize,
    /// Columns (the second dimension).
    pub cols: usize,
    /// `rows * cols` elements, row-major, as f32 (not yet checked for being finite).
    pub samples: Vec<f32>,
    /// The stored element type.
    pub dtype: Dtype,
}

/// Reads a 2D `.npy` array of `len` bytes from `reader`, streaming: the header's shape must
/// agree with `len` and pass [`ReadOptions::check_size`] before the samples are allocated,
/// and exactly the data bytes are read (nothing past them); errors do not name the file.
pub(crate) fn read_npy_array_from<R: Read>(
    mut reader: R,
    len: u64,
    options: &ReadOptions,
) -> Result<NpyArray, FormatError> {
    let header = read_header(&mut reader, len)?;
    let (rows, cols) = match header.shape[..] {
        [rows, cols] => (rows, cols),
        ref shape => {
            return Err(FormatError::Unsupported(format!(
                "{}-dimensional array of shape {shape:?}; need 2 dimensions",
                shape.len()
            )))
        }
    };
    if rows == 0 || cols == 0 {
        return Err(FormatError::Format(format!("array of shape ({rows}, {cols}) is empty")));
    }
    let size = header.dtype.size();
    let data_len = len.saturating_sub(header.data_offset);
    let needed = rows.checked_mul(cols).and_then(|n| n.checked_mul(size as u64));
    if needed != Some(data_len) {
        return Err(FormatError::Format(format!(
                "shape ({rows}, {cols}) of {size}-byte elements needs {} data bytes, the file has {data_len}",
                needed.map_or("more than 2^64".into(), |n| n.to_string())
            ),
        ));
    }
    options.check_samples(cols, rows)?;
    let (Ok(rows), Ok(cols)) = (usize::try_from(rows), usize::try_from(cols)) else {
        return Err(FormatError::Unsupported(format!("shape ({rows}, {cols}) on this machine")));
    };
    let samples = decode(&mut reader, header.dtype, rows, cols, header.fortran_order)?;
    Ok(NpyArray { rows, cols, samples, dtype: header.dtype })
}

/// Reads the `rows * cols` elements of `dtype` from `reader` as f32 into row-major order.
/// When `fortran` says the file stores the array column by column, each chunk is scattered to
/// its row-major places, so no second copy of the array is made.
fn decode(
    reader: &mut impl Read,
    dtype: Dtype,
    rows: usize,
    cols: usize,
    fortran: bool,
) -> Result<Vec<f32>, FormatError> {
    let size = dtype.size();
    let count = rows * cols;
    let mut samples = vec![0f32; count];
    let mut bytes = vec![0u8; CHUNK];
    let mut read_chunk = |chunk: &mut [u8]| {
        reader.read_exact(chunk).map_err(|e| match e.kind() {
            ErrorKind::UnexpectedEof => FormatError::Format("truncated in the data".into()),
            _ => FormatError::Io(e),
        })
    };
    if !fortran {
        for out in samples.chunks_mut(CHUNK / size) {
            let chunk = &mut bytes[..out.len() * size];
            read_chunk(chunk)?;
            convert(chunk, dtype, out);
        }
    } else {
        let mut column_major = vec![0f32; CHUNK / size];
        let mut done = 0;
        while done < count {
            let n = (count - done).min(column_major.len());
            let chunk = &mut bytes[..n * size];
            read_chunk(chunk)?;
            convert(chunk, dtype, &mut column_major[..n]);
            for (k, &v) in (done..).zip(&column_major[..n]) {
                samples[k / rows + (k % rows) * cols] = v;
            }
            done += n;
        }
    }
    Ok(samples)
}

/// Converts the elements in `bytes` to f32 into `out` (float16 exactly, as every f16 is an f32).
pub(crate) fn convert(bytes: &[u8], dtype: Dtype, out: &mut [f32]) {
    let order = if dtype.big_endian { SampleOrder::Big } else { SampleOrder::Little };
    match dtype.kind {
        ScalarKind::Sample(sample) => sample.decode(bytes, order, out),
        ScalarKind::F16 => {
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(2)) {
                let raw = [b[0], b[1]];
                let bits = match order {
                    SampleOrder::Big => u16::from_be_bytes(raw),
                    _ => u16::from_le_bytes(raw),
                };
                *o = f16::from_bits(bits).to_f32();
            }
        }
    }
}

#[cfg(test)]
#[path = "read_tests.rs"]
mod tests;
