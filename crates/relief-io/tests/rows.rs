//! Rasters read as rows (`open_rows`): every row band equals the same rows of `read_raster`,
//! for GeoTIFF strips and tiles of every codec, SRTM tiles and `.npy` arrays (streamed) and
//! the formats served from memory; bad requests are errors.

mod common;
#[path = "common/tiff_files.rs"]
mod tiff_files;

use common::TestDir;
use proptest::prelude::*;
use relief_core::{GridGeometry, HeightField};
use relief_io::{open_rows, read_raster, IoError, Raster, ReadOptions, RowSource};
use std::path::{Path, PathBuf};
use tiff::encoder::colortype::{Gray32Float, GrayI16};
use tiff::encoder::compression::{CompressionAlgorithm, Deflate, DeflateLevel};
use tiff::encoder::{Compression, Predictor};
use tiff::tags::Tag;
use tiff_files::{
    encode_f32_tiles, encode_predicted_strips, encode_strips, projected, Extra, TileCodec,
};

fn options() -> ReadOptions {
    ReadOptions { max_memory: 1 << 30, ..ReadOptions::default() }
}

/// Samples of a `w x h` test grid (file order), every `void_every`-th one `void`.
fn values(w: usize, h: usize, void: f32, void_every: usize) -> Vec<f32> {
    (0..w * h)
        .map(|i| if i % void_every == 5 { void } else { ((i * 7919) % 1013) as f32 * 0.5 - 40.0 })
        .collect()
}

/// Reads every row of `source` in bands of `band` rows, from `first` on and wrapping
/// around, and returns them in grid order.
fn read_in_bands(source: &mut dyn RowSource, band: usize, first: usize) -> Vec<f32> {
    let (w, h) = (source.width(), source.height());
    let mut all = vec![0f32; w * h];
    let mut starts: Vec<usize> = (0..h).step_by(band).collect();
    let turn = first.min(starts.len() - 1);
    starts.rotate_left(turn);
    for start in starts {
        let rows = band.min(h - start);
        source.read_rows(start, &mut all[start * w..(start + rows) * w]).unwrap();
    }
    all
}

fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()))
}

/// Checks that the rows of `path` equal `read_raster`'s in size, geometry, info and every
/// sample, read in several band sizes and orders.
fn assert_rows_equal_raster(path: &Path) -> Raster {
    let raster = read_raster(path, &options()).unwrap_or_else(|e| panic!("{e}"));
    let mut rows = open_rows(path, &options()).unwrap_or_else(|e| panic!("{e}"));
    let name = path.display();
    assert_eq!((rows.width(), rows.height()), (raster.width, raster.height), "{name}");
    assert_eq!(rows.geometry(), raster.geometry, "{name}");
    // Debug text: a NaN nodata value is equal to itself there.
    assert_eq!(format!("{:?}", rows.info()), format!("{:?}", raster.info), "{name}");
    for (band, first) in [(1, 0), (3, 2), (7, 1), (16, 0), (raster.height, 0)] {
        let got = read_in_bands(rows.as_mut(), band, first);
        assert!(same_bits(&got, &raster.samples), "{name}: bands of {band} from {first}");
    }
    raster
}

