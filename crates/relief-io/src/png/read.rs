//! Reading a PNG image as 8-bit RGB, e.g. a colour texture to drape over a terrain.

use crate::format_error::FormatError;
use crate::input_file::open_input;
use crate::png::decoding_error::png_decoding_error;
use crate::IoError;
use png::{ColorType, Transformations};
use std::io::{BufRead, BufReader, Seek};
use std::path::Path;

/// The largest inflation deflate allows (about 1032:1) times the largest growth of a pixel
/// through the transformations (1-bit palette index to 32-bit RGBA): bounds the pixel bytes
/// a file of a given length can hold, so a lying header cannot make us allocate.
const MAX_BYTES_PER_FILE_BYTE: u64 = 1032 * 32;

/// An 8-bit RGB image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, row by row, row 0 the top row of the image.
    pub pixels: Vec<[u8; 3]>,
}

/// Reads the PNG at `path` as 8-bit RGB.
///
/// Greyscale, greyscale with alpha, RGB, RGBA and palette images of any bit depth are accepted:
/// 16-bit samples are reduced to 8 bits, grey is replicated into the three channels and alpha
/// is ignored. Only the first frame of an animated PNG is read.
///
/// Errors: [`IoError::Io`] when the file cannot be read, [`IoError::Format`] for a file that is
/// not a valid PNG or is truncated.
pub fn read_png_rgb(path: &Path) -> Result<RgbImage, IoError> {
    let (file, file_len) = open_input(path)?;
    read_png_rgb_from(BufReader::new(file), file_len).map_err(|e| e.at(path))
}

