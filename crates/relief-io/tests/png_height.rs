//! Heights in PNG images: 16-bit and 8-bit greyscale, terrain-RGB and Terrarium pixels,
//! interlacing, colour types that do not fit the encoding, broken and lying files.

mod common;
#[path = "common/reading.rs"]
mod reading;

use common::TestDir;
use reading::{
    assert_format, assert_none_read, check_truncations_and_flips, options, png_options, read_bytes,
    same_samples,
};

use relief_core::{GridGeometry, HeightField};
use relief_io::png::{read_png_height, write_png16_height};
use relief_io::{Format, IoError, PngEncoding, Raster, ReadOptions};
use std::io::Write;

/// Encodes a PNG of `color`/`depth` with `data` rows from the top.
fn encode_png(
    (width, height): (u32, u32),
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
) -> Vec<u8> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(color);
    encoder.set_depth(depth);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(data).unwrap();
    writer.finish().unwrap();
    out
}

#[test]
fn png16_round_trips_with_the_top_row_north() {
    let dir = TestDir::new("png16-round");
    let path = dir.join("heights.png");
    let (w, h) = (5, 4);
    let samples: Vec<f32> = (0..w * h).map(|i| (i * 3449 % 65536) as f32).collect();
    let holes: Vec<bool> = (0..w * h).map(|i| i == 7).collect();
    let field = HeightField::new(w, h, samples.clone(), GridGeometry::unit())
        .unwrap()
        .with_holes(holes)
        .unwrap();
    write_png16_height(&path, &field).unwrap();
    let raster = read_png_height(&path, &options()).unwrap();
    // Whole heights in 0..=65535 are stored as they are; the hole is transparent, a void.
    let mut expected = samples;
    expected[7] = f32::NAN;
    assert!(same_samples(&raster, &Raster { samples: expected.clone(), ..raster.clone() }));
    assert_eq!(raster.info.format, Format::Png16);
    assert_eq!(raster.info.sample_type, "uint16");
    assert!(!raster.info.georeferenced);
    // The image's top row is the field's last (north) row.
    let image = relief_io::png::read_png_rgb(&path).unwrap();
    let top_left = (expected[(h - 1) * w] as u32 >> 8) as u8;
    assert_eq!(image.pixels[0], [top_left; 3]);
}

#[test]
fn png16_heights_use_their_16_bits_and_round_trip_within_their_step() {
    let dir = TestDir::new("png16-step");
    let path = dir.join("heights.png");
    // Fractional heights, negative ones, past 65535: each read back within half a step.
    for (low, high) in [(0.0f32, 188.7), (-12.25, 3.5), (-400.0, 90_000.0), (1.4, 65534.6)] {
        let (w, h) = (7, 5);
        let samples: Vec<f32> =
            (0..w * h).map(|i| low + (high - low) * ((i * 17 % 35) as f32 / 34.0)).collect();
        let field = HeightField::new(w, h, samples.clone(), GridGeometry::unit()).unwrap();
        let scale = relief_io::png::PngHeightScale::of(&field);
        write_png16_height(&path, &field).unwrap();
        let raster = read_png_height(&path, &options()).unwrap();
        let step = (f64::from(high) - f64::from(low)) / 65535.0;
        assert!((scale.scale - step).abs() < 1e-9 * step.max(1.0), "{scale:?}");
        for (got, want) in raster.samples.iter().zip(&samples) {
            let error = (f64::from(*got) - f64::from(*want)).abs();
            let rounding = f64::from(want.abs()) * 1e-7;
            assert!(error <= 0.5 * step + rounding, "{got} vs {want}, step {step}");
        }
        assert_eq!(raster.info.height_unit.unit, relief_io::LengthUnit::Metre);
        assert!(!raster.info.height_unit.is_assumed());
    }
    // The unit written is the unit read: heights in feet come back with a z scale to metres.
    let field = HeightField::new(2, 1, vec![10.5, 20.25], GridGeometry::unit()).unwrap();
    relief_io::png::write_png16_height_in(&path, &field, relief_io::LengthUnit::Foot).unwrap();
    let raster = read_png_height(&path, &options()).unwrap();
    assert_eq!(raster.info.height_unit.unit, relief_io::LengthUnit::Foot);
    assert_eq!(raster.geometry.z_scale, 0.3048);
}

