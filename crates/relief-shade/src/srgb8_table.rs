//! The tone curve to 8-bit sRGB without a power function: the 255 inputs at which the byte
//! steps up, found once, and a coarse index into them.
//!
//! [`crate::tonemap_to_srgb8`]'s byte of a channel is `round(255 * srgb(aces(x)))`, which never
//! decreases as `x` grows. So it is the number of steps at or below `x`: the table keeps, for
//! every byte `b` in 1..=255, the smallest `f32` at which the curve reaches `b`, found by
//! bisection over the `f32` values with the curve itself, and answers in a lookup and at most a
//! few comparisons the byte that the curve (a `powf` in `f64` per channel) gives, bit for bit.

use std::sync::OnceLock;

/// Buckets of the coarse index per unit of input: at most about one step falls in a bucket,
/// where the curve is steepest (near black, about 700 bytes per unit).
const BUCKETS_PER_UNIT: f32 = 2048.0;

/// The steps of a non-decreasing curve from `[0, inf)` onto the bytes 0..=255.
#[derive(Debug)]
pub(crate) struct ByteSteps {
    /// `first[b]`: the smallest input whose byte is at least `b` (`first[0]` is 0).
    first: [f32; 256],
    /// `below[k]`: a byte no greater than that of any input in bucket `k`, i.e. in
    /// `[k / BUCKETS_PER_UNIT, (k + 1) / BUCKETS_PER_UNIT)`.
    below: Vec<u8>,
}

impl ByteSteps {
    /// The steps of `byte`, which must map 0 to 0, never decrease, and reach 255.
    fn new(byte: impl Fn(f32) -> u8) -> Self {
        let mut first = [0.0f32; 256];
        for (b, step) in first.iter_mut().enumerate().skip(1) {
            *step = smallest_reaching(&byte, b as u8);
        }
        let buckets = (first[255] * BUCKETS_PER_UNIT) as usize + 1;
        let below = (0..buckets)
            .map(|k| {
                // The bucket before's lower edge: below every input the index can put here,
                // whatever the rounding of `x * BUCKETS_PER_UNIT`.
                let edge = k.saturating_sub(1) as f32 / BUCKETS_PER_UNIT;
                first.iter().skip(1).take_while(|&&t| t <= edge).count() as u8
            })
            .collect();
        ByteSteps { first, below }
    }

    /// The byte of `x`: 0 for negative or NaN input, 255 from the last step on.
    #[inline]
    pub(crate) fn byte(&self, x: f32) -> u8 {
        if x.is_nan() || x <= 0.0 {
            return 0;
        }
        if x >= self.first[255] {
            return 255;
        }
        // x lies below first[255], so the bucket exists.
        let mut b = self.below[(x * BUCKETS_PER_UNIT) as usize];
        while x >= self.first[b as usize + 1] {
            b += 1;
        }
        b
    }
}

/// The smallest non-negative `f32` whose byte is at least `target`, by bisection over the
/// ordered bit patterns of the positive floats (`byte` reaches 255 below `f32::MAX`).
fn smallest_reaching(byte: &impl Fn(f32) -> u8, target: u8) -> f32 {
    let (mut lo, mut hi) = (0u32, f32::MAX.to_bits());
    // Invariant: byte(lo) < target <= byte(hi).
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if byte(f32::from_bits(mid)) >= target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    f32::from_bits(hi)
}

/// The steps of [`crate::tonemap_to_srgb8`]'s curve, built on first use.
pub(crate) fn srgb8_steps() -> &'static ByteSteps {
    static STEPS: OnceLock<ByteSteps> = OnceLock::new();
    STEPS.get_or_init(|| ByteSteps::new(crate::tonemap::srgb8_byte_by_formula))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tonemap::srgb8_byte_by_formula;

    #[test]
    fn the_table_gives_the_formulas_byte_around_every_step_and_across_the_range() {
        let steps = srgb8_steps();
        // Every input within 3000 ulps of a step, where a table could err.
        for &t in &steps.first[1..] {
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
        assert!(steps.first.windows(2).all(|w| w[0] < w[1]));
        for b in 1..=255u8 {
            let t = steps.first[b as usize];
            assert_eq!(srgb8_byte_by_formula(t), b);
            assert_eq!(srgb8_byte_by_formula(f32::from_bits(t.to_bits() - 1)), b - 1);
        }
    }
}
