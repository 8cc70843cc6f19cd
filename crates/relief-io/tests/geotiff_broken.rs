//! GeoTIFFs that relief refuses, by cause: truncated, corrupted, of the wrong magic, claiming
//! a huge raster, of zero size, of several bands or other layouts, with NaN samples that no
//! nodata declares; and big-endian files read like little-endian ones.

mod common;
#[path = "common/geotiff_cases.rs"]
mod geotiff_cases;
#[path = "common/peak_heap.rs"]
mod peak_heap;

use common::TestDir;
use geotiff_cases::*;
use peak_heap::peak_heap;

use relief_io::geotiff::read_geotiff;
use relief_io::{IoError, ReadOptions};
use std::io::ErrorKind;
use tiff::encoder::colortype;
use tiff::encoder::compression::DeflateLevel;
use tiff::encoder::{Compression, Predictor};
use tiff::tags::Tag;

// ---------------------------------------------------------------------------------------------
// Broken and unsupported files.

#[test]
fn every_truncation_of_the_fixture_is_an_error() {
    let dir = TestDir::new("truncated");
    let good = std::fs::read(fixture()).unwrap();
    let mut cuts: Vec<usize> = (0..4096).collect();
    cuts.extend([5000, 20_000, 100_000, 163_656, 163_657, 170_000, good.len() - 1]);
    for len in cuts {
        let path = dir.file("cut.tif", &good[..len]);
        match read_geotiff(&path, &options()) {
            Err(IoError::Format { .. }) => {}
            other => panic!("prefix of {len} bytes: {other:?}"),
        }
    }
}

#[test]
fn corrupted_tiles_are_refused_or_read_at_their_size_as_their_codec_allows() {
    let dir = TestDir::new("corrupt");
    let samples = Samples {
        bytes: (0..40 * 30).flat_map(|i: u32| (i as f32 * 0.5).to_ne_bytes()).collect(),
        size: 4,
        bits: 32,
        format: 3,
    };
    // The fewest of 400 copies, 4 bytes changed in each, a codec must refuse. Deflate tiles
    // are zlib streams whose Adler-32 sees any change; LZW and PackBits carry no checksum, so
    // a change inside a tile reads as other heights (PackBits tiles are mostly raw samples),
    // and only changes to the header, the tile tables or the codes' structure are refused.
    let files = [
        (encode_tiles(&samples, (40, 30), 16, TileCodec::Deflate, 3, &projected()), 390),
        (encode_tiles(&samples, (40, 30), 16, TileCodec::Lzw, 1, &projected()), 300),
        (encode_tiles(&samples, (40, 30), 16, TileCodec::PackBits, 1, &projected()), 30),
    ];
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for (good, min_refused) in &files {
        assert!(read_geotiff(&dir.file("good.tif", good), &options()).is_ok());
        let mut refused = 0;
        for _ in 0..400 {
            let mut bad = good.clone();
            for _ in 0..4 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let at = (state % bad.len() as u64) as usize;
                bad[at] = (state >> 40) as u8;
            }
            match read_geotiff(&dir.file("bad.tif", &bad), &options()) {
                Err(_) => refused += 1,
                // The tile tables must match the size, so a copy that reads has the size that
                // was written, every sample a height (no nodata is declared).
                Ok(r) => {
                    assert_eq!((r.width, r.height, r.samples.len()), (40, 30, 1200));
                    assert!(r.samples.iter().all(|v| v.is_finite()));
                }
            }
        }
        assert!(refused >= *min_refused, "{refused} of 400 refused, fewer than {min_refused}");
    }
}

#[test]
fn wrong_magic_empty_file_directory_and_missing_file() {
    let dir = TestDir::new("paths");
    let mut bytes = std::fs::read(fixture()).unwrap();
    bytes[..2].copy_from_slice(b"XX");
    let err = read_geotiff(&dir.file("magic.tif", &bytes), &options()).unwrap_err();
    assert!(
        matches!(err, IoError::Format { .. }) && err.to_string().contains("not a TIFF"),
        "{err}"
    );
    bytes[..4].copy_from_slice(b"II\x29\x00");
    assert!(matches!(
        read_geotiff(&dir.file("v41.tif", &bytes), &options()),
        Err(IoError::Format { .. })
    ));
    let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR";
    assert!(matches!(
        read_geotiff(&dir.file("png.tif", png), &options()),
        Err(IoError::Format { .. })
    ));
    let err = read_geotiff(&dir.file("empty.tif", b""), &options()).unwrap_err();
    assert!(matches!(err, IoError::Format { .. }), "{err}");
    let err = read_geotiff(dir.path(), &options()).unwrap_err();
    assert!(
        matches!(&err, IoError::Io { source, .. } if source.kind() == ErrorKind::IsADirectory),
        "{err}"
    );
    let err = read_geotiff(&dir.join("absent.tif"), &options()).unwrap_err();
    assert!(
        matches!(&err, IoError::Io { source, .. } if source.kind() == ErrorKind::NotFound),
        "{err}"
    );
}

