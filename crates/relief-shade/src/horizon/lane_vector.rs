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
    /// Bit `i` set where `a <= b` in lane `i`.
    fn le_mask(a: Self, b: Self) -> u16 {
        let (a, b) = (a.to_array(), b.to_array());
        (0..LANES).fold(0, |m, i| m | (u16::from(a[i] <= b[i]) << i))
    }
    /// The lanes as an array.
    fn to_array(self) -> [f32; LANES];

    /// Per lane `i`, in f64: `(da + w (db - da)) * scale - lift` with `da = z[at_a + i] -
    /// z0[i]` and `db = z[at_b + i] - z0[i]` (the exact slope of a point on an edge).
    #[inline(always)]
    fn exact_slopes(
        z: &[f32],
        at_a: usize,
        at_b: usize,
        [w, scale, lift]: [f64; 3],
        z0: &[f64; LANES],
    ) -> [f64; LANES] {
        let (a, b) = (&z[at_a..at_a + LANES], &z[at_b..at_b + LANES]);
        let mut slopes = [0.0; LANES];
        for i in 0..LANES {
            let (da, db) = (f64::from(a[i]) - z0[i], f64::from(b[i]) - z0[i]);
            slopes[i] = (da + w * (db - da)) * scale - lift;
        }
        slopes
    }

    /// Per lane, `yes` where bit `i` of `mask` is set, else `no`.
    #[inline(always)]
    fn select_exact(mask: u16, yes: &[f64; LANES], no: &[f64; LANES]) -> [f64; LANES] {
        std::array::from_fn(|i| if mask >> i & 1 == 1 { yes[i] } else { no[i] })
    }

    /// Raises `best` to `slopes` in the lanes where they are greater, setting those lanes'
    /// `steps` to `step`; whether any lane was raised.
    #[inline(always)]
    fn raise_exact(
        best: &mut [f64; LANES],
        steps: &mut [u32; LANES],
        slopes: &[f64; LANES],
        step: u32,
    ) -> bool {
        let mut raised = false;
        for i in 0..LANES {
            if slopes[i] > best[i] {
                (best[i], steps[i], raised) = (slopes[i], step, true);
            }
        }
        raised
    }

    /// Per lane, the largest `f32` at most `exact`.
    #[inline(always)]
    fn round_down(exact: &[f64; LANES]) -> Self {
        Self::from_array(exact.map(|x| {
            let y = x as f32;
            if f64::from(y) > x {
                y.next_down()
            } else {
                y
            }
        }))
    }
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
    fn to_array(self) -> [f32; LANES] {
        self.0
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
        fn to_array(self) -> [f32; LANES] {
            let mut a = [0.0; LANES];
            unsafe { _mm512_storeu_ps(a.as_mut_ptr(), self.0) };
            a
        }
        #[inline(always)]
        fn le_mask(a: Self, b: Self) -> u16 {
            unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(a.0, b.0) }
        }
        #[inline(always)]
        fn exact_slopes(
            z: &[f32],
            at_a: usize,
            at_b: usize,
            [w, scale, lift]: [f64; 3],
            z0: &[f64; LANES],
        ) -> [f64; LANES] {
            let (a, b) = (&z[at_a..at_a + LANES], &z[at_b..at_b + LANES]);
            let mut out = [0.0; LANES];
            unsafe {
                let (w, scale, lift) =
                    (_mm512_set1_pd(w), _mm512_set1_pd(scale), _mm512_set1_pd(lift));
                for half in 0..2 {
                    let at = 8 * half;
                    let z0 = _mm512_loadu_pd(z0.as_ptr().add(at));
                    let da =
                        _mm512_sub_pd(_mm512_cvtps_pd(_mm256_loadu_ps(a.as_ptr().add(at))), z0);
                    let db =
                        _mm512_sub_pd(_mm512_cvtps_pd(_mm256_loadu_ps(b.as_ptr().add(at))), z0);
                    let along = _mm512_add_pd(da, _mm512_mul_pd(w, _mm512_sub_pd(db, da)));
                    let slope = _mm512_sub_pd(_mm512_mul_pd(along, scale), lift);
                    _mm512_storeu_pd(out.as_mut_ptr().add(at), slope);
                }
            }
            out
        }
        #[inline(always)]
        fn select_exact(mask: u16, yes: &[f64; LANES], no: &[f64; LANES]) -> [f64; LANES] {
            let mut out = [0.0; LANES];
            unsafe {
                for half in 0..2 {
                    let at = 8 * half;
                    let m = (mask >> at) as u8;
                    let (y, n) = (
                        _mm512_loadu_pd(yes.as_ptr().add(at)),
                        _mm512_loadu_pd(no.as_ptr().add(at)),
                    );
                    _mm512_storeu_pd(out.as_mut_ptr().add(at), _mm512_mask_blend_pd(m, n, y));
                }
            }
            out
        }
        #[inline(always)]
        fn raise_exact(
            best: &mut [f64; LANES],
            steps: &mut [u32; LANES],
            slopes: &[f64; LANES],
            step: u32,
        ) -> bool {
            unsafe {
                let mut mask: u16 = 0;
                for half in 0..2 {
                    let at = 8 * half;
                    let b = _mm512_loadu_pd(best.as_ptr().add(at));
                    let s = _mm512_loadu_pd(slopes.as_ptr().add(at));
                    let m = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(s, b);
                    _mm512_storeu_pd(best.as_mut_ptr().add(at), _mm512_mask_blend_pd(m, b, s));
                    mask |= u16::from(m) << at;
                }
                if mask == 0 {
                    return false;
                }
                let old = _mm512_loadu_si512(steps.as_ptr().cast());
                let new = _mm512_mask_mov_epi32(old, mask, _mm512_set1_epi32(step as i32));
                _mm512_storeu_si512(steps.as_mut_ptr().cast(), new);
                true
            }
        }
        #[inline(always)]
        fn round_down(exact: &[f64; LANES]) -> Self {
            unsafe {
                const DOWN: i32 = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
                let lo = _mm512_cvt_roundpd_ps::<DOWN>(_mm512_loadu_pd(exact.as_ptr()));
                let hi = _mm512_cvt_roundpd_ps::<DOWN>(_mm512_loadu_pd(exact.as_ptr().add(8)));
                // Both halves in one register (AVX-512 F's insert, as 64-bit lanes).
                let low = _mm512_castps_pd(_mm512_castps256_ps512(lo));
                Avx512(_mm512_castpd_ps(_mm512_insertf64x4::<1>(low, _mm256_castps_pd(hi))))
            }
        }
    }
}
