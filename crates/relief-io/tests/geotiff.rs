//! GeoTIFF reading and writing: a real DEM, files made here with the `tiff` crate for every
//! sample type, compression and chunk layout, placements, the writer's round trip and broken
//! files.
//! In a bare clone (no ../shared) a test that reads the shared data is reported ignored.

mod common;

use common::{clients, shared_data, TestDir};

use relief_core::{DVec2, GridGeometry, HeightField};
use relief_io::geotiff::{read_geotiff, write_geotiff};
use relief_io::npy::read_npy_height_field;
use relief_io::{metres_per_degree, IoError, Raster, ReadOptions, VoidPolicy};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::io::{Cursor, ErrorKind};
use std::path::{Path, PathBuf};
use tiff::encoder::colortype::{self, ColorType};
use tiff::encoder::compression::{CompressionAlgorithm, Deflate, DeflateLevel, Lzw, Packbits};
use tiff::encoder::{Compression, Predictor, TiffEncoder, TiffValue};
use tiff::tags::Tag;

fn main() {
    clients::run(vec![
        clients::trial!(jacksboro_dem_reads_with_its_size_type_placement_and_values),
        clients::trial_reading!(
            jacksboro_rows_run_south_to_north_like_the_numpy_copy_flipped,
            "data/jacksboro_fault_dem.npy"
        ),
        clients::trial!(written_field_reads_back_with_the_same_geometry_samples_and_holes),
        clients::trial!(z_scale_is_applied_to_written_values),
        clients::trial!(failed_writes_leave_no_file),
        clients::trial!(every_sample_type_in_strips_and_tiles_with_every_compression),
        clients::trial!(nan_nodata_marks_nan_samples_as_voids),
        clients::trial!(sparse_tiles_are_filled_with_nodata),
        clients::trial!(reading_holds_the_samples_and_one_strip_not_the_decoded_file),
        clients::trial!(placements_of_projected_rasters),
        clients::trial!(geographic_pixel_is_point_raster_is_placed_in_metres),
        clients::trial!(every_truncation_of_the_fixture_is_an_error),
        clients::trial!(corrupted_tiles_are_refused_or_read_at_their_size_as_their_codec_allows),
        clients::trial!(wrong_magic_empty_file_directory_and_missing_file),
        clients::trial!(a_tiny_file_claiming_a_huge_raster_is_refused_before_allocating),
        clients::trial!(zero_sized_raster_is_a_format_error),
        clients::trial!(rgb_images_and_other_layouts_are_unsupported),
        clients::trial!(nan_without_nodata_is_refused_naming_its_place),
        clients::trial!(big_endian_files_read_like_little_endian_ones),
    ]);
}

// ---------------------------------------------------------------------------------------------
// Allocation accounting: the largest amount of heap this thread held at once.

struct CountingAllocator;

thread_local! {
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
}

fn account(delta: isize) {
    let _ = LIVE.try_with(|live| {
        let now = live.get() + delta;
        live.set(now);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
    });
}

// SAFETY: every call is forwarded to the system allocator unchanged; the accounting only
// touches thread-local cells without destructors, which never allocate.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let ptr = unsafe { System.alloc(layout) };
        if !ptr.is_null() {
            account(layout.size() as isize);
        }
        ptr
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let ptr = unsafe { System.alloc_zeroed(layout) };
        if !ptr.is_null() {
            account(layout.size() as isize);
        }
        ptr
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        account(-(layout.size() as isize));
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let new = unsafe { System.realloc(ptr, layout, new_size) };
        if !new.is_null() {
            account(new_size as isize - layout.size() as isize);
        }
        new
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

/// Runs `f` and returns its result with the most heap bytes this thread held meanwhile beyond
/// what it held before.
fn peak_heap<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = LIVE.with(Cell::get);
    PEAK.with(|p| p.set(base));
    let result = f();
    let peak = PEAK.with(Cell::get);
    (result, (peak - base).max(0) as usize)
}

// ---------------------------------------------------------------------------------------------
// Helpers.

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/jacksboro_fault_dem.tif")
}

fn options() -> ReadOptions {
    ReadOptions { max_memory: 1 << 30, ..ReadOptions::default() }
}

