//! Numbers the kernels' formulas are written over: `f32` for one column, [`Lanes`] for eight
//! cells side by side. One formula serves both, so the one-column paths that compute eight
//! cells at a time (and that the compiler turns into vector instructions) give the same bits
//! as the general path's one column at a time: every lane does the same f32 operations in
//! the same order.

use std::ops::{Add, Div, Mul, Sub};

/// Cells the one-column paths compute at a time.
pub(crate) const LANES: usize = 8;

/// A real number of the kernels' formulas: `f32`, or [`Lanes`] of them.
pub(crate) trait Real:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// The result of a comparison: `bool`, or one per lane.
    type Mask: Copy;
    /// `v` (in every lane).
    fn splat(v: f32) -> Self;
    /// `f32::max`.
    fn max(self, other: Self) -> Self;
    /// `f32::min`.
    fn min(self, other: Self) -> Self;
    /// `f32::sqrt`.
    fn sqrt(self) -> Self;
    /// `2^k` for an integer `k` in -126..=127 (held as a float).
    fn pow2(k: Self) -> Self;
    /// `self > other`.
    fn gt(self, other: Self) -> Self::Mask;
    /// `self >= other`.
    fn ge(self, other: Self) -> Self::Mask;
    /// `a` where `mask`, else `b`.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Both masks.
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;

    /// `f32::clamp`.
    #[inline(always)]
    fn clamp(self, lo: f32, hi: f32) -> Self {
        self.max(Self::splat(lo)).min(Self::splat(hi))
    }
}