/// A little-endian TIFF of one IFD with `entries` (tag, type, count, value), sorted by tag.
fn hand_made_tiff(entries: &[(u16, u16, u32, u32)], trailing: &[u8]) -> Vec<u8> {
    let mut bytes = b"II\x2a\x00\x08\x00\x00\x00".to_vec();
    bytes.extend((entries.len() as u16).to_le_bytes());
    for &(tag, kind, count, value) in entries {
        bytes.extend(tag.to_le_bytes());
        bytes.extend(kind.to_le_bytes());
        bytes.extend(count.to_le_bytes());
        bytes.extend(value.to_le_bytes());
    }
    bytes.extend(0u32.to_le_bytes());
    bytes.extend(trailing);
    bytes
}

#[test]
fn a_tiny_file_claiming_a_huge_raster_is_refused_before_allocating() {
    let dir = TestDir::new("huge");
    const SHORT: u16 = 3;
    const LONG: u16 = 4;
    let data_at = 8 + 2 + 9 * 12 + 4;
    let bytes = hand_made_tiff(
        &[
            (256, LONG, 1, 100_000),       // ImageWidth
            (257, LONG, 1, 100_000),       // ImageLength
            (258, SHORT, 1, 16),           // BitsPerSample
            (259, SHORT, 1, 1),            // Compression: none
            (262, SHORT, 1, 1),            // BlackIsZero
            (273, LONG, 1, data_at),       // StripOffsets
            (277, SHORT, 1, 1),            // SamplesPerPixel
            (278, LONG, 1, 100_000),       // RowsPerStrip
            (279, LONG, 1, 4_000_000_000), // StripByteCounts
        ],
        &[0; 16],
    );
    let path = dir.file("huge.tif", &bytes);
    let (result, peak) = peak_heap(|| read_geotiff(&path, &options()));
    let err = result.unwrap_err();
    assert!(matches!(err, IoError::Limits { width: 100_000, height: 100_000, .. }), "{err}");
    assert!(peak < 1 << 20, "reading the header took {peak} bytes");
    // With the default budget, whatever the machine: refused as over the limit or as a file
    // too short for its data, never allocated.
    let (result, peak) = peak_heap(|| read_geotiff(&path, &ReadOptions::default()));
    assert!(matches!(result, Err(IoError::Limits { .. } | IoError::Format { .. })), "{result:?}");
    assert!(peak < 1 << 20, "reading the header took {peak} bytes");
    // Within the budget but larger than the file holds: refused before allocating too.
    let small = ReadOptions { max_memory: 1 << 40, ..ReadOptions::default() };
    let (result, peak) = peak_heap(|| read_geotiff(&path, &small));
    assert!(matches!(result, Err(IoError::Format { .. })), "{result:?}");
    assert!(peak < 1 << 20, "reading the header took {peak} bytes");
}

#[test]
fn zero_sized_raster_is_a_format_error() {
    let dir = TestDir::new("zero");
    let bytes = hand_made_tiff(
        &[
            (256, 4, 1, 0),
            (257, 4, 1, 5),
            (258, 3, 1, 8),
            (262, 3, 1, 1),
            (273, 4, 1, 8),
            (279, 4, 1, 0),
        ],
        &[],
    );
    let err = read_geotiff(&dir.file("zero.tif", &bytes), &options()).unwrap_err();
    assert!(matches!(err, IoError::Format { .. }), "{err}");
}