/// [`read_png_rgb`] from `reader` holding the `file_len` bytes of a PNG, before the file is
/// named.
fn read_png_rgb_from<R: BufRead + Seek>(reader: R, file_len: u64) -> Result<RgbImage, FormatError> {
    let mut decoder = png::Decoder::new(reader);
    decoder.set_transformations(Transformations::EXPAND | Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(png_decoding_error)?;
    let (width, height) = reader.info().size();
    let size = reader
        .output_buffer_size()
        .filter(|&n| n as u64 <= file_len.saturating_mul(MAX_BYTES_PER_FILE_BYTE));
    let Some(size) = size else {
        return Err(FormatError::Format(format!(
            "{width} x {height} pixels cannot fit in a file of {file_len} bytes"
        )));
    };
    let mut buf = vec![0u8; size];
    let frame = reader.next_frame(&mut buf).map_err(png_decoding_error)?;
    let (width, height) = (frame.width, frame.height);
    let channels = match frame.color_type {
        ColorType::Grayscale => 1,
        ColorType::GrayscaleAlpha => 2,
        ColorType::Rgb => 3,
        ColorType::Rgba => 4,
        ColorType::Indexed => {
            return Err(FormatError::Unsupported("palette image that did not expand to RGB".into()))
        }
    };
    let line = frame.line_size;
    let mut pixels = Vec::with_capacity(width as usize * height as usize);
    for row in buf.chunks_exact(line.max(1)).take(height as usize) {
        pixels.extend(row.chunks_exact(channels).take(width as usize).map(|p| match *p {
            [g] | [g, _] => [g, g, g],
            [r, g, b] | [r, g, b, _] => [r, g, b],
            _ => [0, 0, 0],
        }));
    }
    if pixels.len() != width as usize * height as usize {
        return Err(FormatError::Format("decoded frame is smaller than the image".into()));
    }
    Ok(RgbImage { width, height, pixels })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::png::{write_png_gray16, write_png_rgb8};
    use crate::test_dir::TestDir;
    use png::BitDepth;

    /// Encodes a PNG with the given colour type, depth, palette and raw data.
    fn encode(
        path: &Path,
        (width, height): (u32, u32),
        color: ColorType,
        depth: BitDepth,
        palette: Option<Vec<u8>>,
        data: &[u8],
    ) {
        let file = std::fs::File::create(path).unwrap();
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
        encoder.set_color(color);
        encoder.set_depth(depth);
        if let Some(p) = palette {
            encoder.set_palette(p);
        }
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(data).unwrap();
        writer.finish().unwrap();
    }

    #[test]
    fn rgb8_round_trips_with_row_zero_at_the_top() {
        let dir = TestDir::new("png-rgb");
        let path = dir.path().join("rgb.png");
        let rgb: Vec<u8> = (0..2 * 3 * 3).map(|v| (v * 13) as u8).collect();
        write_png_rgb8(&path, 2, 3, &rgb).unwrap();
        let image = read_png_rgb(&path).unwrap();
        assert_eq!((image.width, image.height), (2, 3));
        let flat: Vec<u8> = image.pixels.iter().flatten().copied().collect();
        assert_eq!(flat, rgb);
    }

    #[test]
    fn every_compression_level_round_trips_and_the_levels_trade_size() {
        let dir = TestDir::new("png-levels");
        let (w, h) = (64u32, 48u32);
        // A smooth gradient with some noise: compressible, as rendered pictures are.
        let rgb: Vec<u8> =
            (0..w * h * 3).map(|v| ((v / 3 % w) * 3 + (v * 7919 % 5)) as u8).collect();
        let mut sizes = Vec::new();
        for level in crate::PngCompression::ALL {
            let path = dir.path().join(format!("{level}.png"));
            crate::write_png_rgb8_compressed(&path, w, h, &rgb, level).unwrap();
            let image = read_png_rgb(&path).unwrap();
            assert_eq!(image.pixels.as_flattened(), &rgb[..], "{level}");
            assert_eq!(level.name().parse::<crate::PngCompression>(), Ok(level));
            sizes.push(std::fs::metadata(&path).unwrap().len());
        }
        assert!(sizes[0] > sizes[1] && sizes[1] >= sizes[3], "sizes {sizes:?}");
        assert!("fastest".parse::<crate::PngCompression>().is_err());
    }

    #[test]
    fn other_colour_types_become_rgb() {
        let dir = TestDir::new("png-kinds");
        let path = dir.path().join("kind.png");
        let expected = vec![[10, 10, 10], [200, 200, 200]];
        encode(&path, (2, 1), ColorType::Grayscale, BitDepth::Eight, None, &[10, 200]);
        assert_eq!(read_png_rgb(&path).unwrap().pixels, expected);
        let ga = [10, 255, 200, 0];
        encode(&path, (2, 1), ColorType::GrayscaleAlpha, BitDepth::Eight, None, &ga);
        assert_eq!(read_png_rgb(&path).unwrap().pixels, expected);
        let rgba = [1, 2, 3, 255, 4, 5, 6, 0];
        encode(&path, (2, 1), ColorType::Rgba, BitDepth::Eight, None, &rgba);
        assert_eq!(read_png_rgb(&path).unwrap().pixels, vec![[1, 2, 3], [4, 5, 6]]);
        let palette = Some(vec![9, 8, 7, 1, 2, 3]);
        // Two 1-bit indices, 1 then 0, packed into one byte.
        encode(&path, (2, 1), ColorType::Indexed, BitDepth::One, palette, &[0b1000_0000]);
        assert_eq!(read_png_rgb(&path).unwrap().pixels, vec![[1, 2, 3], [9, 8, 7]]);
        write_png_gray16(&path, 2, 1, &[0x1234, 0xff00]).unwrap();
        assert_eq!(read_png_rgb(&path).unwrap().pixels, vec![[0x12; 3], [0xff; 3]]);
    }

    #[test]
    fn broken_files_are_format_errors_and_missing_ones_io_errors() {
        let dir = TestDir::new("png-broken");
        let path = dir.path().join("broken.png");
        let rgb = vec![7u8; 16 * 16 * 3];
        write_png_rgb8(&path, 16, 16, &rgb).unwrap();
        let good = std::fs::read(&path).unwrap();
        for len in [0, 7, 20, good.len() / 2, good.len() - 13] {
            std::fs::write(&path, &good[..len]).unwrap();
            let err = read_png_rgb(&path).unwrap_err();
            assert!(matches!(err, IoError::Format { .. }), "prefix of {len}: {err}");
        }
        std::fs::write(&path, b"not a png at all").unwrap();
        assert!(matches!(read_png_rgb(&path), Err(IoError::Format { .. })));
        assert!(matches!(read_png_rgb(&dir.path().join("absent.png")), Err(IoError::Io { .. })));
        assert!(matches!(read_png_rgb(dir.path()), Err(IoError::Io { .. })));
    }

    #[test]
    fn header_claiming_more_pixels_than_the_file_can_hold_is_refused() {
        let dir = TestDir::new("png-lie");
        let path = dir.path().join("lie.png");
        write_png_rgb8(&path, 1, 1, &[1, 2, 3]).unwrap();
        let mut bytes = std::fs::read(&path).unwrap();
        // IHDR width and height live at bytes 16..24; fix the chunk's CRC after them.
        bytes[16..24].copy_from_slice(&[0, 0, 0x40, 0, 0, 0, 0x40, 0]);
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        std::fs::write(&path, &bytes).unwrap();
        let err = read_png_rgb(&path).unwrap_err();
        assert!(matches!(err, IoError::Format { .. }), "{err}");
        assert!(err.to_string().contains("16384 x 16384 pixels cannot fit"), "{err}");
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

    #[test]
    fn writers_refuse_buffers_of_the_wrong_size() {
        let dir = TestDir::new("png-sizes");
        let path = dir.path().join("x.png");
        let err = write_png_rgb8(&path, 2, 2, &[0; 11]).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        assert!(matches!(write_png_gray16(&path, 0, 2, &[]), Err(IoError::InvalidData { .. })));
        assert!(!path.exists());
    }
}