/// A tag added to a generated file.
enum Extra {
    Ascii(Tag, &'static str),
    Doubles(Tag, Vec<f64>),
    Shorts(Tag, Vec<u16>),
}

/// A projected placement: pixels of 10 x 20 m, north-west corner at (1000, 5000).
fn projected() -> Vec<Extra> {
    vec![
        Extra::Doubles(Tag::ModelPixelScaleTag, vec![10.0, 20.0, 0.0]),
        Extra::Doubles(Tag::ModelTiepointTag, vec![0.0, 0.0, 0.0, 1000.0, 5000.0, 0.0]),
        Extra::Shorts(Tag::GeoKeyDirectoryTag, vec![1, 1, 0, 1, 1024, 0, 1, 1]),
    ]
}

/// A file of one image in strips, made by the `tiff` crate's encoder.
fn encode_strips<C: ColorType>(
    values: &[C::Inner],
    (width, height): (u32, u32),
    compression: Compression,
    predictor: Predictor,
    rows_per_strip: Option<u32>,
    extras: &[Extra],
) -> Vec<u8>
where
    [C::Inner]: TiffValue,
{
    let mut file = Cursor::new(Vec::new());
    let mut tiff = TiffEncoder::new(&mut file)
        .unwrap()
        .with_compression(compression)
        .with_predictor(predictor);
    let mut image = tiff.new_image::<C>(width, height).unwrap();
    if let Some(rows) = rows_per_strip {
        image.rows_per_strip(rows).unwrap();
    }
    for extra in extras {
        let encoder = image.encoder();
        match extra {
            Extra::Ascii(tag, text) => encoder.write_tag(*tag, *text),
            Extra::Doubles(tag, values) => encoder.write_tag(*tag, &values[..]),
            Extra::Shorts(tag, values) => encoder.write_tag(*tag, &values[..]),
        }
        .unwrap();
    }
    image.write_data(values).unwrap();
    file.into_inner()
}

/// How a hand-made tiled file compresses its tiles.
#[derive(Debug, Clone, Copy)]
enum TileCodec {
    None,
    Lzw,
    Deflate,
    PackBits,
}

impl TileCodec {
    const ALL: [TileCodec; 4] =
        [TileCodec::None, TileCodec::Lzw, TileCodec::Deflate, TileCodec::PackBits];

    fn code(self) -> u16 {
        match self {
            TileCodec::None => 1,
            TileCodec::Lzw => 5,
            TileCodec::Deflate => 8,
            TileCodec::PackBits => 32773,
        }
    }