#[test]
fn grey8_png_heights_and_orientation() {
    let dir = TestDir::new("png8");
    let path = dir.join("grey.png");
    let bytes =
        encode_png((3, 2), png::ColorType::Grayscale, png::BitDepth::Eight, &[9, 9, 9, 1, 2, 3]);
    let raster = read_bytes(read_png_height, &path, &bytes, &options()).unwrap();
    assert_eq!(raster.samples, [1.0, 2.0, 3.0, 9.0, 9.0, 9.0]);
    assert_eq!(raster.info.sample_type, "uint8");
}

#[test]
fn terrain_rgb_and_terrarium_pixels_decode_to_known_heights() {
    let dir = TestDir::new("png-rgb");
    let path = dir.join("tile.png");
    // Top row first: the second row is the raster's first.
    let terrain_rgb: [([u8; 3], f32); 4] = [
        ([1, 134, 160], 0.0), // 100000 * 0.1 - 10000
        ([0, 0, 0], -10000.0),
        ([1, 135, 5], 10.1),  // 100101 * 0.1 - 10000
        ([3, 0, 20], 9662.8), // 196628 * 0.1 - 10000
    ];
    let data: Vec<u8> = terrain_rgb.iter().flat_map(|(p, _)| *p).collect();
    let bytes = encode_png((2, 2), png::ColorType::Rgb, png::BitDepth::Eight, &data);
    let options = png_options(PngEncoding::TerrainRgb);
    let raster = read_bytes(read_png_height, &path, &bytes, &options).unwrap();
    let expected = [terrain_rgb[2].1, terrain_rgb[3].1, terrain_rgb[0].1, terrain_rgb[1].1];
    for (got, want) in raster.samples.iter().zip(expected) {
        assert!((got - want).abs() < 1e-3, "{got} != {want}");
    }
    assert_eq!(raster.info.format, Format::TerrainRgb);

    let terrarium: [([u8; 4], f32); 4] = [
        ([128, 0, 0, 255], 0.0),
        ([128, 100, 128, 255], 100.5),
        ([0, 0, 0, 255], -32768.0),
        ([121, 42, 64, 0], f32::NAN), // transparent: a void
    ];
    let data: Vec<u8> = terrarium.iter().flat_map(|(p, _)| *p).collect();
    let bytes = encode_png((4, 1), png::ColorType::Rgba, png::BitDepth::Eight, &data);
    let options = png_options(PngEncoding::Terrarium);
    let raster = read_bytes(read_png_height, &path, &bytes, &options).unwrap();
    assert_eq!(&raster.samples[..3], &[0.0, 100.5, -32768.0]);
    assert!(raster.samples[3].is_nan());
    assert_eq!((raster.info.format, raster.void_count()), (Format::Terrarium, 1));
    // 0x79 * 256 + 0x2a + 0x40 / 256 - 32768 for the same pixel made opaque.
    let data = [121, 42, 64];
    let bytes = encode_png((1, 1), png::ColorType::Rgb, png::BitDepth::Eight, &data);
    let raster = read_bytes(read_png_height, &path, &bytes, &options).unwrap();
    assert_eq!(raster.samples, [121.0 * 256.0 + 42.0 + 0.25 - 32768.0]);
}

#[test]
fn png_colour_type_that_does_not_fit_the_encoding_is_unsupported() {
    let dir = TestDir::new("png-kind");
    let path = dir.join("tile.png");
    let grey16 = encode_png((1, 1), png::ColorType::Grayscale, png::BitDepth::Sixteen, &[1, 2]);
    let rgb = encode_png((1, 1), png::ColorType::Rgb, png::BitDepth::Eight, &[1, 2, 3]);
    let rgb16 = encode_png((1, 1), png::ColorType::Rgb, png::BitDepth::Sixteen, &[0; 6]);
    let cases = [
        (&grey16, PngEncoding::TerrainRgb, "16-bit greyscale"),
        (&grey16, PngEncoding::Terrarium, "16-bit greyscale"),
        (&rgb, PngEncoding::Grey, "8-bit RGB"),
        (&rgb16, PngEncoding::TerrainRgb, "16-bit RGB"),
    ];
    for (bytes, encoding, colour) in cases {
        let err = read_bytes(read_png_height, &path, bytes, &png_options(encoding)).unwrap_err();
        assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
        let message = err.to_string();
        assert!(message.contains(colour) && message.contains("--png-encoding"), "{message}");
    }
}

