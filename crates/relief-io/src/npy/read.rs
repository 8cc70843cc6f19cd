//! Reading a 2D NumPy `.npy` array: the streaming decoder shared by `.npy` and `.npz` readers.

use crate::npy::header::{read_header, Dtype, ScalarKind};
use crate::raster::{ReadOptions, VoidPolicy};
use crate::sample_type::SampleType;
use crate::IoError;
use half::f16;
use relief_core::HeightField;
use std::io::{ErrorKind, Read};
use std::path::Path;

/// Bytes decoded at a time; a multiple of every element size.
const CHUNK: usize = 1 << 16;

/// Reads the 2D `.npy` array at `path` as a height field with [`GridGeometry::unit`].
///
/// Array row `r` becomes grid row `r` (no flip) and array column `c` grid column `c`.
/// Elements may be int8, uint8, int16, uint16, int32, uint32, int64, uint64, float16, float32
/// or float64, little- or big-endian, in C or Fortran order; they are converted to f32. The
/// default [`ReadOptions`] apply (see [`read_npy`](crate::read_npy) for the raster with options).
///
/// Errors: [`IoError::Io`] when the file cannot be read, [`IoError::Format`] for a malformed or
/// truncated file, an empty array, or a shape that disagrees with the data length,
/// [`IoError::Unsupported`] for other dtypes or a number of dimensions other than 2,
/// [`IoError::Limits`] for an array over the memory budget, and [`IoError::InvalidData`]
/// naming the first NaN or infinite sample.
///
/// [`GridGeometry::unit`]: relief_core::GridGeometry::unit
pub fn read_npy_height_field(path: &Path) -> Result<HeightField, IoError> {
    crate::npy::raster::read_npy(path, &ReadOptions::default())?
        .into_height_field(path, VoidPolicy::Fill)
}

