//! Writing 8-bit RGB and 16-bit greyscale PNG images.

use crate::atomic_write::write_atomically;
use crate::IoError;
use png::{BitDepth, ColorType, EncodingError};
use std::path::Path;

/// Writes a `width x height` 8-bit RGB PNG from `rgb`, three bytes per pixel, rows from the top.
///
/// The file is written atomically. [`IoError::InvalidData`] when the image is empty or `rgb`
/// does not hold exactly `width * height * 3` bytes.
pub fn write_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), IoError> {
    check_size(path, width, height, 3, rgb.len(), "bytes")?;
    write_png(path, width, height, ColorType::Rgb, BitDepth::Eight, rgb)
}

/// Writes a `width x height` 16-bit greyscale PNG from `gray`, one value per pixel, rows from
/// the top.
///
/// The file is written atomically. [`IoError::InvalidData`] when the image is empty or `gray`
/// does not hold exactly `width * height` values.
pub fn write_png_gray16(path: &Path, width: u32, height: u32, gray: &[u16]) -> Result<(), IoError> {
    check_size(path, width, height, 1, gray.len(), "values")?;
    let bytes: Vec<u8> = gray.iter().flat_map(|v| v.to_be_bytes()).collect();
    write_png(path, width, height, ColorType::Grayscale, BitDepth::Sixteen, &bytes)
}

/// Checks that the image has pixels and that `len` is `width * height * per_pixel`.
fn check_size(
    path: &Path,
    width: u32,
    height: u32,
    per_pixel: u64,
    len: usize,
    unit: &str,
) -> Result<(), IoError> {
    if width == 0 || height == 0 {
        return Err(IoError::invalid_data(
            path,
            format!("image of {width} x {height} pixels is empty"),
        ));
    }
    let needed = u64::from(width) * u64::from(height) * per_pixel;
    if needed != len as u64 {
        return Err(IoError::invalid_data(
            path,
            format!("a {width} x {height} image needs {needed} {unit}, got {len}"),
        ));
    }
    Ok(())
}

/// Encodes `data` (rows from the top, big-endian samples) as a PNG at `path`.
fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    color: ColorType,
    depth: BitDepth,
    data: &[u8],
) -> Result<(), IoError> {
    let map = |e: EncodingError| match e {
        EncodingError::IoError(e) => IoError::io(path, e),
        other => IoError::invalid_data(path, other.to_string()),
    };
    write_atomically(path, |w| {
        let mut encoder = png::Encoder::new(w, width, height);
        encoder.set_color(color);
        encoder.set_depth(depth);
        let mut writer = encoder.write_header().map_err(map)?;
        writer.write_image_data(data).map_err(map)?;
        writer.finish().map_err(map)
    })
}
