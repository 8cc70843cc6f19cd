//! Colour textures draped over the terrain's footprint, sampled bilinearly.

use relief_core::colour::srgb_to_linear;
use relief_core::DVec3;

use crate::ShadeError;

/// A linear-RGB image draped over the terrain: row 0 is the top (north) row, so texture
/// coordinate `v = 1` is the northern edge and `u = 0` the western edge.
#[derive(Debug, Clone, PartialEq)]
pub struct RgbTexture {
    width: usize,
    height: usize,
    pixels: Vec<[f32; 3]>,
}

impl RgbTexture {
    /// A texture from linear-RGB pixels, row-major, row 0 the top (north) row.
    ///
    /// Fails when the size is zero, the pixel count does not match or a channel is negative
    /// or not finite.
    pub fn new(width: usize, height: usize, pixels: Vec<[f32; 3]>) -> Result<Self, ShadeError> {
        if width == 0 || height == 0 || width.checked_mul(height) != Some(pixels.len()) {
            return Err(ShadeError::parameter(
                "texture",
                format!("{width} x {height} does not match its {} pixels", pixels.len()),
            ));
        }
        if let Some(k) = pixels.iter().position(|p| !p.iter().all(|c| c.is_finite() && *c >= 0.0)) {
            return Err(ShadeError::parameter(
                "texture",
                format!("pixel {k} {:?} has a negative or non-finite channel", pixels[k]),
            ));
        }
        Ok(RgbTexture { width, height, pixels })
    }

    /// A texture from interleaved 8-bit sRGB pixels (`R, G, B`, row 0 the top row), decoded to
    /// linear with the sRGB transfer function.
    pub fn from_srgb8(width: usize, height: usize, rgb: &[u8]) -> Result<Self, ShadeError> {
        if width.checked_mul(height).and_then(|n| n.checked_mul(3)) != Some(rgb.len()) {
            return Err(ShadeError::parameter(
                "texture",
                format!("{width} x {height} RGB needs 3 bytes per pixel, got {} bytes", rgb.len()),
            ));
        }
        let decode = |b: u8| srgb_to_linear(b as f32 / 255.0);
        let pixels = rgb.chunks_exact(3).map(|p| [decode(p[0]), decode(p[1]), decode(p[2])]);
        Self::new(width, height, pixels.collect())
    }

    /// Width in texels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The linear pixels, row-major, row 0 the top (north) row.
    pub fn pixels(&self) -> &[[f32; 3]] {
        &self.pixels
    }

    /// The bilinearly filtered colour at texture coordinates `(u, v)`: texel centres sit at
    /// `u = (col + 0.5) / width` and `v = 1 - (row + 0.5) / height`; outside the centres the
    /// edge texels are extended (clamp to edge). NaN coordinates read the centre of the image.
    pub fn sample_bilinear(&self, u: f64, v: f64) -> DVec3 {
        let (x0, x1, wx) = Self::taps(u, self.width);
        let (y0, y1, wy) = Self::taps(1.0 - v, self.height);
        let texel =
            |x: usize, y: usize| DVec3::from(self.pixels[x + y * self.width].map(f64::from));
        let top = texel(x0, y0).lerp(texel(x1, y0), wx);
        let bottom = texel(x0, y1).lerp(texel(x1, y1), wx);
        top.lerp(bottom, wy)
    }

    /// The two texel indices around coordinate `s` (0..1 over `n` texels) and the weight of the
    /// second.
    fn taps(s: f64, n: usize) -> (usize, usize, f64) {
        let s = if s.is_nan() { 0.5 } else { s };
        let x = (s * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
        let i0 = x.floor() as usize;
        let i1 = (i0 + 1).min(n - 1);
        (i0, i1, x - i0 as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_zero_is_north_and_interpolation_is_linear() {
        // 2 x 2: top row (north) red, green; bottom row (south) blue, white.
        let px = vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
        let t = RgbTexture::new(2, 2, px).unwrap();
        assert_eq!(t.sample_bilinear(0.25, 0.75), DVec3::X, "north-west texel centre");
        assert_eq!(t.sample_bilinear(0.75, 0.75), DVec3::Y, "north-east");
        assert_eq!(t.sample_bilinear(0.25, 0.25), DVec3::Z, "south-west");
        assert_eq!(t.sample_bilinear(0.0, 1.0), DVec3::X, "clamped at the corner");
        assert_eq!(t.sample_bilinear(0.5, 0.75), DVec3::new(0.5, 0.5, 0.0));
        assert_eq!(t.sample_bilinear(0.5, 0.5), DVec3::new(0.5, 0.5, 0.5));
        assert_eq!(t.sample_bilinear(-5.0, 9.0), DVec3::X);
        // A NaN coordinate samples the centre; an infinite one clamps to the edge.
        assert_eq!(t.sample_bilinear(f64::NAN, f64::INFINITY), DVec3::new(0.5, 0.5, 0.0));
    }

    #[test]
    fn decodes_srgb_bytes_and_refuses_bad_sizes() {
        let t = RgbTexture::from_srgb8(1, 2, &[255, 0, 128, 0, 0, 0]).unwrap();
        assert_eq!(t.pixels()[0][0], 1.0);
        assert!((t.pixels()[0][2] - srgb_to_linear(128.0 / 255.0)).abs() < 1e-7);
        assert!(RgbTexture::from_srgb8(2, 2, &[0; 11]).is_err());
        assert!(RgbTexture::new(0, 1, vec![]).is_err());
        assert!(RgbTexture::new(1, 1, vec![[f32::NAN, 0.0, 0.0]]).is_err());
    }
}
