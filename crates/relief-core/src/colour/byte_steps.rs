//! A non-decreasing curve onto bytes without evaluating it: the 255 inputs at which the byte
//! steps up, found once, and a coarse index into them.
//!
//! A curve's byte that never decreases as `x` grows is the number of steps at or below `x`:
//! the table keeps, for every byte `b` in 1..=255, the smallest `f32` at which the curve
//! reaches `b`, found by bisection over the `f32` values with the curve itself, and a coarse
//! index by the input's bit pattern (buckets a fixed fraction of an octave wide), and answers
//! with two lookups and one comparison the byte that the curve gives, bit for bit. The tone
//! curve to 8-bit sRGB (relief-shade) and the sRGB encoding of ortho photos' texels
//! ([`super::linear_to_srgb8`]) are such curves.

/// Buckets of the coarse index per octave of input, as a number of mantissa bits: bucket `k`
/// holds the `f32` values whose bit patterns lie `k << (23 - BUCKET_BITS)` and more above the
/// lowest bucket's start, so a bucket is 1/256 of its octave wide (at most one step falls in a
/// bucket, checked when the table is built) and the index is small enough (about 3,600
/// entries for the tone curve) to stay in the first-level cache.
const BUCKET_BITS: u32 = 8;

/// The shift from an `f32`'s bit pattern to its bucket.
const BUCKET_SHIFT: u32 = 23 - BUCKET_BITS;

/// The steps of a non-decreasing curve from `[0, inf)` onto the bytes 0..=255.
#[derive(Debug)]
pub struct ByteSteps {
    /// `first[b]`: the smallest input whose byte is at least `b` (`first[0]` is 0).
    first: [f32; 256],
    /// The bit pattern of the power of two at or below `first[1]`, where bucket 0 starts
    /// (every smaller input has byte 0).
    lowest: u32,
    /// `at_start[k]`: the byte of the first input of bucket `k`.
    at_start: Vec<u8>,
}

impl ByteSteps {
    /// The steps of `byte`, which must map 0 to 0, never decrease, reach 255 below `f32::MAX`
    /// and step at most once in 1/256 of an octave.
    ///
    /// Panics when the curve steps more than once in a bucket (the table could not answer).
    pub fn new(byte: impl Fn(f32) -> u8) -> Self {
        let mut first = [0.0f32; 256];
        for (b, step) in first.iter_mut().enumerate().skip(1) {
            *step = smallest_reaching(&byte, b as u8);
        }
        let lowest = first[1].to_bits() >> 23 << 23;
        let bucket_start = |k: u32| f32::from_bits(lowest + (k << BUCKET_SHIFT));
        let buckets = ((first[255].to_bits() - lowest) >> BUCKET_SHIFT) + 1;
        let steps_to = |x: f32| first.iter().skip(1).take_while(|&&t| t <= x).count();
        let at_start: Vec<u8> = (0..buckets).map(|k| steps_to(bucket_start(k)) as u8).collect();
        let most_in_a_bucket = (0..buckets)
            .map(|k| steps_to(bucket_start(k + 1).next_down()) - at_start[k as usize] as usize)
            .max();
        assert!(most_in_a_bucket <= Some(1), "the curve steps more than once in a bucket");
        ByteSteps { first, lowest, at_start }
    }

    /// The smallest input whose byte is at least `b` (0 for `b = 0`).
    pub fn first_reaching(&self, b: u8) -> f32 {
        self.first[b as usize]
    }

    /// The byte of `x`: 0 for negative or NaN input, 255 from the last step on.
    #[inline]
    pub fn byte(&self, x: f32) -> u8 {
        if x.is_nan() || x <= 0.0 {
            return 0;
        }
        if x >= self.first[255] {
            return 255;
        }
        let Some(above) = x.to_bits().checked_sub(self.lowest) else {
            return 0;
        };
        // x lies below first[255], so its bucket exists and its byte is below 255.
        let b = self.at_start[(above >> BUCKET_SHIFT) as usize];
        b + u8::from(x >= self.first[b as usize + 1])
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linear_ramp_steps_at_its_rounding_points() {
        let ramp = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
        let steps = ByteSteps::new(ramp);
        for b in 1..=255u8 {
            let t = steps.first_reaching(b);
            assert_eq!(ramp(t), b);
            assert_eq!(ramp(t.next_down()), b - 1);
        }
        for k in 0..300_000 {
            let x = k as f32 * 4e-6;
            assert_eq!(steps.byte(x), ramp(x), "x = {x:e}");
        }
        assert_eq!(steps.byte(f32::NAN), 0);
        assert_eq!(steps.byte(-3.0), 0);
        assert_eq!(steps.byte(f32::INFINITY), 255);
    }

    #[test]
    #[should_panic(expected = "more than once in a bucket")]
    fn a_curve_too_steep_for_the_index_is_refused() {
        // All 255 steps within a hundredth of an octave.
        ByteSteps::new(|x: f32| ((x - 1.0).clamp(0.0, 0.01) * 25_500.0).round() as u8);
    }
}