impl Real for f32 {
    type Mask = bool;
    #[inline(always)]
    fn splat(v: f32) -> Self {
        v
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f32::max(self, other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f32::min(self, other)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn pow2(k: Self) -> Self {
        f32::from_bits(((k as i32 + 127) << 23) as u32)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> bool {
        self > other
    }
    #[inline(always)]
    fn ge(self, other: Self) -> bool {
        self >= other
    }
    #[inline(always)]
    fn select(mask: bool, a: Self, b: Self) -> Self {
        if mask {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn and(a: bool, b: bool) -> bool {
        a && b
    }
}

/// `[f(a[0]), ..., f(a[3])]`: as `<[T; 4]>::map`, which the compiler does not always
/// inline into the lanes' loops.
#[inline(always)]
pub(crate) fn map4<T: Copy, U>(a: [T; 4], f: impl Fn(T) -> U) -> [U; 4] {
    [f(a[0]), f(a[1]), f(a[2]), f(a[3])]
}

/// A mask of lanes: all bits set where true, none where false (as vector comparisons give,
/// so the compiler keeps masks in vector registers).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LaneMask(pub [i32; LANES]);

impl LaneMask {
    /// The mask `[f(0), ..., f(7)]`.
    #[inline(always)]
    pub(crate) fn from_fn(f: impl Fn(usize) -> bool) -> Self {
        let mut m = [0; LANES];
        for (l, v) in m.iter_mut().enumerate() {
            *v = -i32::from(f(l));
        }
        LaneMask(m)
    }

    /// Whether lane `l` is set.
    #[inline(always)]
    pub(crate) fn get(self, l: usize) -> bool {
        self.0[l] != 0
    }
}

/// Eight f32 side by side, one per cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Lanes(pub [f32; LANES]);

impl Lanes {
    /// The lanes `f(0), ..., f(7)`.
    #[inline(always)]
    pub(crate) fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        let mut lanes = [0.0; LANES];
        for (l, v) in lanes.iter_mut().enumerate() {
            *v = f(l);
        }
        Lanes(lanes)
    }

    /// `f` of each lane.
    #[inline(always)]
    pub(crate) fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Lanes::from_fn(|l| f(self.0[l]))
    }
}

/// Lane by lane `a op b`.
macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Lanes {
            type Output = Lanes;
            #[inline(always)]
            fn $method(self, other: Lanes) -> Lanes {
                Lanes::from_fn(|l| self.0[l] $op other.0[l])
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl Real for Lanes {
    type Mask = LaneMask;
    #[inline(always)]
    fn splat(v: f32) -> Self {
        Lanes([v; LANES])
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        Lanes::from_fn(|l| self.0[l].max(other.0[l]))
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        Lanes::from_fn(|l| self.0[l].min(other.0[l]))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f32::sqrt)
    }
    #[inline(always)]
    fn pow2(k: Self) -> Self {
        k.map(<f32 as Real>::pow2)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self::Mask {
        LaneMask::from_fn(|l| self.0[l] > other.0[l])
    }
    #[inline(always)]
    fn ge(self, other: Self) -> Self::Mask {
        LaneMask::from_fn(|l| self.0[l] >= other.0[l])
    }
    #[inline(always)]
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self {
        let bits = |v: f32| v.to_bits() as i32;
        Lanes::from_fn(|l| {
            f32::from_bits(((mask.0[l] & bits(a.0[l])) | (!mask.0[l] & bits(b.0[l]))) as u32)
        })
    }
    #[inline(always)]
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask {
        let mut m = [0; LANES];
        for (l, v) in m.iter_mut().enumerate() {
            *v = a.0[l] & b.0[l];
        }
        LaneMask(m)
    }
}

/// `e^x` for `x` in [0, 80], to about 2 ulp, in operations that vectorize (range reduction
/// by `ln 2`, a degree-6 polynomial, a power of two), the same for one number as for lanes.
/// The step's kernels use it where the compiler would call `expf` once per lane.
#[inline(always)]
pub(crate) fn exp<R: Real>(x: R) -> R {
    let splat = R::splat;
    let x = x.clamp(0.0, 80.0);
    // k = round(x / ln 2): adding and taking away 1.5 * 2^23 rounds to the nearest integer.
    let round = splat(12_582_912.0);
    let k = (x * splat(std::f32::consts::LOG2_E) + round) - round;
    // r = x - k ln 2, in two parts so that r is exact to f32; |r| <= ln 2 / 2.
    let r = (x - k * splat(0.693_145_75)) - k * splat(1.428_606_8e-6);
    let p = splat(1.0 / 720.0);
    let p = p * r + splat(1.0 / 120.0);
    let p = p * r + splat(1.0 / 24.0);
    let p = p * r + splat(1.0 / 6.0);
    let p = p * r + splat(0.5);
    let p = p * r + splat(1.0);
    let p = p * r + splat(1.0);
    p * R::pow2(k)
}

/// The values of one column, as numbers of type `R`: one column, or [`Lanes`] of columns.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Column<R> {
    pub bedrock: R,
    pub sand: R,
    pub water: R,
}

impl<R: Real> Column<R> {
    /// `bedrock + sand`, as [`relief_core::MlhmColumn::solid_top`].
    #[inline(always)]
    pub(crate) fn solid_top(self) -> R {
        self.bedrock + self.sand
    }

    /// `bedrock + sand + water`, as [`relief_core::MlhmColumn::water_top`].
    #[inline(always)]
    pub(crate) fn water_top(self) -> R {
        self.bedrock + self.sand + self.water
    }
}

impl From<relief_core::MlhmColumn> for Column<f32> {
    #[inline(always)]
    fn from(c: relief_core::MlhmColumn) -> Self {
        Column { bedrock: c.bedrock, sand: c.sand, water: c.water }
    }
}

impl<R: Real> Column<R> {
    /// `a` where `mask`, else `b`, field by field.
    #[inline(always)]
    pub(crate) fn select(mask: R::Mask, a: Self, b: Self) -> Self {
        Column {
            bedrock: R::select(mask, a.bedrock, b.bedrock),
            sand: R::select(mask, a.sand, b.sand),
            water: R::select(mask, a.water, b.water),
        }
    }
}

impl Column<Lanes> {
    /// The columns `columns[0..LANES]`, field by field.
    #[inline(always)]
    pub(crate) fn load(columns: &[relief_core::MlhmColumn]) -> Self {
        let c = &columns[..LANES];
        Column {
            bedrock: Lanes::from_fn(|l| c[l].bedrock),
            sand: Lanes::from_fn(|l| c[l].sand),
            water: Lanes::from_fn(|l| c[l].water),
        }
    }
}

/// The four lanes of `v` into `out[0..LANES]`, lane `l` into `out[l]`.
#[inline(always)]
pub(crate) fn store4(out: &mut [[f32; 4]], v: [Lanes; 4]) {
    let out: &mut [[f32; 4]; LANES] = (&mut out[..LANES]).try_into().expect("LANES slots");
    for (l, o) in out.iter_mut().enumerate() {
        *o = [v[0].0[l], v[1].0[l], v[2].0[l], v[3].0[l]];
    }
}

/// `src[0..LANES]` as four lanes, `src[l][d]` into lane `l` of the `d`th.
#[inline(always)]
pub(crate) fn load4(src: &[[f32; 4]]) -> [Lanes; 4] {
    let src: &[[f32; 4]; LANES] = src[..LANES].try_into().expect("LANES slots");
    map4([0, 1, 2, 3], |d| Lanes::from_fn(|l| src[l][d]))
}

/// `src[0..LANES]` as lanes.
#[inline(always)]
pub(crate) fn load(src: &[f32]) -> Lanes {
    Lanes(src[..LANES].try_into().expect("LANES slots"))
}

/// The lanes of `v` into `out[0..LANES]`.
#[inline(always)]
pub(crate) fn store(out: &mut [f32], v: Lanes) {
    out[..LANES].copy_from_slice(&v.0);
}

/// Defines `fn $name(args) -> ret { body }` so that it runs the body compiled for AVX2 (eight
/// lanes to a register) where the CPU has it, and for the baseline otherwise: the body is an
/// `#[inline(always)]` function that each version inlines whole. Both do the same IEEE
/// operations (no fused multiply-add), so they give the same bits.
macro_rules! avx2_dispatch {
    ($(#[$meta:meta])* fn $name:ident($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? $body:block) => {
        $(#[$meta])*
        fn $name($($arg: $ty),*) $(-> $ret)? {
            #[inline(always)]
            fn body($($arg: $ty),*) $(-> $ret)? $body
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2")]
                fn avx2($($arg: $ty),*) $(-> $ret)? {
                    body($($arg),*)
                }
                if std::is_x86_feature_detected!("avx2") {
                    // SAFETY: the CPU has AVX2.
                    return unsafe { avx2($($arg),*) };
                }
            }
            body($($arg),*)
        }
    };
}
pub(crate) use avx2_dispatch;

/// The two lanes of `v` into `out[0..LANES]`, lane `l` into `out[l]`.
#[inline(always)]
pub(crate) fn store2(out: &mut [[f32; 2]], v: [Lanes; 2]) {
    let out: &mut [[f32; 2]; LANES] = (&mut out[..LANES]).try_into().expect("LANES slots");
    for (l, o) in out.iter_mut().enumerate() {
        *o = [v[0].0[l], v[1].0[l]];
    }
}

impl Column<Lanes> {
    /// The lanes into `out[0..LANES]` as columns with ceiling `ceiling`.
    #[inline(always)]
    pub(crate) fn store(self, out: &mut [relief_core::MlhmColumn], ceiling: f32) {
        let out: &mut [relief_core::MlhmColumn; LANES] =
            (&mut out[..LANES]).try_into().expect("LANES slots");
        for (l, o) in out.iter_mut().enumerate() {
            *o = relief_core::MlhmColumn::new(
                self.bedrock.0[l],
                self.sand.0[l],
                self.water.0[l],
                ceiling,
            );
        }
    }
}

/// `src[0..LANES]` as two lanes, `src[l][d]` into lane `l` of the `d`th.
#[inline(always)]
pub(crate) fn load2(src: &[[f32; 2]]) -> [Lanes; 2] {
    let src: &[[f32; 2]; LANES] = src[..LANES].try_into().expect("LANES slots");
    [Lanes::from_fn(|l| src[l][0]), Lanes::from_fn(|l| src[l][1])]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_is_within_a_few_ulp_and_the_same_in_lanes() {
        let xs: Vec<f32> = (0..80_000).map(|i| i as f32 * 0.001).collect();
        for chunk in xs.chunks_exact(LANES) {
            let lanes = exp(Lanes::from_fn(|l| chunk[l]));
            for (l, &x) in chunk.iter().enumerate() {
                let one = exp(x);
                assert_eq!(one.to_bits(), lanes.0[l].to_bits(), "x = {x}");
                let exact = f64::from(x).exp();
                let error = ((f64::from(one) - exact) / exact).abs();
                assert!(error < 3e-7, "exp({x}) = {one}, {exact}: {error:e}");
            }
        }
        assert_eq!(exp(0.0f32), 1.0);
    }
}
