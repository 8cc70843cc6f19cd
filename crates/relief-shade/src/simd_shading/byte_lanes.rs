//! The tone curve's 8-bit step table (`ByteSteps` of `tonemap.rs`) rebuilt for lanes: the same
//! byte for every input, from two lookups at clamped indices, without branches.

use std::sync::LazyLock;

use relief_core::colour::ByteSteps;

/// Mantissa bits of the coarse index (as `ByteSteps` has it): buckets 1/256 of an octave wide.
const BUCKET_SHIFT: u32 = 23 - 8;

/// Entries of the coarse index: enough for the tone curve's (about 3,600; checked when built).
const BUCKETS: usize = 4096;

/// The steps of a curve onto bytes, laid out for lanes.
pub(crate) struct ByteLanes {
    /// `first[b]`: the smallest input whose byte is at least `b`; `first[256]` is `+inf`.
    first: [f32; 257],
    /// The bit pattern where bucket 0 starts (every smaller input has byte 0).
    lowest: u32,
    /// `at_start[k]`: the byte of the first input of bucket `k`, as a `u32`.
    at_start: Box<[u32; BUCKETS]>,
}

impl ByteLanes {
    /// The lanes' copy of `steps`, which must have at most [`BUCKETS`] buckets.
    pub(crate) fn new(steps: &ByteSteps) -> ByteLanes {
        let mut first = [f32::INFINITY; 257];
        for (b, step) in first.iter_mut().enumerate().take(256) {
            *step = steps.first_reaching(b as u8);
        }
        let lowest = first[1].to_bits() >> 23 << 23;
        let buckets = ((first[255].to_bits() - lowest) >> BUCKET_SHIFT) as usize + 1;
        assert!(buckets <= BUCKETS, "the curve's index needs {buckets} buckets");
        let mut at_start = Box::new([255u32; BUCKETS]);
        for (k, entry) in at_start.iter_mut().enumerate().take(buckets) {
            let start = f32::from_bits(lowest + ((k as u32) << BUCKET_SHIFT));
            *entry = first[1..256].iter().take_while(|&&t| t <= start).count() as u32;
        }
        ByteLanes { first, lowest, at_start }
    }

    /// The tone curve's table (`tonemap.rs`), built once.
    pub(crate) fn tone_curve() -> &'static ByteLanes {
        static TABLE: LazyLock<ByteLanes> =
            LazyLock::new(|| ByteLanes::new(crate::tonemap::srgb8_steps()));
        &TABLE
    }

    /// The byte of each of `x`: 0 for negative or NaN input, 255 from the last step on; what
    /// `ByteSteps::byte` gives.
    #[inline(always)]
    pub(crate) fn bytes<const N: usize>(&self, x: &[f32; N]) -> [u32; N] {
        // Fields read once, and `&` rather than `&&`: the loop then has no conditional loads.
        let (first, at_start, lowest, last) =
            (&self.first, &*self.at_start, self.lowest, self.first[255]);
        let mut out = [0u32; N];
        for l in 0..N {
            let v = x[l];
            let bits = v.to_bits();
            let inside = (v > 0.0) & (v < last) & (bits >= lowest);
            // Outside, the bucket is any in range: its byte is not used.
            let bucket = (bits.wrapping_sub(lowest) >> BUCKET_SHIFT) & (BUCKETS as u32 - 1);
            let b = at_start[bucket as usize];
            let step_up = u32::from(v >= first[(b + 1).min(256) as usize]);
            let top = if v >= last { 255 } else { 0 };
            out[l] = if inside { b + step_up } else { top };
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tonemap::srgb8_steps;

    #[test]
    fn gives_the_step_tables_byte() {
        let (lanes, steps) = (ByteLanes::tone_curve(), srgb8_steps());
        let check = |x: [f32; 8]| {
            let got = lanes.bytes(&x);
            for (v, b) in x.iter().zip(got) {
                assert_eq!(b, u32::from(steps.byte(*v)), "x = {v:e}");
            }
        };
        for b in 1..=255u8 {
            let bits = steps.first_reaching(b).to_bits();
            for k in (bits - 2000..bits + 2000).step_by(8) {
                check(std::array::from_fn(|l| f32::from_bits(k + l as u32)));
            }
        }
        for k in 0..300_000 {
            check(std::array::from_fn(|l| (8 * k + l) as f32 * 4e-6));
        }
        check([-1.0, -0.0, f32::NAN, f32::MIN_POSITIVE, 1e-30, 7.5, 1e30, f32::INFINITY]);
    }
}