#[test]
fn rgb_images_and_other_layouts_are_unsupported() {
    let dir = TestDir::new("unsupported");
    let rgb = encode_strips::<colortype::RGB8>(
        &[0; 4 * 3 * 3],
        (4, 3),
        Compression::Deflate(DeflateLevel::Fast),
        Predictor::None,
        None,
        &projected(),
    );
    let err = read_geotiff(&dir.file("rgb.tif", &rgb), &options()).unwrap_err();
    assert!(
        matches!(err, IoError::Unsupported { .. }) && err.to_string().contains("3 bands"),
        "{err}"
    );
    // JPEG compression (code 7) is not decoded.
    let samples = Samples { bytes: vec![0; 16 * 16], size: 1, bits: 8, format: 1 };
    let mut jpeg = encode_tiles(&samples, (16, 16), 16, TileCodec::None, 1, &[]);
    let at = entry_value_at(&jpeg, Tag::Compression.to_u16());
    jpeg[at..at + 2].copy_from_slice(&7u16.to_le_bytes());
    let err = read_geotiff(&dir.file("jpeg.tif", &jpeg), &options()).unwrap_err();
    assert!(matches!(err, IoError::Unsupported { .. }) && err.to_string().contains("7"), "{err}");
    // 16-bit floats are not read.
    let half = Samples { bytes: vec![0; 16 * 16 * 2], size: 2, bits: 16, format: 3 };
    let bytes = encode_tiles(&half, (16, 16), 16, TileCodec::None, 1, &[]);
    let err = read_geotiff(&dir.file("half.tif", &bytes), &options()).unwrap_err();
    assert!(
        matches!(err, IoError::Unsupported { .. }) && err.to_string().contains("16-bit"),
        "{err}"
    );
}

#[test]
fn nan_without_nodata_is_refused_naming_its_place() {
    let dir = TestDir::new("nan");
    let mut values = vec![0.5f32; 6 * 4];
    values[4 + 2 * 6] = f32::NAN;
    let bytes = encode_strips::<colortype::Gray32Float>(
        &values,
        (6, 4),
        Compression::Lzw,
        Predictor::None,
        None,
        &projected(),
    );
    let err = read_geotiff(&dir.file("nan.tif", &bytes), &options()).unwrap_err();
    assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    assert!(err.to_string().contains("column 4, row 2"), "{err}");
    // An infinity that is not the nodata value is refused too.
    values[4 + 2 * 6] = f32::INFINITY;
    let mut extras = projected();
    extras.push(Extra::Ascii(Tag::GdalNodata, "-9999"));
    let bytes = encode_strips::<colortype::Gray32Float>(
        &values,
        (6, 4),
        Compression::Uncompressed,
        Predictor::None,
        None,
        &extras,
    );
    let err = read_geotiff(&dir.file("inf.tif", &bytes), &options()).unwrap_err();
    assert!(
        matches!(err, IoError::InvalidData { .. }) && err.to_string().contains("column 4, row 2"),
        "{err}"
    );
}

#[test]
fn big_endian_files_read_like_little_endian_ones() {
    let dir = TestDir::new("big-endian");
    // "MM", version 42, the IFD at 8; entries of (tag, type, count, value) with SHORT values
    // left-justified in their 4-byte field; then 3 x 2 int16 samples, big-endian.
    let values: [i16; 6] = [-300, 2, 1000, -5, 32767, -32768];
    let entries: [(u16, u16, u32); 10] = [
        (256, 3, 3),   // ImageWidth
        (257, 3, 2),   // ImageLength
        (258, 3, 16),  // BitsPerSample
        (259, 3, 1),   // no compression
        (262, 3, 1),   // BlackIsZero
        (273, 4, 0),   // StripOffsets, patched below
        (277, 3, 1),   // SamplesPerPixel
        (279, 4, 12),  // StripByteCounts
        (339, 3, 2),   // SampleFormat: signed
        (42113, 2, 0), // GDAL_NODATA "-5", inline
    ];
    let data_at = 8 + 2 + entries.len() as u32 * 12 + 4;
    let mut bytes = b"MM\x00\x2a\x00\x00\x00\x08".to_vec();
    bytes.extend((entries.len() as u16).to_be_bytes());
    for (tag, kind, value) in entries {
        bytes.extend(tag.to_be_bytes());
        bytes.extend(kind.to_be_bytes());
        let count: u32 = if kind == 2 { 3 } else { 1 };
        bytes.extend(count.to_be_bytes());
        match (tag, kind) {
            (273, _) => bytes.extend(data_at.to_be_bytes()),
            (_, 2) => bytes.extend(b"-5\0\0"),
            (_, 3) => bytes.extend([(value as u16).to_be_bytes(), [0, 0]].concat()),
            _ => bytes.extend(value.to_be_bytes()),
        }
    }
    bytes.extend(0u32.to_be_bytes());
    bytes.extend(values.iter().flat_map(|v| v.to_be_bytes()));
    let raster = read_geotiff(&dir.file("be.tif", &bytes), &options()).unwrap();
    assert_eq!(raster.info.sample_type, "int16");
    assert_eq!(raster.info.nodata, Some(-5.0));
    let expected = [f32::NAN, 32767.0, -32768.0, -300.0, 2.0, 1000.0];
    for (got, want) in raster.samples.iter().zip(expected) {
        assert!(*got == want || got.is_nan() && want.is_nan(), "{:?}", raster.samples);
    }
}
