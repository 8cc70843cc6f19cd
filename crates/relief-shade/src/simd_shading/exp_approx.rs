//! `exp` in `f32` by range reduction and a polynomial: the same operations in every lane
//! width, so the fog's transmittance has the same bits whichever path computes it.

/// `1.5 * 2^23`: added and subtracted, it rounds an `f32` of magnitude below `2^22` to the
/// nearest integer.
const ROUNDING_MAGIC: f32 = 12_582_912.0;

/// `ln 2` split in two: the high part (0.693145751953125) has few enough bits that
/// `k * LN2_HIGH` is exact.
const LN2_HIGH: f32 = f32::from_bits(0x3F31_7200);
/// The rest of `ln 2` (1.4286068e-6).
const LN2_LOW: f32 = f32::from_bits(0x35BF_BE8E);

/// `e^x` for `x <= 0`, within a few `f32` ulps (relative error below 5e-7); `x` is clamped to
/// `[-87, 0]` (NaN taken as -87), so the result lies in `[1.6e-38, 1]` and `e^0` is exactly 1.
#[inline(always)]
// Not `clamp`, which keeps a NaN: `max` takes -87 for it.
#[allow(clippy::manual_clamp)]
pub(crate) fn exp_non_positive(x: f32) -> f32 {
    let x = x.max(-87.0).min(0.0);
    let k = (x * std::f32::consts::LOG2_E + ROUNDING_MAGIC) - ROUNDING_MAGIC;
    let r = x - k * LN2_HIGH - k * LN2_LOW;
    let p = 1.0
        + r * (1.0
            + r * (0.5
                + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0 + r * (1.0 / 720.0))))));
    // k lies in [-126, 0]: 2^k is a normal float.
    let scale = f32::from_bits(((k as i32 + 127) as u32) << 23);
    p * scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_exp_over_the_fogs_range() {
        let mut worst = 0.0f64;
        for n in 0..=1_000_000 {
            let x = -(n as f32) * 8.7e-5;
            let want = (x as f64).exp();
            let got = exp_non_positive(x) as f64;
            worst = worst.max(((got - want) / want).abs());
        }
        assert!(worst < 5e-7, "relative error {worst:e}");
        assert_eq!(exp_non_positive(0.0), 1.0);
        assert_eq!(exp_non_positive(-0.0), 1.0);
        assert!(exp_non_positive(f32::NEG_INFINITY) < 2e-38);
        assert!(exp_non_positive(f32::NAN) < 2e-38);
    }
}
