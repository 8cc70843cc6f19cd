//! How the MLHM hierarchy ([`crate::MlhmHierarchy`]) stores its node bounds: exactly as f32, or
//! as f16 rounded outward (maxima up, minima down), with the bulk f16 conversion, the merging
//! of node layers in either type and the per-level storage and interval walk.

use super::node_layer::MlhmNodeLayer;
use crate::MlhmMode;
use half::f16;
use half::slice::HalfFloatSliceExt;
use std::fmt::Debug;
use std::mem::size_of;

/// A scalar a stored bound is held as: `f32` exactly, or [`f16`] rounded outward, maxima up
/// and minima down, so a stored interval always encloses the exact one.
pub(crate) trait BoundScalar: Copy + PartialEq + Debug + Send + Sync {
    /// `-inf`.
    const NEG_INFINITY: Self;
    /// `+inf`.
    const INFINITY: Self;
    /// The smallest stored value `>= v`.
    fn upper(v: f32) -> Self;
    /// The largest stored value `<= v`.
    fn lower(v: f32) -> Self;
    /// The stored value, exactly, as f32.
    fn widen(self) -> f32;
    /// The larger of two stored values (exact: no rounding).
    fn larger(self, other: Self) -> Self;
    /// The smaller of two stored values (exact: no rounding).
    fn smaller(self, other: Self) -> Self;
    /// Stores each of `exact` into `out` (as long), rounded outward.
    fn store_layers(exact: &[MlhmNodeLayer], out: &mut [StoredLayer<Self>]);
    /// Stores each of `exact` into `out` (as long), rounded down.
    fn store_lower(exact: &[f32], out: &mut [Self]);
}

impl BoundScalar for f32 {
    const NEG_INFINITY: f32 = f32::NEG_INFINITY;
    const INFINITY: f32 = f32::INFINITY;
    #[inline]
    fn upper(v: f32) -> f32 {
        v
    }
    #[inline]
    fn lower(v: f32) -> f32 {
        v
    }
    #[inline]
    fn widen(self) -> f32 {
        self
    }
    /// A plain comparison, which compiles to one instruction where `f32::max`'s care for NaN
    /// takes several: bounds are never NaN (a valid map's values are not).
    #[inline]
    fn larger(self, other: f32) -> f32 {
        if self >= other {
            self
        } else {
            other
        }
    }
    #[inline]
    fn smaller(self, other: f32) -> f32 {
        if self <= other {
            self
        } else {
            other
        }
    }
    fn store_layers(exact: &[MlhmNodeLayer], out: &mut [StoredLayer<f32>]) {
        for (o, e) in out.iter_mut().zip(exact) {
            *o = StoredLayer::store(*e);
        }
    }
    fn store_lower(exact: &[f32], out: &mut [f32]) {
        out.copy_from_slice(exact);
    }
}

impl BoundScalar for f16 {
    const NEG_INFINITY: f16 = f16::NEG_INFINITY;
    const INFINITY: f16 = f16::INFINITY;
    /// Rounds to nearest, then one f16 step up if that fell below: a finite `v` beyond f16's
    /// range gives `+inf` (above `65504`) or `-65504` (below `-65504`); infinities stay.
    #[inline]
    fn upper(v: f32) -> f16 {
        let nearest = f16::from_f32_const(v);
        if nearest.to_f32_const() < v {
            f16_step_up(nearest)
        } else {
            nearest
        }
    }
    #[inline]
    fn lower(v: f32) -> f16 {
        -f16::upper(-v)
    }
    /// In software, which inlines: faster here than the runtime-dispatched F16C call.
    #[inline]
    fn widen(self) -> f32 {
        self.to_f32_const()
    }
    /// Compares the bits, converting nothing.
    #[inline]
    fn larger(self, other: f16) -> f16 {
        self.max(other)
    }
    #[inline]
    fn smaller(self, other: f16) -> f16 {
        self.min(other)
    }
    /// In bulk: see [`f16_outward`].
    fn store_layers(exact: &[MlhmNodeLayer], out: &mut [StoredLayer<f16>]) {
        // Maxima and minima apart, each rounded one way in one pass.
        let mut maxima = vec![0.0; 2 * exact.len()];
        let mut minima = vec![0.0; 2 * exact.len()];
        for ((max, min), l) in maxima.chunks_exact_mut(2).zip(minima.chunks_exact_mut(2)).zip(exact)
        {
            max.copy_from_slice(&[l.water_max, l.solid_max]);
            min.copy_from_slice(&[l.ceiling_min, l.air_min]);
        }
        let (maxima, minima) = (f16_outward(&maxima, true), f16_outward(&minima, false));
        for ((o, max), min) in
            out.iter_mut().zip(maxima.chunks_exact(2)).zip(minima.chunks_exact(2))
        {
            *o = StoredLayer {
                water_max: max[0],
                ceiling_min: min[0],
                solid_max: max[1],
                air_min: min[1],
            };
        }
    }
    fn store_lower(exact: &[f32], out: &mut [f16]) {
        out.copy_from_slice(&f16_outward(exact, false));
    }
}

