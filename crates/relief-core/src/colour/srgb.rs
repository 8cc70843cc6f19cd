//! The sRGB transfer function (IEC 61966-2-1), in floating point and in bytes.

use std::sync::OnceLock;

use super::ByteSteps;

/// The sRGB encoding of a linear value in `[0, 1]` (IEC 61966-2-1; values outside are clamped,
/// NaN gives 0).
pub fn linear_to_srgb(linear: f32) -> f32 {
    // Evaluated in f64 so that the f32 result is the correctly rounded curve (1 maps to 1).
    let x = clamp_unit(linear) as f64;
    let encoded = if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
    encoded as f32
}

/// The linear value of an sRGB-encoded value in `[0, 1]` (clamped, NaN gives 0).
pub fn srgb_to_linear(encoded: f32) -> f32 {
    let x = clamp_unit(encoded) as f64;
    let linear = if x <= 0.040_45 { x / 12.92 } else { ((x + 0.055) / 1.055).powf(2.4) };
    linear as f32
}

/// The sRGB byte of a linear value in `[0, 1]`: `round(255 * linear_to_srgb(linear))`
/// (clamped, NaN gives 0), from a table of the curve's steps ([`ByteSteps`]), equal to the
/// formula bit for bit without a power function.
pub fn linear_to_srgb8(linear: f32) -> u8 {
    static STEPS: OnceLock<ByteSteps> = OnceLock::new();
    STEPS.get_or_init(|| ByteSteps::new(srgb8_byte_by_formula)).byte(linear)
}

/// The linear value of each sRGB byte (`srgb_to_linear(b / 255)`), computed once.
pub fn srgb8_to_linear_table() -> &'static [f32; 256] {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|b| srgb_to_linear(b as f32 / 255.0)))
}

/// The byte [`linear_to_srgb8`] gives, from the formula: what its table reproduces.
fn srgb8_byte_by_formula(linear: f32) -> u8 {
    (linear_to_srgb(linear) * 255.0).round() as u8
}

/// `x` clamped to `[0, 1]`, NaN to 0.
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
    fn srgb_round_trips() {
        for k in 0..=1000 {
            let x = k as f32 / 1000.0;
            assert!((srgb_to_linear(linear_to_srgb(x)) - x).abs() < 1e-6, "{x}");
            assert!((linear_to_srgb(srgb_to_linear(x)) - x).abs() < 1e-6, "{x}");
        }
        // Known points of the standard curve.
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-6);
        assert!((linear_to_srgb(0.0031308) - 0.040_45).abs() < 1e-5);
        assert_eq!(linear_to_srgb(1.0), 1.0);
        assert_eq!(linear_to_srgb(f32::NAN), 0.0);
        // Every 8-bit code survives decoding and re-encoding.
        for code in 0..=255u8 {
            let back = (linear_to_srgb(srgb_to_linear(code as f32 / 255.0)) * 255.0).round();
            assert_eq!(back as u8, code);
        }
    }

    #[test]
    fn srgb_bytes_round_trip_through_linear() {
        let table = srgb8_to_linear_table();
        for b in 0..=255u8 {
            assert_eq!(linear_to_srgb8(table[b as usize]), b);
        }
    }

    #[test]
    fn the_byte_table_gives_the_formulas_byte() {
        // A dense sweep of [0, 1] and beyond, and what lies outside it.
        for k in 0..1_200_000 {
            let x = k as f32 * 1e-6;
            assert_eq!(linear_to_srgb8(x), srgb8_byte_by_formula(x.clamp(0.0, 1.0)), "x = {x:e}");
        }
        for x in [-1.0, -0.0, f32::NAN, f32::MIN_POSITIVE, 1e-30, 1.0, 1e30, f32::INFINITY] {
            assert_eq!(linear_to_srgb8(x), srgb8_byte_by_formula(x), "x = {x:e}");
        }
        assert_eq!(linear_to_srgb8(1.0), 255);
    }
}
