//! Writing 8-bit RGB and 16-bit greyscale PNG images.

use crate::atomic_write::write_atomically;
use crate::IoError;
use png::{BitDepth, ColorType, Compression, EncodingError};
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// How hard a picture's PNG is compressed: a trade of encoding time against file size.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PngCompression {
    /// Stored without compression: the fastest to write, the largest file.
    None,
    /// The `png` crate's fast mode (fdeflate): several times faster than `Balanced`, files a
    /// little larger. The default for rendered pictures.
    #[default]
    Fast,
    /// zlib's balanced level.
    Balanced,
    /// The smallest files, slowest to write.
    High,
}

impl PngCompression {
    /// Every level, fastest first.
    pub const ALL: [PngCompression; 4] = [
        PngCompression::None,
        PngCompression::Fast,
        PngCompression::Balanced,
        PngCompression::High,
    ];

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            PngCompression::None => "none",
            PngCompression::Fast => "fast",
            PngCompression::Balanced => "balanced",
            PngCompression::High => "high",
        }
    }

    fn to_png(self) -> Compression {
        match self {
            PngCompression::None => Compression::NoCompression,
            PngCompression::Fast => Compression::Fast,
            PngCompression::Balanced => Compression::Balanced,
            PngCompression::High => Compression::High,
        }
    }
}

impl fmt::Display for PngCompression {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for PngCompression {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        PngCompression::ALL.into_iter().find(|c| c.name() == s).ok_or_else(|| {
            format!("unknown PNG compression '{s}' (expected none, fast, balanced or high)")
        })
    }
}

/// Writes a `width x height` 8-bit RGB PNG from `rgb`, three bytes per pixel, rows from the
/// top, with [`PngCompression::Fast`] (see [`write_png_rgb8_compressed`]).
pub fn write_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), IoError> {
    write_png_rgb8_compressed(path, width, height, rgb, PngCompression::Fast)
}

/// Writes a `width x height` 8-bit RGB PNG from `rgb`, three bytes per pixel, rows from the
/// top, compressed as `compression` says.
///
/// The file is written atomically. [`IoError::InvalidData`] when the image is empty or `rgb`
/// does not hold exactly `width * height * 3` bytes.
pub fn write_png_rgb8_compressed(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[u8],
    compression: PngCompression,
) -> Result<(), IoError> {
    check_size(path, width, height, 3, rgb.len(), "bytes")?;
    let image = (ColorType::Rgb, BitDepth::Eight, compression);
    write_png(path, width, height, image, rgb, &[])
}

/// Writes a `width x height` 16-bit greyscale PNG from `gray`, one value per pixel, rows from
/// the top.
///
/// The file is written atomically. [`IoError::InvalidData`] when the image is empty or `gray`
/// does not hold exactly `width * height` values.
pub fn write_png_gray16(path: &Path, width: u32, height: u32, gray: &[u16]) -> Result<(), IoError> {
    check_size(path, width, height, 1, gray.len(), "values")?;
    let bytes: Vec<u8> = gray.iter().flat_map(|v| v.to_be_bytes()).collect();
    let compression = PngCompression::Balanced;
    let image = (ColorType::Grayscale, BitDepth::Sixteen, compression);
    write_png(path, width, height, image, &bytes, &[])
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

/// Encodes `data` (rows from the top, big-endian samples) as a PNG of `(colour, depth,
/// compression)` at `path`, with the tEXt chunks `text` (keyword, value) before the image data.
pub(crate) fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    (color, depth, compression): (ColorType, BitDepth, PngCompression),
    data: &[u8],
    text: &[(&str, String)],
) -> Result<(), IoError> {
    let map = |e: EncodingError| match e {
        EncodingError::IoError(e) => IoError::io(path, e),
        other => IoError::invalid_data(path, other.to_string()),
    };
    write_atomically(path, |w| {
        let mut encoder = png::Encoder::new(w, width, height);
        encoder.set_color(color);
        encoder.set_depth(depth);
        encoder.set_compression(compression.to_png());
        for (keyword, value) in text {
            encoder.add_text_chunk((*keyword).to_string(), value.clone()).map_err(map)?;
        }
        let mut writer = encoder.write_header().map_err(map)?;
        writer.write_image_data(data).map_err(map)?;
        writer.finish().map_err(map)
    })
}