/// `values` as f16s, rounded `up` or down: converted to nearest in bulk (the `half` crate's
/// slice conversion, SIMD where the CPU has it, F16C on x86), then each one that went the
/// wrong way stepped outward by one f16.
pub(crate) fn f16_outward(values: &[f32], up: bool) -> Vec<f16> {
    let mut rounded = vec![f16::ZERO; values.len()];
    rounded.convert_from_f32_slice(values);
    let mut back = vec![0.0f32; values.len()];
    rounded.convert_to_f32_slice(&mut back);
    for (r, (&v, &b)) in rounded.iter_mut().zip(values.iter().zip(&back)) {
        // Half of them go the wrong way, at random: selects, not branches (it vectorizes).
        let wrong = if up { b < v } else { b > v };
        *r = if wrong { f16_step_up_or_down(*r, up) } else { *r };
    }
    rounded
}

/// The next f16 above `h` (`up`) or below it, for any `h` but the infinity it would step past
/// and NaN (`-inf` steps up to `-65504`, `+inf` down to `65504`).
#[inline]
fn f16_step_up_or_down(h: f16, up: bool) -> f16 {
    let bits = h.to_bits();
    // Nonzero: one unit in the last place away from zero on the side it steps to, towards
    // zero on the other. From +-0: the smallest subnormal of that side.
    let away_from_zero = (bits & 0x8000 == 0) == up;
    let step = if away_from_zero { 1 } else { u16::MAX };
    let from_zero = if up { 0x0001 } else { 0x8001 };
    f16::from_bits(if bits & 0x7fff == 0 { from_zero } else { bits.wrapping_add(step) })
}

/// The next f16 above `h`, for any `h` but `+inf` and NaN (`-inf` steps to `-65504`).
#[inline]
fn f16_step_up(h: f16) -> f16 {
    f16_step_up_or_down(h, true)
}

/// The smallest f32 `>= v + radius` (`v + radius` exactly, in f64, rounded up): a maximum
/// raised by a padding, never below the exact padded value. Infinities stay; a sum beyond
/// f32's range gives `+inf`.
#[inline]
pub(crate) fn pad_up(v: f32, radius: f64) -> f32 {
    let exact = f64::from(v) + radius;
    let nearest = exact as f32;
    if f64::from(nearest) < exact {
        nearest.next_up()
    } else {
        nearest
    }
}

/// The largest f32 `<= v - radius`: a minimum lowered by a padding (see [`pad_up`]).
#[inline]
pub(crate) fn pad_down(v: f32, radius: f64) -> f32 {
    -pad_up(-v, radius)
}

/// `layer` padded by `radius` metres, rounded outward: maxima raised, minima lowered.
#[inline]
pub(crate) fn padded_layer(layer: MlhmNodeLayer, radius: f64) -> MlhmNodeLayer {
    MlhmNodeLayer {
        water_max: pad_up(layer.water_max, radius),
        ceiling_min: pad_down(layer.ceiling_min, radius),
        solid_max: pad_up(layer.solid_max, radius),
        air_min: pad_down(layer.air_min, radius),
    }
}

/// Node layer bounds as a level's build merges them: in the stored type, where merging needs
/// no rounding (f32 bounds, and the f16 bounds of the levels above level 1, which are f16s
/// already), or exact f32 bounds of cells ([`MlhmNodeLayer`]) that are rounded to f16 once
/// merged.
pub(crate) trait MergedLayer<S: BoundScalar>: Copy + Send + Sync {
    /// Bounds nothing reaches.
    const EMPTY: Self;
    /// Both bounds' enclosure.
    fn merge(self, other: Self) -> Self;
    /// These bounds widened by `radius` metres (see [`padded_layer`]).
    fn padded(self, radius: f64) -> Self;
    /// Calls `merge` with a row of bounds as long as `out`, which it sets all of (each node
    /// from [`EMPTY`](MergedLayer::EMPTY) up), then stores them into `out`, rounded outward.
    /// Returns the highest solid and water tops merged when they are known exactly here and
    /// would not be from `out` (rounded).
    fn merge_row(out: &mut [StoredLayer<S>], merge: impl FnOnce(&mut [Self]))
        -> Option<(f32, f32)>;
}

