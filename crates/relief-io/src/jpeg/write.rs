//! Writing an 8-bit RGB picture as a baseline JPEG.

use crate::atomic_write::write_atomically;
use crate::IoError;
use jpeg_encoder::{ColorType, Encoder, EncodingError};
use std::path::Path;

/// The JPEG quality relief writes pictures at (0 to 100): no visible loss on terrain.
pub const JPEG_QUALITY: u8 = 92;

/// Writes a `width x height` 8-bit RGB JPEG from `rgb`, three bytes per pixel, rows from the
/// top, at [`JPEG_QUALITY`].
///
/// The file is written atomically. [`IoError::InvalidData`] when the image is empty, larger
/// than the 65535 pixels a side JPEG allows, or `rgb` does not hold `width * height * 3` bytes.
pub fn write_jpeg_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), IoError> {
    let (Ok(w), Ok(h)) = (u16::try_from(width), u16::try_from(height)) else {
        return Err(IoError::invalid_data(
            path,
            format!("a {width}x{height} picture is larger than a JPEG holds (65535 a side)"),
        ));
    };
    if w == 0 || h == 0 || rgb.len() != width as usize * height as usize * 3 {
        return Err(IoError::invalid_data(
            path,
            format!("{} bytes are not a {width}x{height} RGB picture", rgb.len()),
        ));
    }
    write_atomically(path, |out| {
        let encoder = Encoder::new(out, JPEG_QUALITY);
        encoder.encode(rgb, w, h, ColorType::Rgb).map_err(|e| match e {
            EncodingError::IoError(e) => IoError::io(path, e),
            other => IoError::invalid_data(path, other.to_string()),
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;

    /// The width and height in a JPEG's baseline frame header (SOF0).
    fn frame_size(bytes: &[u8]) -> Option<(u16, u16)> {
        let at = bytes.windows(2).position(|m| m == [0xFF, 0xC0])?;
        let be = |i: usize| u16::from_be_bytes([bytes[i], bytes[i + 1]]);
        Some((be(at + 7), be(at + 5)))
    }

    #[test]
    fn writes_a_baseline_jpeg_of_the_picture_size() {
        let dir = TestDir::new("jpeg-write");
        let path = dir.path().join("picture.jpg");
        let rgb: Vec<u8> = (0..37 * 21 * 3).map(|i| (i % 251) as u8).collect();
        write_jpeg_rgb8(&path, 37, 21, &rgb).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..2], &[0xFF, 0xD8], "start of image");
        assert_eq!(&bytes[bytes.len() - 2..], &[0xFF, 0xD9], "end of image");
        assert_eq!(frame_size(&bytes), Some((37, 21)));
    }

    #[test]
    fn refuses_pictures_a_jpeg_cannot_hold() {
        let dir = TestDir::new("jpeg-refuse");
        let path = dir.path().join("picture.jpg");
        assert!(write_jpeg_rgb8(&path, 70000, 1, &[0; 210000]).is_err());
        assert!(write_jpeg_rgb8(&path, 2, 2, &[0; 11]).is_err());
        assert!(!path.exists());
    }
}
