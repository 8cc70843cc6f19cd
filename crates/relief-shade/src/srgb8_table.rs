//! The tone curve to 8-bit sRGB without a power function, checked against the formula.
//!
//! [`crate::tonemap_to_srgb8`]'s byte of a channel is `round(255 * srgb(aces(x)))`, which never
//! decreases as `x` grows: relief-core's `ByteSteps` (the 255 inputs at which the byte steps
//! up, found once, and a coarse index into them), built over the curve in `tonemap.rs`,
//! answers with two lookups and one comparison the byte that the curve (a `powf` in `f64` per
//! channel) gives, bit for bit. This file holds the tests that show it.

#[cfg(test)]
mod tests {
    use crate::tonemap::{srgb8_byte_by_formula, srgb8_steps};

    #[test]
    fn the_table_gives_the_formulas_byte_around_every_step_and_across_the_range() {
        let steps = srgb8_steps();
        // Every input within 3000 ulps of a step, where a table could err.
        for t in (1..=255u8).map(|b| steps.first_reaching(b)) {
            let bits = t.to_bits();
            for x in (bits.saturating_sub(3000)..bits + 3000).map(f32::from_bits) {
                assert_eq!(steps.byte(x), srgb8_byte_by_formula(x), "x = {x:e}");
            }
        }
        // A dense sweep of the range, and what lies outside it.
        for k in 0..2_000_000 {
            let x = k as f32 * 5e-6;
            assert_eq!(steps.byte(x), srgb8_byte_by_formula(x), "x = {x:e}");
        }
        for x in [-1.0, -0.0, f32::NAN, f32::MIN_POSITIVE, 1e-30, 7.4, 7.5, 1e30, f32::INFINITY] {
            assert_eq!(steps.byte(x), srgb8_byte_by_formula(x), "x = {x:e}");
        }
    }

    #[test]
    fn every_byte_has_a_step() {
        let steps = srgb8_steps();
        assert!((0..255u8).all(|b| steps.first_reaching(b) < steps.first_reaching(b + 1)));
        for b in 1..=255u8 {
            let t = steps.first_reaching(b);
            assert_eq!(srgb8_byte_by_formula(t), b);
            assert_eq!(srgb8_byte_by_formula(f32::from_bits(t.to_bits() - 1)), b - 1);
        }
    }
}