impl<S: BoundScalar> MergedLayer<S> for MlhmNodeLayer {
    const EMPTY: Self = MlhmNodeLayer::EMPTY;
    #[inline]
    fn merge(self, other: Self) -> Self {
        MlhmNodeLayer::merge(self, other)
    }
    #[inline]
    fn padded(self, radius: f64) -> Self {
        padded_layer(self, radius)
    }
    /// Merges into scratch, then rounds the row in bulk.
    fn merge_row(
        out: &mut [StoredLayer<S>],
        merge: impl FnOnce(&mut [Self]),
    ) -> Option<(f32, f32)> {
        let mut row = vec![MlhmNodeLayer::EMPTY; out.len()];
        merge(&mut row);
        S::store_layers(&row, out);
        let tops = (f32::NEG_INFINITY, f32::NEG_INFINITY);
        Some(row.iter().fold(tops, |t, l| (t.0.max(l.solid_max), t.1.max(l.water_max))))
    }
}

impl<S: BoundScalar> MergedLayer<S> for StoredLayer<S> {
    const EMPTY: Self = StoredLayer {
        water_max: S::NEG_INFINITY,
        ceiling_min: S::INFINITY,
        solid_max: S::NEG_INFINITY,
        air_min: S::INFINITY,
    };
    #[inline]
    fn merge(self, other: Self) -> Self {
        StoredLayer {
            water_max: self.water_max.larger(other.water_max),
            ceiling_min: self.ceiling_min.smaller(other.ceiling_min),
            solid_max: self.solid_max.larger(other.solid_max),
            air_min: self.air_min.smaller(other.air_min),
        }
    }
    /// Pads the bounds as f32, then rounds them outward to `S` again.
    fn padded(self, radius: f64) -> Self {
        StoredLayer::store(padded_layer(self.load(), radius))
    }
    /// Merges in place.
    fn merge_row(
        out: &mut [StoredLayer<S>],
        merge: impl FnOnce(&mut [Self]),
    ) -> Option<(f32, f32)> {
        merge(out);
        None
    }
}

/// [`MlhmNodeLayer`] as stored, in a [`BoundScalar`]; `repr(C)`, so that the build's vector
/// merges read a layer's four bounds, in this order, as one register.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub(crate) struct StoredLayer<S> {
    pub(crate) water_max: S,
    pub(crate) ceiling_min: S,
    pub(crate) solid_max: S,
    pub(crate) air_min: S,
}

impl<S: BoundScalar> StoredLayer<S> {
    /// `layer` rounded outward.
    #[inline]
    pub(crate) fn store(layer: MlhmNodeLayer) -> Self {
        StoredLayer {
            water_max: S::upper(layer.water_max),
            ceiling_min: S::lower(layer.ceiling_min),
            solid_max: S::upper(layer.solid_max),
            air_min: S::lower(layer.air_min),
        }
    }

    /// The stored bounds, exactly, as f32.
    #[inline]
    pub(crate) fn load(self) -> MlhmNodeLayer {
        MlhmNodeLayer {
            water_max: self.water_max.widen(),
            ceiling_min: self.ceiling_min.widen(),
            solid_max: self.solid_max.widen(),
            air_min: self.air_min.widen(),
        }
    }
}

/// The bounds of every node of one level, in one scalar type.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LevelBounds<S> {
    /// Per node, `cap` layer slots, node-major (node `i`'s layers at `i * cap..`).
    pub(crate) layers: Vec<StoredLayer<S>>,
    /// Per node, the lowest water top of the topmost column of any cell it covers.
    pub(crate) sky: Vec<S>,
}

impl<S: BoundScalar> LevelBounds<S> {
    pub(crate) fn empty(nodes: usize, cap: usize) -> Self {
        LevelBounds {
            layers: vec![StoredLayer::store(MlhmNodeLayer::EMPTY); nodes * cap],
            sky: vec![S::lower(f32::INFINITY); nodes],
        }
    }