/// Reads the 2D `.npy` array at `path` as f32 values, row-major, without judging them:
/// how a depth image (`+inf` where a ray missed) is read back. Returns (rows, columns,
/// values). The elements and errors are those of [`read_npy`](crate::read_npy), except that
/// no value is refused.
pub fn read_npy_f32_array(
    path: &Path,
    options: &ReadOptions,
) -> Result<(usize, usize, Vec<f32>), IoError> {
    let (file, len) = crate::input_file::open_input(path)?;
    let array = read_npy_array_from(std::io::BufReader::new(file), len, path, options)?;
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
/// and exactly the data bytes are read (nothing past them). `path` names the file in errors.
pub(crate) fn read_npy_array_from<R: Read>(
    mut reader: R,
    len: u64,
    path: &Path,
    options: &ReadOptions,
) -> Result<NpyArray, IoError> {
    let header = read_header(path, &mut reader, len)?;
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
    let data_len = len.saturating_sub(header.data_offset);
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
    options.check_size(path, cols, rows)?;
    let (Ok(rows), Ok(cols)) = (usize::try_from(rows), usize::try_from(cols)) else {
        return Err(IoError::unsupported(path, format!("shape ({rows}, {cols}) on this machine")));
    };
    let samples = decode(path, &mut reader, header.dtype, rows, cols, header.fortran_order)?;
    Ok(NpyArray { rows, cols, samples, dtype: header.dtype })
}

/// Reads the `rows * cols` elements of `dtype` from `reader` as f32 into row-major order.
/// When `fortran` says the file stores the array column by column, each chunk is scattered to
/// its row-major places, so no second copy of the array is made.
fn decode(
    path: &Path,
    reader: &mut impl Read,
    dtype: Dtype,
    rows: usize,
    cols: usize,
    fortran: bool,
) -> Result<Vec<f32>, IoError> {
    let size = dtype.size();
    let count = rows * cols;
    let mut samples = vec![0f32; count];
    let mut bytes = vec![0u8; CHUNK];
    let mut read_chunk = |chunk: &mut [u8]| {
        reader.read_exact(chunk).map_err(|e| match e.kind() {
            ErrorKind::UnexpectedEof => IoError::format(path, "truncated in the data"),
            _ => IoError::io(path, e),
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
    macro_rules! each {
        ($t:ty) => {
            each!($t, |v: $t| v as f32)
        };
        ($t:ty, $to_f32:expr) => {{
            const N: usize = std::mem::size_of::<$t>();
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(N)) {
                let mut raw = [0u8; N];
                raw.copy_from_slice(b);
                let v = if dtype.big_endian {
                    <$t>::from_be_bytes(raw)
                } else {
                    <$t>::from_le_bytes(raw)
                };
                *o = $to_f32(v);
            }
        }};
    }
    match dtype.kind {
        ScalarKind::Sample(sample) => match sample {
            SampleType::I8 => each!(i8),
            SampleType::U8 => each!(u8),
            SampleType::I16 => each!(i16),
            SampleType::U16 => each!(u16),
            SampleType::I32 => each!(i32),
            SampleType::U32 => each!(u32),
            SampleType::I64 => each!(i64),
            SampleType::U64 => each!(u64),
            SampleType::F32 => each!(f32),
            SampleType::F64 => each!(f64),
        },
        ScalarKind::F16 => each!(u16, |bits| f16::from_bits(bits).to_f32()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;
    use relief_core::GridGeometry;

    #[test]
    fn f32_arrays_keep_infinities() {
        let dir = TestDir::new("npy-f32-array");
        let path = dir.path().join("depth.npy");
        let depth = [1.5, f32::INFINITY, 0.0, 7.25, f32::INFINITY, 2.0];
        crate::write_npy_f32(&path, &[2, 3], &depth).unwrap();
        let (rows, cols, values) = read_npy_f32_array(&path, &ReadOptions::default()).unwrap();
        assert_eq!((rows, cols, values.as_slice()), (2, 3, &depth[..]));
        // The height-field reader refuses the same file.
        assert!(read_npy_height_field(&path).is_err());
    }

    /// A version 1.0 `.npy` file with the given header fields and raw data.
    fn npy(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
        let order = if fortran { "True" } else { "False" };
        let mut dict =
            format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': {shape}, }}");
        while (10 + dict.len() + 1) % 64 != 0 {
            dict.push(' ');
        }
        dict.push('\n');
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend_from_slice(&(dict.len() as u16).to_le_bytes());
        bytes.extend_from_slice(dict.as_bytes());
        bytes.extend_from_slice(data);
        bytes
    }

    fn read_bytes(dir: &TestDir, bytes: &[u8]) -> Result<HeightField, IoError> {
        let path = dir.path().join("grid.npy");
        std::fs::write(&path, bytes).unwrap();
        read_npy_height_field(&path)
    }

    type Encode = fn(&[f64], bool) -> Vec<u8>;

    macro_rules! case {
        ($code:literal, $t:ty, [$($v:expr),*]) => {
            ($code, vec![$($v as f64),*], (|values: &[f64], big: bool| {
                values.iter().flat_map(|&v| {
                    let v = v as $t;
                    if big { v.to_be_bytes() } else { v.to_le_bytes() }
                }).collect()
            }) as Encode)
        };
    }

    #[test]
    fn reads_every_dtype_in_both_byte_orders_and_both_memory_orders() {
        let dir = TestDir::new("npy-dtypes");
        let cases = [
            case!("i1", i8, [-128, 127, 0, 1, -1, 5]),
            case!("u1", u8, [0, 255, 1, 2, 3, 4]),
            case!("i2", i16, [-32768, 32767, 0, 1, -1, 300]),
            case!("u2", u16, [0, 65535, 1, 2, 3, 300]),
            case!("i4", i32, [i32::MIN, i32::MAX, 0, 1, -1, 70000]),
            case!("u4", u32, [0, u32::MAX, 1, 2, 3, 70000]),
            case!("i8", i64, [-(1i64 << 40), 1i64 << 40, 0, 1, -1, 7]),
            case!("u8", u64, [0, 1u64 << 50, 1, 2, 3, 7]),
            case!("f4", f32, [-1.5, 2.25, 1e30, 0, -0.125, 3]),
            case!("f8", f64, [0.1, -1e10, 1e-3, 0, 2.5, -7]),
        ];
        for (code, values, encode) in cases {
            // values are row-major for shape (2, 3): row r = grid row r.
            let expected: Vec<f32> = values.iter().map(|&v| v as f32).collect();
            let column_major: Vec<f64> = (0..6).map(|k| values[(k % 2) * 3 + k / 2]).collect();
            for (order, big) in [("<", false), (">", true), ("|", cfg!(target_endian = "big"))] {
                if order == "|" && !code.ends_with('1') {
                    continue;
                }
                let descr = format!("{order}{code}");
                for fortran in [false, true] {
                    let data = encode(if fortran { &column_major } else { &values }, big);
                    let field = read_bytes(&dir, &npy(&descr, fortran, "(2, 3)", &data))
                        .unwrap_or_else(|e| panic!("{descr} fortran={fortran}: {e}"));
                    assert_eq!((field.width(), field.height()), (3, 2), "{descr}");
                    assert_eq!(field.samples(), &expected[..], "{descr} fortran={fortran}");
                    assert_eq!(field.geometry(), &GridGeometry::unit());
                }
            }
        }
    }

    #[test]
    fn reads_float16_in_both_byte_orders_and_both_memory_orders() {
        let dir = TestDir::new("npy-f16");
        // Exact in float16: subnormal, negative zero, the largest finite value, a fraction.
        let values = [5.9604645e-8f32, -0.0, 65504.0, -1.5, 0.099975586, 2048.0];
        let halves = values.map(f16::from_f32);
        assert_eq!(halves.map(f16::to_f32), values, "the values are exact float16s");
        let column_major: Vec<f16> = (0..6).map(|k| halves[(k % 2) * 3 + k / 2]).collect();
        for (order, big) in [("<", false), (">", true)] {
            for fortran in [false, true] {
                let stored = if fortran { &column_major[..] } else { &halves[..] };
                let data: Vec<u8> = stored
                    .iter()
                    .flat_map(|v| if big { v.to_be_bytes() } else { v.to_le_bytes() })
                    .collect();
                let bytes = npy(&format!("{order}f2"), fortran, "(2, 3)", &data);
                let field = read_bytes(&dir, &bytes)
                    .unwrap_or_else(|e| panic!("{order}f2 fortran={fortran}: {e}"));
                assert_eq!((field.width(), field.height()), (3, 2));
                let bits: Vec<u32> = field.samples().iter().map(|v| v.to_bits()).collect();
                assert_eq!(bits, values.map(f32::to_bits), "{order}f2 fortran={fortran}");
            }
        }
        // float16 infinities and NaN are refused like float32 ones.
        for bad in [f16::INFINITY, f16::NEG_INFINITY, f16::NAN] {
            let data: Vec<u8> = [f16::ONE, bad].iter().flat_map(|v| v.to_le_bytes()).collect();
            let err = read_bytes(&dir, &npy("<f2", false, "(1, 2)", &data)).unwrap_err();
            assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
            assert!(err.to_string().contains("column 1, row 0"), "{err}");
        }
    }

    #[test]
    fn refuses_broken_files_with_the_right_variant() {
        let dir = TestDir::new("npy-broken");
        let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let six = f32s(&[0.0; 6]);
        let is_format = |r: Result<HeightField, IoError>| matches!(r, Err(IoError::Format { .. }));
        let is_unsupported =
            |r: Result<HeightField, IoError>| matches!(r, Err(IoError::Unsupported { .. }));
        // Truncated data, and too much data for the shape.
        assert!(is_format(read_bytes(&dir, &npy("<f4", false, "(2, 3)", &six[..20]))));
        assert!(is_format(read_bytes(&dir, &npy("<f4", false, "(2, 2)", &six))));
        // Truncated preamble, wrong magic, empty array.
        assert!(is_format(read_bytes(&dir, b"\x93NUM")));
        let mut wrong_magic = npy("<f4", false, "(2, 3)", &six);
        wrong_magic[1] = b'X';
        assert!(is_format(read_bytes(&dir, &wrong_magic)));
        assert!(is_format(read_bytes(&dir, &npy("<f4", false, "(0, 3)", &[]))));
        // Shapes whose byte count overflows.
        let huge = "(18446744073709551615, 18446744073709551615)";
        assert!(is_format(read_bytes(&dir, &npy("<f4", false, huge, &six))));
        // Wrong number of dimensions, unsupported dtype.
        assert!(is_unsupported(read_bytes(&dir, &npy("<f4", false, "(1, 2, 3)", &six))));
        assert!(is_unsupported(read_bytes(&dir, &npy("<f4", false, "(6,)", &six))));
        assert!(is_unsupported(read_bytes(&dir, &npy("<c8", false, "(2, 3)", &six))));
        assert!(is_unsupported(read_bytes(&dir, &npy("<f16", false, "(2, 3)", &six))));
    }

    #[test]
    fn names_the_first_non_finite_sample() {
        let dir = TestDir::new("npy-nan");
        let mut values = [1.0f32; 6];
        values[5] = f32::NAN;
        values[4] = f32::INFINITY;
        let data: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        let err = read_bytes(&dir, &npy("<f4", false, "(2, 3)", &data)).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        assert!(err.to_string().contains("column 1, row 1"), "{err}");
        // A finite f64 beyond f32's range is refused too.
        let data: Vec<u8> = [0.0f64, 1e300].iter().flat_map(|x| x.to_le_bytes()).collect();
        let err = read_bytes(&dir, &npy("<f8", false, "(1, 2)", &data)).unwrap_err();
        assert!(err.to_string().contains("column 1, row 0"), "{err}");
    }

    #[test]
    fn missing_file_and_directory_are_io_errors() {
        let dir = TestDir::new("npy-paths");
        let err = read_npy_height_field(&dir.path().join("absent.npy")).unwrap_err();
        assert!(
            matches!(&err, IoError::Io { source, .. } if source.kind() == ErrorKind::NotFound),
            "{err}"
        );
        let err = read_npy_height_field(dir.path()).unwrap_err();
        assert!(
            matches!(&err, IoError::Io { source, .. } if source.kind() == ErrorKind::IsADirectory),
            "{err}"
        );
        assert!(err.to_string().contains(&dir.path().display().to_string()));
    }

    #[test]
    fn truncations_are_refused_and_corruptions_refused_or_read_at_the_declared_size() {
        let dir = TestDir::new("npy-fuzz");
        let data: Vec<u8> = (0..6i16).flat_map(|v| v.to_be_bytes()).collect();
        let good = npy(">i2", true, "(2, 3)", &data);
        assert!(read_bytes(&dir, &good).is_ok());
        for len in 0..good.len() {
            assert!(read_bytes(&dir, &good[..len]).is_err(), "prefix of {len} bytes accepted");
        }
        // No checksum: a copy whose changes all land in the 12 data bytes reads (any i16 is a
        // height), about 1 copy in 1700; a changed header byte is refused, as the header's
        // text must parse and its shape must fit the data exactly. So whatever reads is 3 x 2.
        let mut accepted = 0;
        for bad in crate::test_corruption::corrupted_copies(&good, 2000, 3) {
            if let Ok(field) = read_bytes(&dir, &bad) {
                assert_eq!((field.width(), field.height()), (3, 2));
                accepted += 1;
            }
        }
        assert!(accepted <= 10, "{accepted} of 2000 corrupted copies read");
    }
}
