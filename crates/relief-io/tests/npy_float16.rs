//! float16 NumPy grids: a `.npy` or `.npz` of float16 reads as its exact f32 values through
//! every public reader, names its type `float16`, and refuses its infinities and NaN.

mod common;

use common::TestDir;
use half::f16;
use relief_io::npy::{read_npy, read_npy_height_field, read_npz};
use relief_io::{read_raster, IoError, ReadOptions};
use std::io::Write;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

/// A version 1.0 `.npy` file of float16 `values` of `shape` (C order), in either byte order.
fn f16_npy(values: &[f32], shape: &str, big_endian: bool) -> Vec<u8> {
    let descr = if big_endian { ">f2" } else { "<f2" };
    let mut dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    while (10 + dict.len() + 1) % 64 != 0 {
        dict.push(' ');
    }
    dict.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    bytes.extend_from_slice(dict.as_bytes());
    for &v in values {
        let v = f16::from_f32(v);
        bytes.extend_from_slice(&if big_endian { v.to_be_bytes() } else { v.to_le_bytes() });
    }
    bytes
}

/// Values that float16 holds exactly: zero, a fraction, a negative, the largest finite one.
const VALUES: [f32; 6] = [0.0, 0.5, -3.25, 1024.0, 65504.0, 12.125];

#[test]
fn float16_npy_reads_exactly_through_every_reader() {
    let dir = TestDir::new("npy-f16");
    for big_endian in [false, true] {
        let path = dir.file("half.npy", &f16_npy(&VALUES, "(2, 3)", big_endian));
        let raster = read_npy(&path, &ReadOptions::default()).unwrap();
        assert_eq!((raster.width, raster.height), (3, 2));
        assert_eq!(raster.samples, VALUES);
        assert_eq!(raster.info.sample_type, "float16");
        assert_eq!(read_raster(&path, &ReadOptions::default()).unwrap().samples, VALUES);
        assert_eq!(read_npy_height_field(&path).unwrap().samples(), &VALUES[..]);
    }
}

#[test]
fn float16_npz_member_reads_exactly() {
    let dir = TestDir::new("npz-f16");
    for method in [CompressionMethod::Stored, CompressionMethod::Deflated] {
        let mut zip = ZipWriter::new(std::io::Cursor::new(Vec::new()));
        let options = SimpleFileOptions::default().compression_method(method);
        zip.start_file("heights.npy", options).unwrap();
        zip.write_all(&f16_npy(&VALUES, "(3, 2)", false)).unwrap();
        let path = dir.file("arrays.npz", &zip.finish().unwrap().into_inner());
        let raster = read_npz(&path, &ReadOptions::default()).unwrap();
        assert_eq!((raster.width, raster.height), (2, 3));
        assert_eq!(raster.samples, VALUES);
        assert_eq!(raster.info.sample_type, "float16");
    }
}

#[test]
fn float16_infinities_nan_and_short_data_are_refused_by_cause() {
    let dir = TestDir::new("npy-f16-bad");
    for bad in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN, 1e6] {
        // 1e6 is beyond float16's range: it is stored as infinity.
        let path = dir.file("bad.npy", &f16_npy(&[1.0, 2.0, bad, 4.0], "(2, 2)", false));
        let err = read_npy(&path, &ReadOptions::default()).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{bad}: {err}");
        assert!(err.to_string().contains("column 0, row 1"), "{err}");
    }
    let mut short = f16_npy(&VALUES, "(2, 3)", false);
    short.pop();
    let path = dir.file("short.npy", &short);
    let err = read_npy(&path, &ReadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::Format { .. }), "{err}");
    assert!(err.to_string().contains("2-byte elements needs 12 data bytes"), "{err}");
}
