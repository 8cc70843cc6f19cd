//! The sixteen lanes of a horizon group as one value: plain arrays that any processor runs
//! (and compilers vectorise as they can), or one AVX-512 register. Both do the same IEEE
//! operations, no fused multiply-add, so both give the same bits.

use super::lane_frame::LANES;

/// Sixteen `f32` lanes and the operations the horizon lanes need.
pub(crate) trait LaneVector: Copy {
    /// Every lane `v`.
    fn splat(v: f32) -> Self;
    /// Lanes `z[at..at + 16]`.
    fn load(z: &[f32], at: usize) -> Self;
    /// The lanes of an array.
    fn from_array(a: [f32; LANES]) -> Self;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    /// Per lane, the absolute value.
    fn abs(self) -> Self;
    /// Whether `a > b` in any lane.
    fn any_greater(a: Self, b: Self) -> bool;
    /// Per lane, `self` if `self > o`, else `o` (so a NaN in `self` never wins).
    fn max(self, o: Self) -> Self;
    /// Per lane, `yes` where `a <= b`, else `no`.
    fn select_le(a: Self, b: Self, yes: Self, no: Self) -> Self;
    /// Per lane, `yes` where `a < 0`, else `no`.
    fn select_negative(a: Self, yes: Self, no: Self) -> Self;
    /// The least lane.
    fn min_lane(self) -> f32;
}

/// Lanes as a plain array.
#[derive(Clone, Copy)]
pub(crate) struct Portable([f32; LANES]);

impl LaneVector for Portable {
    #[inline(always)]
    fn splat(v: f32) -> Self {
        Portable([v; LANES])
    }
    #[inline(always)]
    fn load(z: &[f32], at: usize) -> Self {
        Portable(z[at..at + LANES].try_into().unwrap())
    }
    #[inline(always)]
    fn from_array(a: [f32; LANES]) -> Self {
        Portable(a)
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Portable(std::array::from_fn(|i| self.0[i] + o.0[i]))
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Portable(std::array::from_fn(|i| self.0[i] - o.0[i]))
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Portable(std::array::from_fn(|i| self.0[i] * o.0[i]))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Portable(self.0.map(f32::abs))
    }
    #[inline(always)]
    fn any_greater(a: Self, b: Self) -> bool {
        (0..LANES).any(|i| a.0[i] > b.0[i])
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        Portable(std::array::from_fn(|i| if self.0[i] > o.0[i] { self.0[i] } else { o.0[i] }))
    }
    #[inline(always)]
    fn select_le(a: Self, b: Self, yes: Self, no: Self) -> Self {
        Portable(std::array::from_fn(|i| if a.0[i] <= b.0[i] { yes.0[i] } else { no.0[i] }))
    }
    #[inline(always)]
    fn select_negative(a: Self, yes: Self, no: Self) -> Self {
        Portable(std::array::from_fn(|i| if a.0[i] < 0.0 { yes.0[i] } else { no.0[i] }))
    }
    #[inline(always)]
    fn min_lane(self) -> f32 {
        self.0.into_iter().fold(f32::INFINITY, |m, v| if v < m { v } else { m })
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx512::Avx512;

#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod avx512 {
    use super::{LaneVector, LANES};
    use std::arch::x86_64::*;

    /// Lanes in one AVX-512 register. Only code compiled with AVX-512 F, and run after
    /// detecting it, may use it (`lanes::dispatch` does so): every method relies on it.
    #[derive(Clone, Copy)]
    pub(crate) struct Avx512(__m512);

    // SAFETY (every block below): the processor has AVX-512 F, as the type's users check
    // before any value of it exists; loads read a slice of exactly 16 floats.
    impl LaneVector for Avx512 {
        #[inline(always)]
        fn splat(v: f32) -> Self {
            Avx512(unsafe { _mm512_set1_ps(v) })
        }
        #[inline(always)]
        fn load(z: &[f32], at: usize) -> Self {
            let lanes = &z[at..at + LANES];
            Avx512(unsafe { _mm512_loadu_ps(lanes.as_ptr()) })
        }
        #[inline(always)]
        fn from_array(a: [f32; LANES]) -> Self {
            Avx512(unsafe { _mm512_loadu_ps(a.as_ptr()) })
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_add_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_sub_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_mul_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn abs(self) -> Self {
            Avx512(unsafe { _mm512_abs_ps(self.0) })
        }
        #[inline(always)]
        fn any_greater(a: Self, b: Self) -> bool {
            unsafe { _mm512_cmp_ps_mask::<_CMP_GT_OQ>(a.0, b.0) != 0 }
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            // MAXPS returns its second operand unless the first is greater.
            Avx512(unsafe { _mm512_max_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn select_le(a: Self, b: Self, yes: Self, no: Self) -> Self {
            unsafe {
                let m = _mm512_cmp_ps_mask::<_CMP_LE_OQ>(a.0, b.0);
                Avx512(_mm512_mask_blend_ps(m, no.0, yes.0))
            }
        }
        #[inline(always)]
        fn select_negative(a: Self, yes: Self, no: Self) -> Self {
            unsafe {
                let m = _mm512_cmp_ps_mask::<_CMP_LT_OQ>(a.0, _mm512_setzero_ps());
                Avx512(_mm512_mask_blend_ps(m, no.0, yes.0))
            }
        }
        #[inline(always)]
        fn min_lane(self) -> f32 {
            unsafe { _mm512_reduce_min_ps(self.0) }
        }
    }
}
