//! Reading a PNG image as 8-bit RGB, e.g. a colour texture to drape over a terrain.

use crate::input_file::open_input;
use crate::IoError;
use png::{ColorType, DecodingError, Transformations};
use std::io::{BufReader, ErrorKind};
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
    let map = |e: DecodingError| match e {
        DecodingError::IoError(e) if e.kind() == ErrorKind::UnexpectedEof => {
            IoError::format(path, "truncated")
        }
        DecodingError::IoError(e) => IoError::io(path, e),
        other => IoError::format(path, other.to_string()),
    };
    let mut decoder = png::Decoder::new(BufReader::new(file));
    decoder.set_transformations(Transformations::EXPAND | Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(map)?;
    let (width, height) = reader.info().size();
    let size = reader.output_buffer_size().filter(|&n| {
        n as u64 <= file_len.saturating_mul(MAX_BYTES_PER_FILE_BYTE)
    });
    let Some(size) = size else {
        return Err(IoError::format(
            path,
            format!("{width} x {height} pixels cannot fit in a file of {file_len} bytes"),
        ));
    };
    let mut buf = vec![0u8; size];
    let frame = reader.next_frame(&mut buf).map_err(map)?;
    let (width, height) = (frame.width, frame.height);
    let channels = match frame.color_type {
        ColorType::Grayscale => 1,
        ColorType::GrayscaleAlpha => 2,
        ColorType::Rgb => 3,
        ColorType::Rgba => 4,
        ColorType::Indexed => {
            return Err(IoError::unsupported(path, "palette image that did not expand to RGB"))
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
        return Err(IoError::format(path, "decoded frame is smaller than the image"));
    }
    Ok(RgbImage { width, height, pixels })
}