    fn compress(self, bytes: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        match self {
            TileCodec::None => out.extend_from_slice(bytes),
            TileCodec::Lzw => {
                Lzw.write_to(&mut out, bytes).unwrap();
            }
            TileCodec::Deflate => {
                Deflate::with_level(DeflateLevel::Fast).write_to(&mut out, bytes).unwrap();
            }
            TileCodec::PackBits => {
                Packbits.write_to(&mut out, bytes).unwrap();
            }
        }
        out
    }
}

/// Samples as a tiled file stores them: native-endian bytes, `size` per sample.
struct Samples {
    bytes: Vec<u8>,
    size: usize,
    bits: u16,
    format: u16,
}

/// TIFF's floating-point predictor over one row of `size`-byte samples.
fn float_predict(row: &mut [u8], size: usize) {
    let n = row.len() / size;
    let mut planes = vec![0u8; row.len()];
    for i in 0..n {
        let mut value = row[i * size..][..size].to_vec();
        if cfg!(target_endian = "little") {
            value.reverse();
        }
        for (plane, byte) in value.into_iter().enumerate() {
            planes[plane * n + i] = byte;
        }
    }
    for j in (1..planes.len()).rev() {
        planes[j] = planes[j].wrapping_sub(planes[j - 1]);
    }
    row.copy_from_slice(&planes);
}

/// A hand-made tiled file: `tile x tile` tiles (padded at the right and bottom edges with
/// zero bytes), compressed with `codec`, predictor 1 or 3.
fn encode_tiles(
    samples: &Samples,
    (width, height): (usize, usize),
    tile: usize,
    codec: TileCodec,
    predictor: u16,
    extras: &[Extra],
) -> Vec<u8> {
    let size = samples.size;
    let mut file = Cursor::new(Vec::new());
    let mut tiff = TiffEncoder::new(&mut file).unwrap();
    let mut dir = tiff.image_directory().unwrap();
    let (mut offsets, mut counts) = (Vec::<u32>::new(), Vec::<u32>::new());
    for ty in 0..height.div_ceil(tile) {
        for tx in 0..width.div_ceil(tile) {
            let mut raw = vec![0u8; tile * tile * size];
            for r in 0..tile {
                for c in 0..tile {
                    let (x, y) = (tx * tile + c, ty * tile + r);
                    if x < width && y < height {
                        let from = &samples.bytes[(y * width + x) * size..][..size];
                        raw[(r * tile + c) * size..][..size].copy_from_slice(from);
                    }
                }
            }
            if predictor == 3 {
                for row in raw.chunks_exact_mut(tile * size) {
                    float_predict(row, size);
                }
            }
            let packed = codec.compress(&raw);
            offsets.push(dir.write_data(&packed[..]).unwrap() as u32);
            counts.push(packed.len() as u32);
        }
    }
    dir.write_tag(Tag::ImageWidth, width as u32).unwrap();
    dir.write_tag(Tag::ImageLength, height as u32).unwrap();
    dir.write_tag(Tag::BitsPerSample, samples.bits).unwrap();
    dir.write_tag(Tag::Compression, codec.code()).unwrap();
    dir.write_tag(Tag::PhotometricInterpretation, 1u16).unwrap();
    dir.write_tag(Tag::SamplesPerPixel, 1u16).unwrap();
    dir.write_tag(Tag::TileWidth, tile as u32).unwrap();
    dir.write_tag(Tag::TileLength, tile as u32).unwrap();
    dir.write_tag(Tag::TileOffsets, &offsets[..]).unwrap();
    dir.write_tag(Tag::TileByteCounts, &counts[..]).unwrap();
    dir.write_tag(Tag::SampleFormat, samples.format).unwrap();
    dir.write_tag(Tag::Predictor, predictor).unwrap();
    for extra in extras {
        match extra {
            Extra::Ascii(tag, text) => dir.write_tag(*tag, *text),
            Extra::Doubles(tag, values) => dir.write_tag(*tag, &values[..]),
            Extra::Shorts(tag, values) => dir.write_tag(*tag, &values[..]),
        }
        .unwrap();
    }
    dir.finish().unwrap();
    file.into_inner()
}

/// Checks `raster` holds `expected` (file order, row 0 north; NaN = void) flipped south-up.
fn assert_north_up_samples(raster: &Raster, expected: &[f32], case: &str) {
    let (w, h) = (raster.width, raster.height);
    assert_eq!(expected.len(), w * h, "{case}");
    for row in 0..h {
        for col in 0..w {
            let want = expected[col + (h - 1 - row) * w];
            let got = raster.samples[col + row * w];
            assert!(
                got == want || (got.is_nan() && want.is_nan()),
                "{case}: raster ({col}, {row}) is {got}, expected {want}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The real DEM.

fn jacksboro_dem_reads_with_its_size_type_placement_and_values() {
    let raster = read_geotiff(&fixture(), &ReadOptions::default()).unwrap();
    assert_eq!((raster.width, raster.height), (403, 344));
    assert_eq!(raster.info.sample_type, "int16");
    assert_eq!(raster.info.nodata, Some(-32768.0));
    assert!(raster.info.georeferenced);
    let degrees = raster.info.from_degrees.expect("a geographic raster");
    let arc3 = 3.0 / 3600.0;
    assert!((degrees.dlon - arc3).abs() < 1e-12 && (degrees.dlat - arc3).abs() < 1e-12);
    // Extents from shared/data/datasets.json.
    let (west, south, north) = (-84.41375, 36.44625, 36.73291666666667);
    assert!((degrees.latitude - 0.5 * (south + north)).abs() < 1e-9, "{}", degrees.latitude);
    let g = raster.geometry;
    assert!((g.dx - 74.5).abs() <= 0.3, "dx {}", g.dx);
    assert!((g.dy - 92.5).abs() <= 0.3, "dy {}", g.dy);
    assert_eq!(g.z_scale, 1.0);
    let (per_lon, per_lat) = metres_per_degree(degrees.latitude);
    assert!((g.origin.x - west * per_lon).abs() < 1e-6, "{}", g.origin);
    assert!((g.origin.y - south * per_lat).abs() < 1e-6, "{}", g.origin);
    assert!((g.dx - arc3 * per_lon).abs() < 1e-9 && (g.dy - arc3 * per_lat).abs() < 1e-9);
    assert_eq!(raster.void_count(), 0);
    assert_eq!(raster.value_range(), Some((236.0, 1076.0)));
    assert!(raster.samples.iter().all(|v| v.fract() == 0.0));
}

fn jacksboro_rows_run_south_to_north_like_the_numpy_copy_flipped() {
    let Some(npy) = shared_data("data/jacksboro_fault_dem.npy") else { return };
    let raster = read_geotiff(&fixture(), &ReadOptions::default()).unwrap();
    let grid = read_npy_height_field(&npy).unwrap();
    assert_eq!((grid.width(), grid.height()), (403, 344));
    for row_from_north in 0..344 {
        for col in 0..403 {
            assert_eq!(
                grid.sample(col, row_from_north),
                raster.samples[col + (343 - row_from_north) * 403],
                "column {col}, row {row_from_north} from the north"
            );
        }
    }
    // Not symmetric: a flip would have been caught.
    assert_ne!(grid.sample(0, 0), grid.sample(0, 343));
}

// ---------------------------------------------------------------------------------------------
// The writer.

fn written_field_reads_back_with_the_same_geometry_samples_and_holes() {
    let dir = TestDir::new("roundtrip");
    let (w, h) = (29, 17);
    let samples: Vec<f32> = (0..w * h).map(|i| ((i * 37) % 101) as f32 * 1.5 - 20.25).collect();
    let geometry =
        GridGeometry { dx: 2.5, dy: 3.0, z_scale: 1.0, origin: DVec2::new(1000.0, 2000.0) };
    let holes: Vec<bool> = (0..w * h).map(|i| [3, 40, 41, 200, w * h - 1].contains(&i)).collect();
    let field = HeightField::new(w, h, samples.clone(), geometry).unwrap();
    let field = field.with_holes(holes.clone()).unwrap();
    let path = dir.join("field.tif");
    write_geotiff(&path, &field).unwrap();
    // Nothing but the file itself is left in the directory (no temporary).
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);

    let raster = read_geotiff(&path, &options()).unwrap();
    assert_eq!((raster.width, raster.height), (w, h));
    let g = raster.geometry;
    assert!((g.dx - 2.5).abs() < 1e-9 && (g.dy - 3.0).abs() < 1e-9, "{g:?}");
    assert!((g.origin - DVec2::new(1000.0, 2000.0)).length() < 1e-9, "{g:?}");
    assert_eq!(g.z_scale, 1.0);
    assert!(raster.info.georeferenced && raster.info.from_degrees.is_none());
    assert_eq!(raster.info.sample_type, "float32");
    for (i, (&got, &hole)) in raster.samples.iter().zip(&holes).enumerate() {
        if hole {
            assert!(got.is_nan(), "sample {i} should be a void, is {got}");
        } else {
            assert_eq!(got, samples[i], "sample {i}");
        }
    }
    assert_eq!(raster.void_count(), 5);
    let back = raster.into_height_field(&path, VoidPolicy::Hole).unwrap();
    assert_eq!(back.holes(), field.holes());
    assert_eq!(back.samples(), field.samples());

    // The file is float32, Deflate with the floating-point predictor, one band, north-up.
    let mut decoder = tiff::decoder::Decoder::new(std::fs::File::open(&path).unwrap()).unwrap();
    let tags = [Tag::Compression, Tag::Predictor, Tag::SampleFormat, Tag::BitsPerSample];
    let values = tags.map(|t| decoder.get_tag_u32(t).unwrap());
    assert_eq!(values, [8, 3, 3, 32], "Deflate, floating-point predictor, float32");
    let first_row = match decoder.read_chunk(0).unwrap() {
        tiff::decoder::DecodingResult::F32(v) => v,
        other => panic!("{other:?}"),
    };
    // File row 0 is the field's northernmost row; its last sample is a hole, written as NaN.
    let north = (h - 1) * w;
    for (col, &got) in first_row[..w].iter().enumerate() {
        let want = if holes[north + col] { f32::NAN } else { samples[north + col] };
        assert!(got == want || got.is_nan() && want.is_nan(), "column {col}: {got} vs {want}");
    }
    assert!(first_row[w - 1].is_nan());
}

fn z_scale_is_applied_to_written_values() {
    let dir = TestDir::new("zscale");
    let geometry = GridGeometry { z_scale: 0.5, ..GridGeometry::unit() };
    let field = HeightField::new(3, 2, vec![2.0, 4.0, 6.0, 8.0, 10.0, -12.0], geometry).unwrap();
    let path = dir.join("z.tif");
    write_geotiff(&path, &field).unwrap();
    let raster = read_geotiff(&path, &options()).unwrap();
    assert_eq!(raster.samples, [1.0, 2.0, 3.0, 4.0, 5.0, -6.0]);
}

fn failed_writes_leave_no_file() {
    let dir = TestDir::new("write-fail");
    let field = HeightField::new(2, 2, vec![0.0; 4], GridGeometry::unit()).unwrap();
    let missing_dir = dir.join("absent").join("x.tif");
    assert!(matches!(write_geotiff(&missing_dir, &field), Err(IoError::Io { .. })));
    assert!(!missing_dir.exists());
    assert!(matches!(write_geotiff(dir.path(), &field), Err(IoError::Io { .. })));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

// ---------------------------------------------------------------------------------------------
// Every sample type, compression, predictor and chunk layout.

const STRIP_CODECS: [(&str, Compression); 4] = [
    ("uncompressed", Compression::Uncompressed),
    ("lzw", Compression::Lzw),
    ("deflate", Compression::Deflate(DeflateLevel::Balanced)),
    ("packbits", Compression::Packbits),
];

/// A sample type the tests write: its value as the reader's f32 and its native bytes.
trait Sample: Copy + PartialEq {
    fn to_f32(self) -> f32;
    fn ne_bytes(self) -> Vec<u8>;
}

macro_rules! impl_sample {
    ($($t:ty),*) => {$(
        impl Sample for $t {
            fn to_f32(self) -> f32 {
                self as f32
            }
            fn ne_bytes(self) -> Vec<u8> {
                self.to_ne_bytes().to_vec()
            }
        }
    )*};
}

impl_sample!(i8, u8, i16, u16, i32, u32, i64, u64, f32, f64);

/// One sample type: its encoder colour type, the name the reader reports, its nodata value and
/// that value as GDAL_NODATA text, its TIFF SampleFormat code and the values to store.
fn check_sample_type<C: ColorType>(
    dir: &TestDir,
    name: &str,
    (nodata, nodata_text): (C::Inner, &'static str),
    format: u16,
    value: fn(usize) -> C::Inner,
) where
    C::Inner: Sample,
    [C::Inner]: TiffValue,
{
    let (w, h) = (37usize, 35usize);
    let integer = format != 3;
    let values: Vec<C::Inner> =
        (0..w * h).map(|i| if i % 10 == 3 { nodata } else { value(i) }).collect();
    let expected: Vec<f32> =
        values.iter().map(|&v| if v == nodata { f32::NAN } else { v.to_f32() }).collect();
    let mut extras = projected();
    extras.push(Extra::Ascii(Tag::GdalNodata, nodata_text));
    let check = |bytes: &[u8], case: &str| {
        let path = dir.file("case.tif", bytes);
        let raster = read_geotiff(&path, &options()).unwrap_or_else(|e| panic!("{case}: {e}"));
        assert_eq!(raster.info.sample_type, name, "{case}");
        assert_eq!((raster.width, raster.height), (w, h), "{case}");
        let g = raster.geometry;
        assert_eq!((g.dx, g.dy), (10.0, 20.0), "{case}");
        assert_eq!(g.origin, DVec2::new(1000.0, 5000.0 - 20.0 * h as f64), "{case}");
        assert_north_up_samples(&raster, &expected, case);
    };
    let predictors: &[Predictor] =
        if integer { &[Predictor::None, Predictor::Horizontal] } else { &[Predictor::None] };
    for (codec_name, codec) in STRIP_CODECS {
        for &predictor in predictors {
            // PackBits strips are one row each (the encoder's rule); the others 4 rows, the
            // last strip short.
            let rows = if codec_name == "packbits" { None } else { Some(4) };
            let size = (w as u32, h as u32);
            let bytes = encode_strips::<C>(&values, size, codec, predictor, rows, &extras);
            check(&bytes, &format!("{name} strips {codec_name} {predictor:?}"));
        }
    }
    let samples = Samples {
        bytes: values.iter().flat_map(|v| v.ne_bytes()).collect(),
        size: std::mem::size_of::<C::Inner>(),
        bits: 8 * std::mem::size_of::<C::Inner>() as u16,
        format,
    };
    let predictors: &[u16] = if integer { &[1] } else { &[1, 3] };
    for codec in TileCodec::ALL {
        for &predictor in predictors {
            let bytes = encode_tiles(&samples, (w, h), 16, codec, predictor, &extras);
            check(&bytes, &format!("{name} tiles {codec:?} predictor {predictor}"));
        }
    }
}

fn every_sample_type_in_strips_and_tiles_with_every_compression() {
    use colortype::*;
    let dir = TestDir::new("types");
    check_sample_type::<GrayI8>(&dir, "int8", (i8::MIN, "-128"), 2, |i| {
        if i == 1 {
            i8::MAX
        } else {
            ((i * 7) % 200) as u8 as i8
        }
    });
    check_sample_type::<Gray8>(&dir, "uint8", (255, "255"), 1, |i| (i % 250) as u8);
    check_sample_type::<GrayI16>(&dir, "int16", (-32768, "-32768"), 2, |i| {
        if i == 1 {
            i16::MAX
        } else {
            (i as i16).wrapping_mul(97) / 3
        }
    });
    check_sample_type::<Gray16>(&dir, "uint16", (0, "0"), 1, |i| {
        if i == 1 {
            u16::MAX
        } else {
            1 + (i as u16).wrapping_mul(311) % 60000
        }
    });
    check_sample_type::<GrayI32>(&dir, "int32", (-9999, " -9999 "), 2, |i| {
        if i == 1 {
            i32::MIN
        } else {
            (i as i32 - 600) * 12_345
        }
    });
    check_sample_type::<Gray32>(&dir, "uint32", (u32::MAX, "4294967295"), 1, |i| {
        i as u32 * 1_000_003
    });
    let i64_nodata = (i64::MIN, "-9223372036854775808");
    check_sample_type::<GrayI64>(&dir, "int64", i64_nodata, 2, |i| (i as i64 - 700) << 20);
    check_sample_type::<Gray64>(&dir, "uint64", (7, "7"), 1, |i| (i as u64 + 8) << 30);
    check_sample_type::<Gray32Float>(&dir, "float32", (-3.4e38, "-3.4e38"), 3, |i| {
        i as f32 * 0.37 - 150.0
    });
    check_sample_type::<Gray64Float>(&dir, "float64", (-1e300, "-1e300"), 3, |i| {
        i as f64 * 1e-3 - 0.5
    });
}

fn nan_nodata_marks_nan_samples_as_voids() {
    let dir = TestDir::new("nan-nodata");
    let mut values = vec![1.5f32; 12];
    values[5] = f32::NAN;
    let mut extras = projected();
    extras.push(Extra::Ascii(Tag::GdalNodata, "nan"));
    let bytes = encode_strips::<colortype::Gray32Float>(
        &values,
        (4, 3),
        Compression::Deflate(DeflateLevel::Fast),
        Predictor::None,
        None,
        &extras,
    );
    let raster = read_geotiff(&dir.file("nan.tif", &bytes), &options()).unwrap();
    assert!(raster.info.nodata.is_some_and(f64::is_nan));
    assert_eq!(raster.void_count(), 1);
    // File sample 5 = column 1, file row 1 = raster row 1 of 3.
    assert!(raster.samples[1 + 4].is_nan());
}

fn sparse_tiles_are_filled_with_nodata() {
    let dir = TestDir::new("sparse");
    let samples =
        Samples { bytes: 5i16.to_ne_bytes().repeat(20 * 20), size: 2, bits: 16, format: 2 };
    let mut extras = projected();
    extras.push(Extra::Ascii(Tag::GdalNodata, "-1"));
    let mut bytes = encode_tiles(&samples, (20, 20), 16, TileCodec::Deflate, 1, &extras);
    // Zero the byte count of the last tile (the south-east one) as GDAL's sparse files do.
    let counts_at = entry_value_at(&bytes, Tag::TileByteCounts.to_u16());
    let counts_at = u32::from_le_bytes(bytes[counts_at..counts_at + 4].try_into().unwrap());
    let last = counts_at as usize + 3 * 4;
    bytes[last..last + 4].copy_from_slice(&0u32.to_le_bytes());
    let raster = read_geotiff(&dir.file("sparse.tif", &bytes), &options()).unwrap();
    // The last tile covers file rows 16..20, columns 16..20: raster rows 0..4.
    assert_eq!(raster.void_count(), 16);
    assert!(raster.samples[19].is_nan() && raster.samples[15] == 5.0);
}

fn reading_holds_the_samples_and_one_strip_not_the_decoded_file() {
    let dir = TestDir::new("memory");
    let (w, h) = (600usize, 500usize);
    let values: Vec<f64> = (0..w * h).map(|i| (i % 1000) as f64).collect();
    let bytes = encode_strips::<colortype::Gray64Float>(
        &values,
        (w as u32, h as u32),
        Compression::Uncompressed,
        Predictor::None,
        Some(10),
        &projected(),
    );
    let path = dir.file("big.tif", &bytes);
    drop(bytes);
    let (raster, peak) = peak_heap(|| read_geotiff(&path, &options()).unwrap());
    let samples = w * h * 4;
    let strip = w * 10 * 8;
    assert_eq!(raster.samples.len(), w * h);
    // The f32 samples, one decoded strip and small change (tags, buffers); decoding the whole
    // f64 file at once would need 2.4 MB more.
    assert!(peak <= samples + strip + (256 << 10), "peak heap {peak} B for {samples} B of samples");
}

// ---------------------------------------------------------------------------------------------
// Placement.

/// A 3 x 2 uint8 raster with `extras`, values 0..6 in file order.
fn placed(dir: &TestDir, extras: &[Extra]) -> Result<Raster, IoError> {
    let bytes = encode_strips::<colortype::Gray8>(
        &[0, 1, 2, 3, 4, 5],
        (3, 2),
        Compression::Uncompressed,
        Predictor::None,
        None,
        extras,
    );
    read_geotiff(&dir.file("placed.tif", &bytes), &options())
}

fn close(a: DVec2, b: DVec2) -> bool {
    (a - b).length() < 1e-9
}

fn placements_of_projected_rasters() {
    let dir = TestDir::new("placement");
    let keys = |raster_type: u16| {
        Extra::Shorts(
            Tag::GeoKeyDirectoryTag,
            vec![1, 1, 0, 2, 1024, 0, 1, 1, 1025, 0, 1, raster_type],
        )
    };
    let scale = |sy: f64| Extra::Doubles(Tag::ModelPixelScaleTag, vec![10.0, sy, 0.0]);
    let tie = |i: f64, j: f64| {
        Extra::Doubles(Tag::ModelTiepointTag, vec![i, j, 0.0, 1000.0, 5000.0, 0.0])
    };

    // PixelIsArea, north-up: north-west corner (1000, 5000), two rows of 20 m.
    let r = placed(&dir, &[scale(20.0), tie(0.0, 0.0), keys(1)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(1000.0, 4960.0)), "{:?}", r.geometry);
    assert_eq!(r.samples, [3.0, 4.0, 5.0, 0.0, 1.0, 2.0], "flipped");
    // A tie point at raster (1, 1) instead of (0, 0).
    let r = placed(&dir, &[scale(20.0), tie(1.0, 1.0), keys(1)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(990.0, 4980.0)), "{:?}", r.geometry);
    // PixelIsPoint: (1000, 5000) is the first sample's centre, so the corner is half a pixel
    // further west and north.
    let r = placed(&dir, &[scale(20.0), tie(0.0, 0.0), keys(2)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(995.0, 4970.0)), "{:?}", r.geometry);
    // South-up (negative y scale): file row 0 is the south row, not flipped.
    let r = placed(&dir, &[scale(-20.0), tie(0.0, 0.0), keys(1)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(1000.0, 5000.0)), "{:?}", r.geometry);
    assert_eq!(r.geometry.dy, 20.0);
    assert_eq!(r.samples, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0], "not flipped");
    // A ModelTransformation without rotation, north-up and south-up.
    let transform = |dy: f64| {
        let t = vec![
            10.0, 0.0, 0.0, 1000.0, 0.0, dy, 0.0, 5000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ];
        Extra::Doubles(Tag::ModelTransformationTag, t)
    };
    let r = placed(&dir, &[transform(-20.0), keys(1)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(1000.0, 4960.0)), "{:?}", r.geometry);
    assert_eq!(r.samples, [3.0, 4.0, 5.0, 0.0, 1.0, 2.0]);
    let r = placed(&dir, &[transform(20.0), keys(2)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(995.0, 4990.0)), "{:?}", r.geometry);
    assert_eq!(r.samples, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    // Rotation or shear is refused.
    let mut rotated = vec![10.0, 1.0, 0.0, 1000.0, 1.0, -20.0, 0.0, 5000.0];
    rotated.extend([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    let err = placed(&dir, &[Extra::Doubles(Tag::ModelTransformationTag, rotated)]).unwrap_err();
    assert!(
        matches!(err, IoError::Unsupported { .. }) && err.to_string().contains("rotated"),
        "{err}"
    );
    // Projected in US survey feet: converted to metres.
    let feet =
        Extra::Shorts(Tag::GeoKeyDirectoryTag, vec![1, 1, 0, 2, 1024, 0, 1, 1, 3076, 0, 1, 9003]);
    let r = placed(&dir, &[scale(20.0), tie(0.0, 0.0), feet]).unwrap();
    assert!((r.geometry.dx - 10.0 * 1200.0 / 3937.0).abs() < 1e-12, "{:?}", r.geometry);
    // No georeference at all: unit spacing at the origin, still flipped (a TIFF's first row
    // is its top).
    let r = placed(&dir, &[]).unwrap();
    assert!(!r.info.georeferenced);
    assert_eq!(r.geometry, GridGeometry::unit());
    assert_eq!(r.samples, [3.0, 4.0, 5.0, 0.0, 1.0, 2.0]);
    // Half a georeference is refused.
    assert!(matches!(placed(&dir, &[scale(20.0)]), Err(IoError::Unsupported { .. })));
    let zero = placed(
        &dir,
        &[Extra::Doubles(Tag::ModelPixelScaleTag, vec![0.0, 1.0, 0.0]), tie(0.0, 0.0)],
    );
    assert!(matches!(zero, Err(IoError::Format { .. })));
}

fn geographic_pixel_is_point_raster_is_placed_in_metres() {
    let dir = TestDir::new("geographic");
    // An SRTM-like layout: 1 arc-second samples, the first sample's centre at (-84 E, 37 N).
    let arc1 = 1.0 / 3600.0;
    let extras = [
        Extra::Doubles(Tag::ModelPixelScaleTag, vec![arc1, arc1, 0.0]),
        Extra::Doubles(Tag::ModelTiepointTag, vec![0.0, 0.0, 0.0, -84.0, 37.0, 0.0]),
        Extra::Shorts(
            Tag::GeoKeyDirectoryTag,
            vec![1, 1, 0, 3, 1024, 0, 1, 2, 1025, 0, 1, 2, 2048, 0, 1, 4326],
        ),
    ];
    let r = placed(&dir, &extras).unwrap();
    let degrees = r.info.from_degrees.unwrap();
    let (west, north) = (-84.0 - arc1 / 2.0, 37.0 + arc1 / 2.0);
    let south = north - 2.0 * arc1;
    assert!((degrees.latitude - (37.0 - arc1 / 2.0)).abs() < 1e-12, "{degrees:?}");
    let (per_lon, per_lat) = metres_per_degree(degrees.latitude);
    let g = r.geometry;
    assert!((g.dx - arc1 * per_lon).abs() < 1e-9 && (g.dy - arc1 * per_lat).abs() < 1e-9);
    assert!(close(g.origin, DVec2::new(west * per_lon, south * per_lat)), "{g:?}");
    // Latitudes past the poles are refused.
    let extras = [
        Extra::Doubles(Tag::ModelPixelScaleTag, vec![1.0, 60.0, 0.0]),
        Extra::Doubles(Tag::ModelTiepointTag, vec![0.0, 0.0, 0.0, 0.0, 95.0, 0.0]),
        Extra::Shorts(Tag::GeoKeyDirectoryTag, vec![1, 1, 0, 1, 1024, 0, 1, 2]),
    ];
    assert!(matches!(placed(&dir, &extras), Err(IoError::Format { .. })));
}

// ---------------------------------------------------------------------------------------------
// Broken and unsupported files.

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

/// Where the value (or the offset of the values) of `tag` sits in a little-endian classic
/// TIFF's first IFD.
fn entry_value_at(bytes: &[u8], tag: u16) -> usize {
    let u16_at = |at: usize| u16::from_le_bytes([bytes[at], bytes[at + 1]]);
    let ifd = u32::from_le_bytes(bytes[4..8].try_into().unwrap()) as usize;
    (0..usize::from(u16_at(ifd)))
        .map(|k| ifd + 2 + 12 * k)
        .find(|&entry| u16_at(entry) == tag)
        .map(|entry| entry + 8)
        .unwrap_or_else(|| panic!("no tag {tag}"))
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
