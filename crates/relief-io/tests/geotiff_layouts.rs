//! GeoTIFFs of every sample type, compression, predictor and chunk layout read as their
//! samples, nodata and sparse chunks as voids, and reading's peak memory: the samples and one
//! strip, never the decoded file.

mod common;
#[path = "common/geotiff_cases.rs"]
mod geotiff_cases;
#[path = "common/peak_heap.rs"]
mod peak_heap;

use common::TestDir;
use geotiff_cases::*;
use peak_heap::peak_heap;

use relief_core::DVec2;
use relief_io::geotiff::read_geotiff;
use tiff::encoder::colortype::{self, ColorType};
use tiff::encoder::compression::DeflateLevel;
use tiff::encoder::{Compression, Predictor, TiffValue};
use tiff::tags::Tag;

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

#[test]
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

#[test]
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

#[test]
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

#[test]
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