#[test]
fn geotiff_strips_of_every_codec_equal_read_raster() {
    let dir = TestDir::new("rows-strips");
    let (w, h) = (23usize, 19usize);
    let codecs = [
        ("none", Compression::Uncompressed),
        ("lzw", Compression::Lzw),
        ("deflate", Compression::Deflate(DeflateLevel::Fast)),
        ("packbits", Compression::Packbits),
    ];
    let mut extras = projected(10.0, 20.0, 1000.0, 5000.0);
    extras.push(Extra::Ascii(Tag::GdalNodata, "-9999"));
    let floats = values(w, h, -9999.0, 11);
    let ints: Vec<i16> = floats.iter().map(|&v| v as i16).collect();
    for (name, codec) in codecs {
        // PackBits strips are one row each (the encoder's rule).
        let rows = if name == "packbits" { None } else { Some(4) };
        let bytes =
            encode_strips::<Gray32Float>(&floats, (w as u32, h as u32), codec, rows, &extras);
        let raster = assert_rows_equal_raster(&dir.file(&format!("f32-{name}.tif"), &bytes));
        assert!(raster.void_count() > 0);
        let bytes = encode_strips::<GrayI16>(&ints, (w as u32, h as u32), codec, rows, &extras);
        assert_rows_equal_raster(&dir.file(&format!("i16-{name}.tif"), &bytes));
    }
    // One strip for the whole image, and no georeference.
    let bytes = encode_strips::<Gray32Float>(
        &floats,
        (w as u32, h as u32),
        Compression::Uncompressed,
        Some(h as u32),
        &[],
    );
    assert_rows_equal_raster(&dir.file("one-strip.tif", &bytes));
}