#[test]
fn png_truncations_corruptions_and_lying_headers_give_errors() {
    let dir = TestDir::new("png-fuzz");
    let path = dir.join("tile.png");
    let field =
        HeightField::new(3, 2, vec![1.0, 2.0, 300.0, 4.0, 5.0, 60000.0], GridGeometry::unit())
            .unwrap();
    write_png16_height(&path, &field).unwrap();
    let good = std::fs::read(&path).unwrap();
    // Every chunk carries a CRC-32 and the image data an Adler-32: no changed byte reads.
    let (_, accepted) =
        check_truncations_and_flips(read_png_height, &path, &good, &options(), |_| false);
    assert_none_read(&accepted);
    let data = [1, 2, 3, 4, 5, 6, 7, 8];
    let rgba = encode_png((2, 1), png::ColorType::Rgba, png::BitDepth::Eight, &data);
    let options = png_options(PngEncoding::TerrainRgb);
    let (_, accepted) =
        check_truncations_and_flips(read_png_height, &path, &rgba, &options, |_| false);
    assert_none_read(&accepted);

    // IHDR claims 16384 x 16384 pixels in a file of a few dozen bytes.
    let mut bytes = good.clone();
    bytes[16..24].copy_from_slice(&[0, 0, 0x40, 0, 0, 0, 0x40, 0]);
    let crc = crc32(&bytes[12..29]);
    bytes[29..33].copy_from_slice(&crc.to_be_bytes());
    let unlimited = ReadOptions { max_memory: u64::MAX, ..ReadOptions::default() };
    assert_format(read_bytes(read_png_height, &path, &bytes, &unlimited), "cannot fit");
    let err = read_bytes(
        read_png_height,
        &path,
        &bytes,
        &ReadOptions { max_memory: 1 << 20, ..unlimited },
    )
    .unwrap_err();
    assert!(matches!(err, IoError::Limits { width: 16384, height: 16384, .. }), "{err}");
}

#[test]
fn interlaced_png_heights_are_read_with_the_top_row_north() {
    // A 3 x 2 Adam7 image, 8-bit grey: top row 10 20 30, bottom row 40 50 60. Its passes
    // hold (0,0); (2,0); (1,0); then the whole second row, each line after filter byte 0.
    let raw = [0, 10, 0, 30, 0, 20, 0, 40, 50, 60];
    let mut zlib = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    zlib.write_all(&raw).unwrap();
    let idat = zlib.finish().unwrap();
    let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
    let ihdr = [0, 0, 0, 3, 0, 0, 0, 2, 8, 0, 0, 0, 1];
    for (kind, data) in [(&b"IHDR"[..], &ihdr[..]), (b"IDAT", &idat), (b"IEND", &[])] {
        bytes.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let start = bytes.len();
        bytes.extend_from_slice(kind);
        bytes.extend_from_slice(data);
        let crc = crc32(&bytes[start..]);
        bytes.extend_from_slice(&crc.to_be_bytes());
    }
    let dir = TestDir::new("png-adam7");
    let path = dir.join("adam7.png");
    let raster = read_bytes(read_png_height, &path, &bytes, &options()).unwrap();
    assert_eq!(raster.samples, [40.0, 50.0, 60.0, 10.0, 20.0, 30.0]);
    // As every PNG: a CRC-32 per chunk, an Adler-32 over the pixels.
    let (_, accepted) =
        check_truncations_and_flips(read_png_height, &path, &bytes, &options(), |_| false);
    assert_none_read(&accepted);
}

/// The CRC-32 of PNG chunks.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
        }
    }
    !crc
}
