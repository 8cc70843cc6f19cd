//! From linear radiance to 8-bit sRGB: exposure, a filmic curve and the sRGB transfer function.

use std::sync::OnceLock;

use rayon::prelude::*;
use relief_core::colour::ByteSteps;

use crate::error::non_negative;
use crate::ShadeError;
// The sRGB transfer function lives in relief-core (relief-tiles encodes texels with it too);
// colour_ramp.rs takes it from here.
pub(crate) use relief_core::colour::{linear_to_srgb, srgb_to_linear};

/// The ACES filmic curve as fitted by Narkowicz (2015): maps `[0, inf)` monotonically onto
/// `[0, 1]`, with 0 to 0, a gentle toe and a soft shoulder reaching white at about 7.2.
/// Negative or NaN input gives 0.
pub fn aces_filmic(x: f32) -> f32 {
    let x = if x > 0.0 { x } else { 0.0 };
    if x >= 7.5 {
        // Past white (the fit exceeds 1 from about 7.24 on); also keeps x² from overflowing.
        return 1.0;
    }
    // In f64, so that the curve rounded to f32 never steps down where the f32 arithmetic's
    // rounding would wiggle: the 8-bit table of its steps (srgb8_table.rs) relies on that.
    let x = x as f64;
    let (a, b, c, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
    clamp_unit(((x * (a * x + b)) / (x * (c * x + d) + e)) as f32)
}

/// Tone-maps linear radiance to interleaved 8-bit sRGB (`R, G, B` per pixel, same order):
/// each channel is multiplied by `exposure`, passed through [`aces_filmic`] and encoded with
/// [`linear_to_srgb`], then rounded to the nearest of 0..=255.
///
/// Fails when `exposure` is negative or not finite. Negative or NaN radiance gives 0.
///
/// The bytes come from a table of the curve's steps (see `srgb8_table.rs`), equal to the
/// formula's bit for bit without a power function per channel.
pub fn tonemap_to_srgb8(radiance: &[[f32; 3]], exposure: f64) -> Result<Vec<u8>, ShadeError> {
    let steps = srgb8_steps();
    encode_rgb8(radiance, exposure, |x| steps.byte(x))
}

/// The byte of [`tonemap_to_srgb8`] for a channel already multiplied by the exposure, from
/// the formula: what the table of steps reproduces.
pub(crate) fn srgb8_byte_by_formula(x: f32) -> u8 {
    to_byte(linear_to_srgb(aces_filmic(x)))
}

/// The steps of [`tonemap_to_srgb8`]'s curve, built on first use (`srgb8_table.rs` checks
/// that they give the formula's bytes).
pub(crate) fn srgb8_steps() -> &'static ByteSteps {
    static STEPS: OnceLock<ByteSteps> = OnceLock::new();
    STEPS.get_or_init(|| ByteSteps::new(srgb8_byte_by_formula))
}

/// One pixel of [`tonemap_to_srgb8`] (the exposure already checked).
#[inline]
pub(crate) fn srgb8_pixel(radiance: [f32; 3], exposure: f32) -> [u8; 3] {
    let steps = srgb8_steps();
    radiance.map(|channel| steps.byte(channel * exposure))
}

/// A value in `[0, 1]` rounded to the nearest of 0..=255.
fn to_byte(value: f32) -> u8 {
    (value * 255.0).round() as u8
}

/// Every channel of `radiance` times `exposure` through `byte`, interleaved; fails when
/// `exposure` is negative or not finite.
fn encode_rgb8(
    radiance: &[[f32; 3]],
    exposure: f64,
    byte: impl Fn(f32) -> u8 + Sync,
) -> Result<Vec<u8>, ShadeError> {
    non_negative("exposure", exposure)?;
    let exposure = exposure as f32;
    let mut out = vec![0u8; radiance.len() * 3];
    out.par_chunks_mut(3).zip(radiance.par_iter()).for_each(|(rgb, pixel)| {
        for (o, &channel) in rgb.iter_mut().zip(pixel) {
            *o = byte(channel * exposure);
        }
    });
    Ok(out)
}