#[test]
fn deflate_strips_with_predictors_and_big_endian_equal_read_raster() {
    let dir = TestDir::new("rows-predictors");
    let (w, h) = (29usize, 31usize);
    let mut extras = projected(1.0, 1.0, 0.0, 31.0);
    extras.push(Extra::Ascii(Tag::GdalNodata, "-32768"));
    let ints: Vec<i16> = values(w, h, -32768.0, 9).iter().map(|&v| (v * 3.0) as i16).collect();
    let deflate = (Compression::Deflate(DeflateLevel::Fast), Predictor::Horizontal);
    for rows in [1, 3, 31] {
        let size = (w as u32, h as u32);
        let bytes = encode_predicted_strips::<GrayI16>(&ints, size, deflate, Some(rows), &extras);
        assert_rows_equal_raster(&dir.file(&format!("horizontal-{rows}.tif"), &bytes));
    }
    // relief's own files: Deflate with the floating-point predictor.
    let samples: Vec<f32> = values(w, h, 1.0, 1000);
    let field = HeightField::new(w, h, samples, GridGeometry::unit()).unwrap();
    let own = dir.join("own.tif");
    relief_io::geotiff::write_geotiff(&own, &field).unwrap();
    assert_rows_equal_raster(&own);
    // A big-endian file ("MM") of 3 x 2 int16 samples in one Deflate strip, horizontal
    // predictor: differences of big-endian samples.
    let samples: [i16; 6] = [-300, 2, 1000, -5, 32767, -32768];
    let mut raw = Vec::new();
    for row in samples.chunks(3) {
        let mut previous = 0i16;
        for &v in row {
            raw.extend(v.wrapping_sub(previous).to_be_bytes());
            previous = v;
        }
    }
    let mut packed = Vec::new();
    Deflate::with_level(DeflateLevel::Fast).write_to(&mut packed, &raw).unwrap();
    let entries: [(u16, u16, u32); 11] = [
        (256, 3, 3),                   // ImageWidth
        (257, 3, 2),                   // ImageLength
        (258, 3, 16),                  // BitsPerSample
        (259, 3, 8),                   // Deflate
        (262, 3, 1),                   // BlackIsZero
        (273, 4, 0),                   // StripOffsets, patched below
        (277, 3, 1),                   // SamplesPerPixel
        (279, 4, packed.len() as u32), // StripByteCounts
        (317, 3, 2),                   // Predictor: horizontal
        (339, 3, 2),                   // SampleFormat: signed
        (42113, 2, 0),                 // GDAL_NODATA "-5", inline
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
    bytes.extend(&packed);
    let raster = assert_rows_equal_raster(&dir.file("big-endian.tif", &bytes));
    let expected = [f32::NAN, 32767.0, -32768.0, -300.0, 2.0, 1000.0];
    assert!(same_bits(&raster.samples, &expected), "{:?}", raster.samples);
}

#[test]
fn geotiff_tiles_of_every_codec_equal_read_raster() {
    let dir = TestDir::new("rows-tiles");
    let (w, h) = (37usize, 35usize);
    let mut extras = projected(2.0, 3.0, -500.0, 700.0);
    extras.push(Extra::Ascii(Tag::GdalNodata, "nan"));
    let floats = values(w, h, f32::NAN, 13);
    for codec in TileCodec::ALL {
        // Tile 4 (of 3 x 3) stored with no bytes: nodata.
        let bytes = encode_f32_tiles(&floats, (w, h), 16, codec, &[4], &extras);
        let raster = assert_rows_equal_raster(&dir.file(&format!("{codec:?}.tif"), &bytes));
        assert!(raster.void_count() > 16 * 16, "{codec:?}");
    }
}

#[test]
fn south_up_geotiffs_are_not_flipped() {
    let dir = TestDir::new("rows-south-up");
    let (w, h) = (9usize, 14usize);
    let mut matrix = vec![5.0, 0.0, 0.0, 100.0, 0.0, 5.0, 0.0, 200.0];
    matrix.extend([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    let extras = [Extra::Doubles(Tag::ModelTransformationTag, matrix)];
    let floats = values(w, h, 0.0, 1000);
    let bytes = encode_f32_tiles(&floats, (w, h), 16, TileCodec::Deflate, &[], &extras);
    let raster = assert_rows_equal_raster(&dir.file("south-up.tif", &bytes));
    assert_eq!(raster.samples[..w], floats[..w], "row 0 is the file's first");
}

#[test]
fn the_jacksboro_dem_reads_as_rows() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/jacksboro_fault_dem.tif");
    let raster = assert_rows_equal_raster(&path);
    assert!(raster.info.from_degrees.is_some());
}

#[test]
fn a_nan_without_nodata_is_refused_when_its_row_is_read() {
    let dir = TestDir::new("rows-nan");
    let (w, h) = (6usize, 8usize);
    let mut floats = values(w, h, 0.0, 1000);
    floats[2 * w + 3] = f32::NAN; // file row 2: grid row 5
    let bytes = encode_strips::<Gray32Float>(
        &floats,
        (w as u32, h as u32),
        Compression::Uncompressed,
        Some(2),
        &[],
    );
    let path = dir.file("nan.tif", &bytes);
    let mut rows = open_rows(&path, &options()).unwrap();
    let mut band = vec![0f32; 4 * w];
    rows.read_rows(0, &mut band).unwrap();
    let err = rows.read_rows(4, &mut band).unwrap_err();
    assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    let text = err.to_string();
    assert!(text.contains("nan.tif") && text.contains("column 3, row 2"), "{text}");
}

#[test]
fn geotiff_rows_need_memory_for_one_row_of_chunks_only() {
    let dir = TestDir::new("rows-budget");
    let (w, h) = (64usize, 64usize);
    let floats = values(w, h, 0.0, 1000);
    let bytes = encode_f32_tiles(&floats, (w, h), 16, TileCodec::Deflate, &[], &[]);
    let path = dir.file("tiles.tif", &bytes);
    // The whole raster needs 64 * 64 * 5 bytes; a row of tiles 64 * 16 * 4 and one tile.
    let small = ReadOptions { max_memory: 64 * 16 * 4 + 16 * 16 * 4, ..ReadOptions::default() };
    assert!(matches!(read_raster(&path, &small), Err(IoError::Limits { .. })));
    let mut rows = open_rows(&path, &small).unwrap();
    assert!(same_bits(
        &read_in_bands(rows.as_mut(), 5, 3),
        &read_raster(&path, &options()).unwrap().samples
    ));
    let tiny = ReadOptions { max_memory: 64 * 16 * 4, ..ReadOptions::default() };
    assert!(matches!(open_rows(&path, &tiny), Err(IoError::Limits { .. })));
}

/// A 1201 x 1201 field with heights from -500 to 4000, and holes.
fn srtm_field() -> HeightField {
    let n = 1201;
    let samples = (0..n * n).map(|i| ((i * 37) % 4501) as f32 - 500.0).collect();
    let holes = (0..n * n).map(|i| i % 997 == 3).collect();
    HeightField::new(n, n, samples, GridGeometry::unit()).unwrap().with_holes(holes).unwrap()
}

#[test]
fn srtm_tiles_equal_read_raster_named_or_not() {
    let dir = TestDir::new("rows-hgt");
    let field = srtm_field();
    for name in ["N36W085.hgt", "s12e045.hgt", "tile.hgt"] {
        let path = dir.join(name);
        relief_io::hgt::write_hgt(&path, &field).unwrap();
        let raster = assert_rows_equal_raster(&path);
        assert_eq!(raster.void_count(), field.samples().len().div_ceil(997));
    }
}

/// A version 1.0 `.npy` file with the given header fields and raw data.
fn npy(descr: &str, fortran: bool, shape: (usize, usize), data: &[u8]) -> Vec<u8> {
    let order = if fortran { "True" } else { "False" };
    let mut dict = format!(
        "{{'descr': '{descr}', 'fortran_order': {order}, 'shape': ({}, {}), }}",
        shape.0, shape.1
    );
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

#[test]
fn npy_arrays_of_several_dtypes_and_orders_equal_read_raster() {
    let dir = TestDir::new("rows-npy");
    let (rows, cols) = (13usize, 7usize);
    let v: Vec<f32> = values(cols, rows, 1.0, 1000);
    let f32_le: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    let f64_be: Vec<u8> = v.iter().flat_map(|&x| f64::from(x).to_be_bytes()).collect();
    let i16_le: Vec<u8> = v.iter().flat_map(|&x| (x as i16).to_le_bytes()).collect();
    let f16_le: Vec<u8> = v.iter().flat_map(|&x| half::f16::from_f32(x).to_le_bytes()).collect();
    let u8s: Vec<u8> = v.iter().map(|&x| x.abs() as u8).collect();
    let cases = [
        ("<f4", false, f32_le.clone()),
        (">f8", false, f64_be),
        ("<i2", false, i16_le),
        ("<f2", false, f16_le),
        ("|u1", false, u8s),
        // Fortran order: read whole, served from memory.
        ("<f4", true, f32_le),
    ];
    for (k, (descr, fortran, data)) in cases.into_iter().enumerate() {
        let path = dir.file(&format!("case{k}.npy"), &npy(descr, fortran, (rows, cols), &data));
        assert_rows_equal_raster(&path);
    }
    // A NaN is refused when its row is read, naming its place.
    let mut bad = v.clone();
    bad[3 * cols + 2] = f32::NAN;
    let data: Vec<u8> = bad.iter().flat_map(|x| x.to_le_bytes()).collect();
    let path = dir.file("nan.npy", &npy("<f4", false, (rows, cols), &data));
    let mut source = open_rows(&path, &options()).unwrap();
    let mut band = vec![0f32; 3 * cols];
    source.read_rows(0, &mut band).unwrap();
    let err = source.read_rows(2, &mut band).unwrap_err();
    assert!(err.to_string().contains("column 2, row 3"), "{err}");
}

#[test]
fn other_formats_are_served_from_memory() {
    let dir = TestDir::new("rows-other");
    let samples: Vec<f32> = (0..30).map(|i| (i * 3 % 17) as f32).collect();
    let field = HeightField::new(6, 5, samples, GridGeometry::unit()).unwrap();
    for name in ["grid.asc", "grid.png"] {
        let path = dir.join(name);
        relief_io::write_height_field(&path, &field).unwrap();
        assert_rows_equal_raster(&path);
    }
}

/// One file of each streamed kind, and one served from memory.
fn every_kind(dir: &TestDir) -> Vec<PathBuf> {
    let (w, h) = (11usize, 9usize);
    let floats = values(w, h, 0.0, 1000);
    let field = HeightField::new(w, h, floats.clone(), GridGeometry::unit()).unwrap();
    let strips = dir.file(
        "strips.tif",
        &encode_strips::<Gray32Float>(
            &floats,
            (w as u32, h as u32),
            Compression::Lzw,
            Some(2),
            &[],
        ),
    );
    let tiles =
        dir.file("tiles.tif", &encode_f32_tiles(&floats, (w, h), 16, TileCodec::Zstd, &[], &[]));
    let npy = dir.join("grid.npy");
    relief_io::npy::write_height_field_npy(&npy, &field).unwrap();
    let hgt = dir.join("N01E002.hgt");
    relief_io::hgt::write_hgt(&hgt, &srtm_field()).unwrap();
    let asc = dir.join("grid.asc");
    relief_io::write_height_field(&asc, &field).unwrap();
    vec![strips, tiles, npy, hgt, asc]
}

#[test]
fn requests_past_the_raster_or_of_partial_rows_are_errors() {
    let dir = TestDir::new("rows-range");
    for path in every_kind(&dir) {
        let mut rows = open_rows(&path, &options()).unwrap();
        let (w, h) = (rows.width(), rows.height());
        let mut one = vec![0f32; w];
        rows.read_rows(h - 1, &mut one).unwrap();
        rows.read_rows(h, &mut []).unwrap();
        for (first, len) in [(h, w), (h - 1, 2 * w), (0, w + 1), (0, (h + 1) * w), (usize::MAX, w)]
        {
            let mut out = vec![0f32; len];
            let err = rows.read_rows(first, &mut out).unwrap_err();
            assert!(matches!(err, IoError::InvalidData { .. }), "{}: {err}", path.display());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any sequence of requests gives read_raster's rows, whatever came before.
    #[test]
    fn any_requests_give_read_rasters_rows(
        requests in proptest::collection::vec((0usize..1000, 1usize..12), 1..12)
    ) {
        let dir = TestDir::new("rows-prop");
        for path in every_kind(&dir) {
            let raster = read_raster(&path, &options()).unwrap();
            let mut rows = open_rows(&path, &options()).unwrap();
            let (w, h) = (raster.width, raster.height);
            for &(first, count) in &requests {
                let first = first % h;
                let count = count.min(h - first);
                let mut out = vec![0f32; count * w];
                rows.read_rows(first, &mut out).unwrap();
                let want = &raster.samples[first * w..(first + count) * w];
                prop_assert!(same_bits(&out, want), "{}: rows {first}+{count}", path.display());
                if first % 3 == 0 {
                    rows.release_cache();
                }
            }
        }
    }
}

#[test]
fn corrupted_chunks_fail_as_read_raster_fails_or_read_the_same() {
    let dir = TestDir::new("rows-corrupt");
    let (w, h) = (40usize, 40usize);
    let floats = values(w, h, 0.0, 1000);
    for codec in [TileCodec::Deflate, TileCodec::Zstd] {
        let good = encode_f32_tiles(&floats, (w, h), 16, codec, &[], &[]);
        let (mut refused, mut read) = (0, 0);
        for at in (8..good.len() - 200).step_by(37) {
            let mut bad = good.clone();
            bad[at] ^= 0x5a;
            let path = dir.file("bad.tif", &bad);
            let whole = read_raster(&path, &options());
            let rows = open_rows(&path, &options()).and_then(|mut rows| {
                let mut all = vec![0f32; rows.width() * rows.height()];
                rows.read_rows(0, &mut all).map(|()| all)
            });
            match (whole, rows) {
                (Ok(raster), Ok(all)) => {
                    assert!(same_bits(&raster.samples, &all), "{codec:?} byte {at}");
                    read += 1;
                }
                (Err(_), Err(e)) => {
                    assert!(e.to_string().contains("bad.tif"), "{e}");
                    refused += 1;
                }
                (whole, rows) => panic!("{codec:?} byte {at}: {whole:?} but {:?}", rows.err()),
            }
        }
        assert!(refused > 0, "{codec:?}: {refused} refused, {read} read");
    }
}
