//! Tests of the `.npy` decoder: every dtype, byte order and memory order, broken and
//! corrupted files refused by cause.

use super::*;
use crate::npy::{read_npy_height_field, write_npy_f32};
use crate::test_dir::TestDir;
use relief_core::{GridGeometry, HeightField};

#[test]
fn f32_arrays_keep_infinities() {
    let dir = TestDir::new("npy-f32-array");
    let path = dir.path().join("depth.npy");
    let depth = [1.5, f32::INFINITY, 0.0, 7.25, f32::INFINITY, 2.0];
    write_npy_f32(&path, &[2, 3], &depth).unwrap();
    let (rows, cols, values) = read_npy_f32_array(&path, &ReadOptions::default()).unwrap();
    assert_eq!((rows, cols, values.as_slice()), (2, 3, &depth[..]));
    // The height-field reader refuses the same file.
    assert!(read_npy_height_field(&path).is_err());
}

/// A version 1.0 `.npy` file with the given header fields and raw data.
fn npy(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
    let order = if fortran { "True" } else { "False" };
    let mut dict = format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': {shape}, }}");
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