/// Tone-maps linear radiance to interleaved 8-bit RGB as the MLHM reference renderer does:
/// each channel is multiplied by `exposure`, compressed by Reinhard's `x / (1 + x)` and
/// encoded with a gamma of 1/2.2, then rounded to the nearest of 0..=255.
///
/// Fails when `exposure` is negative or not finite. Negative or NaN radiance gives 0.
pub fn tonemap_reinhard_to_rgb8(
    radiance: &[[f32; 3]],
    exposure: f64,
) -> Result<Vec<u8>, ShadeError> {
    encode_rgb8(radiance, exposure, |x| {
        // An infinite channel gives inf / inf: white, as its limit.
        let compressed = if x == f32::INFINITY { 1.0 } else { clamp_unit(x / (1.0 + x)) };
        to_byte(compressed.powf(1.0 / 2.2))
    })
}

fn clamp_unit(x: f32) -> f32 {
    if x > 0.0 {
        x.min(1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tonemap_is_monotonic_and_maps_black_to_black() {
        let ramp: Vec<[f32; 3]> = (0..4000).map(|k| [k as f32 * 0.005; 3]).collect();
        let bytes = tonemap_to_srgb8(&ramp, 1.0).unwrap();
        assert_eq!(&bytes[..3], &[0, 0, 0]);
        assert!(bytes.windows(6).step_by(3).all(|w| w[3] >= w[0]));
        assert!(*bytes.last().unwrap() >= 250, "bright radiance approaches white");
        let mut prev = 0.0;
        for k in 1..3500 {
            let y = aces_filmic(k as f32 * 0.002);
            assert!(y > prev && y < 1.0, "strictly increasing below white at {k}");
            prev = y;
        }
        for x in [7.0, 7.3, 7.5, 8.0, 1e20, f32::MAX, f32::INFINITY] {
            let y = aces_filmic(x);
            assert!(y >= prev && y <= 1.0, "non-decreasing up to white at {x}");
            prev = y;
        }
        assert_eq!(aces_filmic(1e30), 1.0);
        assert_eq!(aces_filmic(0.0), 0.0);
    }

    #[test]
    fn reinhard_halves_one_and_encodes_with_gamma() {
        let px = [[0.0f32, 1.0, f32::INFINITY], [-1.0, f32::NAN, 3.0]];
        let rgb = tonemap_reinhard_to_rgb8(&px, 1.0).unwrap();
        let half = (0.5f32.powf(1.0 / 2.2) * 255.0).round() as u8;
        let three = (0.75f32.powf(1.0 / 2.2) * 255.0).round() as u8;
        assert_eq!(rgb, vec![0, half, 255, 0, 0, three]);
        assert_eq!(tonemap_reinhard_to_rgb8(&px[..1], 0.5).unwrap()[1], {
            ((1.0f32 / 3.0).powf(1.0 / 2.2) * 255.0).round() as u8
        });
        assert!(tonemap_reinhard_to_rgb8(&px, -1.0).is_err());
    }

    #[test]
    fn exposure_scales_and_bad_exposure_is_refused() {
        let px = [[0.1f32, 0.2, 0.4]];
        assert_eq!(tonemap_to_srgb8(&px, 0.0).unwrap(), vec![0, 0, 0]);
        let dim = tonemap_to_srgb8(&px, 1.0).unwrap();
        let bright = tonemap_to_srgb8(&px, 2.0).unwrap();
        assert!(dim.iter().zip(&bright).all(|(a, b)| b > a));
        assert!(tonemap_to_srgb8(&px, -1.0).is_err());
        assert!(tonemap_to_srgb8(&px, f64::NAN).is_err());
        assert_eq!(
            tonemap_to_srgb8(&[[f32::NAN, -1.0, f32::INFINITY]], 1.0).unwrap(),
            vec![0, 0, 255]
        );
    }
}