    /// Bytes of storage.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.layers.len() * size_of::<StoredLayer<S>>() + self.sky.len() * size_of::<S>()
    }

    /// [`MlhmHierarchy::for_each_interval`] on node `node`'s `n` layers (of `cap` slots).
    #[inline]
    pub(crate) fn for_each_interval(
        &self,
        node: usize,
        cap: usize,
        n: usize,
        mode: MlhmMode,
        mut f: impl FnMut(f64, f64) -> bool,
    ) -> bool {
        let layers = &self.layers[node * cap..][..n];
        let mut below: Option<&StoredLayer<S>> = None;
        for layer in layers {
            let (bottom, top) = match mode {
                MlhmMode::Solids => (
                    below.map_or(f32::NEG_INFINITY, |b| b.ceiling_min.widen()),
                    layer.solid_max.widen(),
                ),
                MlhmMode::SolidsWater => (
                    below.map_or(f32::NEG_INFINITY, |b| b.ceiling_min.widen()),
                    layer.water_max.widen(),
                ),
                MlhmMode::SolidsAir => (
                    below.map_or(f32::NEG_INFINITY, |b| b.air_min.widen()),
                    layer.solid_max.widen(),
                ),
            };
            if f(bottom as f64, top as f64) {
                return true;
            }
            below = Some(layer);
        }
        mode == MlhmMode::SolidsAir && f(self.sky[node].widen() as f64, f64::INFINITY)
    }
}

/// A level's bounds at the hierarchy's [`Precision`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum StoredBounds {
    F32(LevelBounds<f32>),
    F16(LevelBounds<f16>),
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every f16 value but NaN (one zero), as f32, ascending: `-inf .. +inf`.
    fn all_f16_ascending() -> Vec<f32> {
        let mut all: Vec<f32> = (0..=u16::MAX)
            .filter(|&bits| bits != 0x8000) // -0: one zero is enough
            .map(|bits| f16::from_bits(bits).to_f32())
            .filter(|v| !v.is_nan())
            .collect();
        all.sort_by(f32::total_cmp);
        all
    }

    /// The next f32 above (`+1`) or below (`-1`) a finite nonzero `v` (by magnitude in bits).
    fn f32_neighbours(v: f32) -> [f32; 2] {
        let bits = v.to_bits();
        [f32::from_bits(bits + 1), f32::from_bits(bits - 1)]
    }

    #[test]
    fn f16_rounding_is_outward_and_tight_everywhere() {
        let all = all_f16_ascending();
        assert_eq!((all[0], all[all.len() - 1]), (f32::NEG_INFINITY, f32::INFINITY));
        let mut values = vec![0.0, -0.0, 1e-9, -1e-9, 65504.5, 65520.0, 1e6, -1e6, f32::MAX];
        values.extend([f32::MIN, f32::MIN_POSITIVE, f32::INFINITY, f32::NEG_INFINITY, 1000.3]);
        // Every f16, the midpoints between neighbours (ties of round-to-nearest) and the
        // f32s right beside both.
        for pair in all[1..all.len() - 1].windows(2) {
            let mid = 0.5 * (pair[0] + pair[1]);
            values.extend([pair[0], mid]);
            for v in [pair[0], mid] {
                if v != 0.0 {
                    values.extend(f32_neighbours(v));
                }
            }
        }
        // One by one and in bulk.
        let bulk_up = f16_outward(&values, true);
        let bulk_down = f16_outward(&values, false);
        for (i, &v) in values.iter().enumerate() {
            let (up, down) = (f16::upper(v).to_f32(), f16::lower(v).to_f32());
            let expected_up = all[all.partition_point(|&a| a < v)];
            let expected_down = all[all.partition_point(|&a| a <= v) - 1];
            assert_eq!((up, down), (expected_up, expected_down), "{v:e}");
            assert_eq!((bulk_up[i].to_f32(), bulk_down[i].to_f32()), (up, down), "{v:e}");
        }
        // Round to nearest goes the wrong way here, outward rounding does not.
        assert!(f16::from_f32(1000.2).to_f32() < 1000.2);
        assert_eq!(f16::upper(1000.2).to_f32(), 1000.5);
        assert!(f16::from_f32(1000.3).to_f32() > 1000.3);
        assert_eq!(f16::lower(1000.3).to_f32(), 1000.0);
        assert_eq!(f16::upper(70000.0), f16::INFINITY);
        assert_eq!(f16::lower(70000.0), f16::MAX);
        assert_eq!(f16::lower(-70000.0), f16::NEG_INFINITY);
    }
}
