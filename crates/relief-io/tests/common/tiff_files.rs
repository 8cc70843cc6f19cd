//! Small GeoTIFFs made for the tests: float32 or int16 samples in strips (by the `tiff`
//! crate's encoder) or in tiles (assembled here), with any codec relief reads.
#![allow(dead_code)]

use std::io::Cursor;
use tiff::encoder::colortype::ColorType;
use tiff::encoder::compression::{CompressionAlgorithm, Deflate, DeflateLevel, Lzw, Packbits};
use tiff::encoder::{Compression, Predictor, TiffEncoder, TiffValue};
use tiff::tags::Tag;

/// A tag added to a generated file.
pub enum Extra {
    Ascii(Tag, &'static str),
    Doubles(Tag, Vec<f64>),
    Shorts(Tag, Vec<u16>),
}

/// A projected placement: pixels of `dx x dy` m, north-west corner at (`west`, `north`).
pub fn projected(dx: f64, dy: f64, west: f64, north: f64) -> Vec<Extra> {
    vec![
        Extra::Doubles(Tag::ModelPixelScaleTag, vec![dx, dy, 0.0]),
        Extra::Doubles(Tag::ModelTiepointTag, vec![0.0, 0.0, 0.0, west, north, 0.0]),
        Extra::Shorts(Tag::GeoKeyDirectoryTag, vec![1, 1, 0, 1, 1024, 0, 1, 1]),
    ]
}

/// A file of one image in strips of `rows_per_strip` rows, made by the `tiff` crate.
pub fn encode_strips<C: ColorType>(
    values: &[C::Inner],
    size: (u32, u32),
    compression: Compression,
    rows_per_strip: Option<u32>,
    extras: &[Extra],
) -> Vec<u8>
where
    [C::Inner]: TiffValue,
{
    encode_predicted_strips::<C>(
        values,
        size,
        (compression, Predictor::None),
        rows_per_strip,
        extras,
    )
}

/// [`encode_strips`] with a predictor.
pub fn encode_predicted_strips<C: ColorType>(
    values: &[C::Inner],
    (width, height): (u32, u32),
    (compression, predictor): (Compression, Predictor),
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
        write_extra(image.encoder(), extra);
    }
    image.write_data(values).unwrap();
    file.into_inner()
}

fn write_extra<W: std::io::Write + std::io::Seek, K: tiff::encoder::TiffKind>(
    encoder: &mut tiff::encoder::DirectoryEncoder<'_, W, K>,
    extra: &Extra,
) {
    match extra {
        Extra::Ascii(tag, text) => encoder.write_tag(*tag, *text),
        Extra::Doubles(tag, values) => encoder.write_tag(*tag, &values[..]),
        Extra::Shorts(tag, values) => encoder.write_tag(*tag, &values[..]),
    }
    .unwrap();
}

/// How a hand-made tiled file compresses its tiles.
#[derive(Debug, Clone, Copy)]
pub enum TileCodec {
    None,
    Lzw,
    Deflate,
    PackBits,
    Zstd,
}

impl TileCodec {
    pub const ALL: [TileCodec; 5] =
        [TileCodec::None, TileCodec::Lzw, TileCodec::Deflate, TileCodec::PackBits, TileCodec::Zstd];

    fn code(self) -> u16 {
        match self {
            TileCodec::None => 1,
            TileCodec::Lzw => 5,
            TileCodec::Deflate => 8,
            TileCodec::PackBits => 32773,
            TileCodec::Zstd => 50000,
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
            TileCodec::Zstd => {
                let level = ruzstd::encoding::CompressionLevel::Fastest;
                ruzstd::encoding::compress(bytes, &mut out, level);
            }
        }
        out
    }
}

/// A hand-made tiled file of float32 samples (row 0 north) in `tile x tile` tiles (padded at
/// the right and bottom edges with zeros), compressed with `codec`; `sparse` tiles are
/// stored with no bytes.
pub fn encode_f32_tiles(
    values: &[f32],
    (width, height): (usize, usize),
    tile: usize,
    codec: TileCodec,
    sparse: &[usize],
    extras: &[Extra],
) -> Vec<u8> {
    let mut file = Cursor::new(Vec::new());
    let mut tiff = TiffEncoder::new(&mut file).unwrap();
    let mut dir = tiff.image_directory().unwrap();
    let (mut offsets, mut counts) = (Vec::<u32>::new(), Vec::<u32>::new());
    for ty in 0..height.div_ceil(tile) {
        for tx in 0..width.div_ceil(tile) {
            if sparse.contains(&(ty * width.div_ceil(tile) + tx)) {
                offsets.push(0);
                counts.push(0);
                continue;
            }
            let mut raw = vec![0u8; tile * tile * 4];
            for r in 0..tile {
                for c in 0..tile {
                    let (x, y) = (tx * tile + c, ty * tile + r);
                    if x < width && y < height {
                        let bytes = values[y * width + x].to_ne_bytes();
                        raw[(r * tile + c) * 4..][..4].copy_from_slice(&bytes);
                    }
                }
            }
            let packed = codec.compress(&raw);
            offsets.push(dir.write_data(&packed[..]).unwrap() as u32);
            counts.push(packed.len() as u32);
        }
    }
    dir.write_tag(Tag::ImageWidth, width as u32).unwrap();
    dir.write_tag(Tag::ImageLength, height as u32).unwrap();
    dir.write_tag(Tag::BitsPerSample, 32u16).unwrap();
    dir.write_tag(Tag::Compression, codec.code()).unwrap();
    dir.write_tag(Tag::PhotometricInterpretation, 1u16).unwrap();
    dir.write_tag(Tag::SamplesPerPixel, 1u16).unwrap();
    dir.write_tag(Tag::TileWidth, tile as u32).unwrap();
    dir.write_tag(Tag::TileLength, tile as u32).unwrap();
    dir.write_tag(Tag::TileOffsets, &offsets[..]).unwrap();
    dir.write_tag(Tag::TileByteCounts, &counts[..]).unwrap();
    dir.write_tag(Tag::SampleFormat, 3u16).unwrap();
    for extra in extras {
        write_extra(&mut dir, extra);
    }
    dir.finish().unwrap();
    file.into_inner()
}
