//! GeoTIFFs made for the GeoTIFF reader's tests with the `tiff` crate, in strips or tiles,
//! with placements and other tags, and the fixture they are held against.
#![allow(dead_code)]

use relief_io::{Raster, ReadOptions};
use std::io::Cursor;
use std::path::{Path, PathBuf};
use tiff::encoder::colortype::ColorType;
use tiff::encoder::compression::{CompressionAlgorithm, Deflate, DeflateLevel, Lzw, Packbits};
use tiff::encoder::{Compression, Predictor, TiffEncoder, TiffValue};
use tiff::tags::Tag;

pub fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/jacksboro_fault_dem.tif")
}

pub fn options() -> ReadOptions {
    ReadOptions { max_memory: 1 << 30, ..ReadOptions::default() }
}

/// A tag added to a generated file.
pub enum Extra {
    Ascii(Tag, &'static str),
    Doubles(Tag, Vec<f64>),
    Shorts(Tag, Vec<u16>),
}

/// A projected placement: pixels of 10 x 20 m, north-west corner at (1000, 5000).
pub fn projected() -> Vec<Extra> {
    vec![
        Extra::Doubles(Tag::ModelPixelScaleTag, vec![10.0, 20.0, 0.0]),
        Extra::Doubles(Tag::ModelTiepointTag, vec![0.0, 0.0, 0.0, 1000.0, 5000.0, 0.0]),
        Extra::Shorts(Tag::GeoKeyDirectoryTag, vec![1, 1, 0, 1, 1024, 0, 1, 1]),
    ]
}

/// A file of one image in strips, made by the `tiff` crate's encoder.
pub fn encode_strips<C: ColorType>(
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
pub enum TileCodec {
    None,
    Lzw,
    Deflate,
    PackBits,
}

impl TileCodec {
    pub const ALL: [TileCodec; 4] =
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
pub struct Samples {
    pub bytes: Vec<u8>,
    pub size: usize,
    pub bits: u16,
    pub format: u16,
}

/// TIFF's floating-point predictor over one row of `size`-byte samples.
pub fn float_predict(row: &mut [u8], size: usize) {
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
pub fn encode_tiles(
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
pub fn assert_north_up_samples(raster: &Raster, expected: &[f32], case: &str) {
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

/// Where the value (or the offset of the values) of `tag` sits in a little-endian classic
/// TIFF's first IFD.
pub fn entry_value_at(bytes: &[u8], tag: u16) -> usize {
    let u16_at = |at: usize| u16::from_le_bytes([bytes[at], bytes[at + 1]]);
    let ifd = u32::from_le_bytes(bytes[4..8].try_into().unwrap()) as usize;
    (0..usize::from(u16_at(ifd)))
        .map(|k| ifd + 2 + 12 * k)
        .find(|&entry| u16_at(entry) == tag)
        .map(|entry| entry + 8)
        .unwrap_or_else(|| panic!("no tag {tag}"))
}
