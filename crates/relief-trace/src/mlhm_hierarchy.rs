//! The MLHM's 2D hierarchy of conservative column bounds (Nilles & Müller 2025, section 4.2):
//! its levels, layer caps and folding, its parallel bottom-up build, and its bounds stored as
//! exact f32 or as f16 rounded outward.

use crate::MlhmMode;
use half::f16;
use half::slice::HalfFloatSliceExt;
use rayon::prelude::*;
use relief_core::{Mlhm, Precision};
use std::fmt::Debug;
use std::mem::size_of;

/// The four bounds of one layer of a hierarchy node, over every column it stands for.
///
/// For layer `k` of a node, the boxes of the three [`MlhmMode`]s are enclosed by
///
/// - solids: `[ceiling_min(k - 1), solid_max(k)]`,
/// - solids + water: `[ceiling_min(k - 1), water_max(k)]`,
/// - solids + air: `[air_min(k - 1), solid_max(k)]`, plus the open sky above the node,
///   `[sky_min, +inf]` (see [`MlhmHierarchy::sky_min`]),
///
/// with `ceiling_min(-1) = air_min(-1) = -inf`. A layer no column of the node reaches holds
/// `-inf` maxima and `+inf` minima.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlhmNodeLayer {
    /// Highest water top (`bedrock + sand + water`).
    pub water_max: f32,
    /// Lowest ceiling: the lowest floor of the layer above.
    pub ceiling_min: f32,
    /// Highest solid top (`bedrock + sand`).
    pub solid_max: f32,
    /// Lowest water top: where the air of the layer (the bottom of the air box of the layer
    /// above, for rays inside water) begins at the lowest.
    pub air_min: f32,
}

impl MlhmNodeLayer {
    /// The bounds of a layer nothing reaches: any column merged in replaces them.
    pub const EMPTY: MlhmNodeLayer = MlhmNodeLayer {
        water_max: f32::NEG_INFINITY,
        ceiling_min: f32::INFINITY,
        solid_max: f32::NEG_INFINITY,
        air_min: f32::INFINITY,
    };

    /// These bounds widened to enclose `other` as well.
    #[inline]
    pub fn merge(self, other: MlhmNodeLayer) -> MlhmNodeLayer {
        MlhmNodeLayer {
            water_max: self.water_max.max(other.water_max),
            ceiling_min: self.ceiling_min.min(other.ceiling_min),
            solid_max: self.solid_max.max(other.solid_max),
            air_min: self.air_min.min(other.air_min),
        }
    }
}

/// A scalar a stored bound is held as: `f32` exactly, or [`f16`] rounded outward, maxima up
/// and minima down, so a stored interval always encloses the exact one.
trait BoundScalar: Copy + PartialEq + Debug + Send + Sync {
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
    #[inline]
    fn larger(self, other: f32) -> f32 {
        self.max(other)
    }
    #[inline]
    fn smaller(self, other: f32) -> f32 {
        self.min(other)
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
fn f16_outward(values: &[f32], up: bool) -> Vec<f16> {
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

/// Node layer bounds as a level's build merges them: in the stored type, where merging needs
/// no rounding (f32 bounds, and the f16 bounds of the levels above level 1, which are f16s
/// already), or exact f32 bounds of cells ([`MlhmNodeLayer`]) that are rounded to f16 once
/// merged.
trait MergedLayer<S: BoundScalar>: Copy + Send + Sync {
    /// Bounds nothing reaches.
    const EMPTY: Self;
    /// Both bounds' enclosure.
    fn merge(self, other: Self) -> Self;
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
    /// Merges in place.
    fn merge_row(
        out: &mut [StoredLayer<S>],
        merge: impl FnOnce(&mut [Self]),
    ) -> Option<(f32, f32)> {
        merge(out);
        None
    }
}

/// [`MlhmNodeLayer`] as stored, in a [`BoundScalar`].
#[derive(Debug, Clone, Copy, PartialEq)]
struct StoredLayer<S> {
    water_max: S,
    ceiling_min: S,
    solid_max: S,
    air_min: S,
}

impl<S: BoundScalar> StoredLayer<S> {
    /// `layer` rounded outward.
    #[inline]
    fn store(layer: MlhmNodeLayer) -> Self {
        StoredLayer {
            water_max: S::upper(layer.water_max),
            ceiling_min: S::lower(layer.ceiling_min),
            solid_max: S::upper(layer.solid_max),
            air_min: S::lower(layer.air_min),
        }
    }

    /// The stored bounds, exactly, as f32.
    #[inline]
    fn load(self) -> MlhmNodeLayer {
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
struct LevelBounds<S> {
    /// Per node, `cap` layer slots, node-major (node `i`'s layers at `i * cap..`).
    layers: Vec<StoredLayer<S>>,
    /// Per node, the lowest water top of the topmost column of any cell it covers.
    sky: Vec<S>,
}

impl<S: BoundScalar> LevelBounds<S> {
    fn empty(nodes: usize, cap: usize) -> Self {
        LevelBounds {
            layers: vec![StoredLayer::store(MlhmNodeLayer::EMPTY); nodes * cap],
            sky: vec![S::lower(f32::INFINITY); nodes],
        }
    }

    /// Bytes of storage.
    fn memory_bytes(&self) -> usize {
        self.layers.len() * size_of::<StoredLayer<S>>() + self.sky.len() * size_of::<S>()
    }

    /// [`MlhmHierarchy::for_each_interval`] on node `node`'s `n` layers (of `cap` slots).
    #[inline]
    fn for_each_interval(
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
enum StoredBounds {
    F32(LevelBounds<f32>),
    F16(LevelBounds<f16>),
}

/// One level of the hierarchy above the cells.
#[derive(Debug, Clone, PartialEq)]
struct Level {
    nodes_x: usize,
    nodes_y: usize,
    /// Layers kept per node at this level.
    cap: usize,
    /// Per node, how many of its `cap` layer slots hold bounds.
    counts: Vec<u8>,
    /// Per node, its layers' bounds and where its open sky begins.
    bounds: StoredBounds,
}

/// A hierarchy of conservative bounds over an [`Mlhm`]'s cells, for the hierarchical box
/// traversal ([`crate::MlhmHierarchyTracer`]).
///
/// Level 0 is the map itself. Above it are
/// [`level_count`](MlhmHierarchy::level_count)` = clamp(ceil(log2(max(W, H))) - 1, 1, 11)`
/// levels; node `(x, y)` of level `i` covers cells `[x 2^i, (x + 1) 2^i) x [y 2^i, (y + 1) 2^i)`
/// (clipped to the grid), so level `i` has `ceil(W / 2^i) x ceil(H / 2^i)` nodes. Level `i`
/// merges layer `k` of the 2 x 2 nodes (cells, for level 1) below it into its layer `k`
/// ([`MlhmNodeLayer`]). The layers kept per node start from the map's maximum layer count and
/// halve, rounding up, at every odd level (8, 4, 4, 2, 2, 1, ...); the layers of a child
/// beyond its parent's cap are folded into the parent's top kept layer.
///
/// Bounds are stored at a [`Precision`] chosen at build time:
///
/// - [`Precision::F32`] (16 bytes per node layer): exact, the maxima and minima of the map's
///   own f32 sums;
/// - [`Precision::F16`] (8 bytes per node layer), as the paper stores them: each level-1
///   bound is rounded outward from the exact one, maxima up and minima down (not to nearest,
///   which could cut into a box), and the levels above take maxima and minima of these, which
///   are f16 already. So every stored bound is the exact f32 bound rounded outward to the
///   nearest f16 on its side. Infinities stay; a finite maximum above 65504 becomes `+inf`
///   and a finite minimum below -65504 becomes `-inf`.
///
/// At either precision each node layer's interval in each [`MlhmMode`] contains every child
/// interval it stands for, and a ray that misses all of a node's intervals misses every box of
/// its cells. The bounds only cull: hits come from the cells (level 0, the map itself, at its
/// own [`Mlhm::precision`]), and the scene top ([`MlhmHierarchy::top`]) is exact at both.
///
/// The build runs bottom-up, each level's rows in parallel (rayon); it is cheap enough to
/// redo every frame of a simulation.
///
/// ```
/// use relief_core::{Mlhm, MlhmColumn, Precision};
/// use relief_trace::MlhmHierarchy;
/// let mut map = Mlhm::new(4, 4, 4, 1.0)?;
/// map.set_cell(1, 2, &[
///     MlhmColumn::new(1.0, 0.5, 0.0, 3.0),
///     MlhmColumn::new(4.0, 0.0, 1.0, f32::INFINITY),
/// ])?;
/// let hierarchy = MlhmHierarchy::build(&map);
/// assert_eq!(hierarchy.level_count(), 1);
/// assert_eq!(hierarchy.nodes(1), (2, 2));
/// assert_eq!(hierarchy.layer_cap(1), 2); // 4 layers, halved at level 1
/// let layer = hierarchy.node_layer(1, 0, 1, 1);
/// assert_eq!((layer.solid_max, layer.water_max), (4.0, 5.0));
/// assert_eq!(hierarchy.node_layer(1, 0, 1, 0).ceiling_min, 3.0);
///
/// // In half precision, 1000.3 (between the f16s 1000.0 and 1000.5) bounds as 1000.5 from
/// // above and as 1000.0 from below.
/// map.set_cell(0, 0, &[
///     MlhmColumn::new(1000.3, 0.0, 0.0, 1000.3),
///     MlhmColumn::new(1001.0, 0.0, 0.0, f32::INFINITY),
/// ])?;
/// let half = MlhmHierarchy::build_with_precision(&map, Precision::F16);
/// let layer = half.node_layer(1, 0, 0, 0);
/// assert_eq!((layer.solid_max, layer.ceiling_min), (1000.5, 1000.0));
/// // 2 x 2 nodes of 2 layer slots: 16 and 8 bytes a slot, 1 byte of count and 4 or 2 of sky
/// // a node.
/// assert_eq!(MlhmHierarchy::build(&map).memory_bytes(), 4 * (1 + 4 + 2 * 16));
/// assert_eq!(half.memory_bytes(), 4 * (1 + 2 + 2 * 8));
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MlhmHierarchy {
    width: usize,
    height: usize,
    precision: Precision,
    levels: Vec<Level>,
    /// Exact highest solid top over the map.
    solid_max: f32,
    /// Exact highest water top over the map.
    water_max: f32,
}

/// Largest number of levels above the cells.
pub const MAX_HIERARCHY_LEVELS: usize = 11;

impl MlhmHierarchy {
    /// Builds the hierarchy of `map` with exact f32 bounds ([`Precision::F32`]).
    pub fn build(map: &Mlhm) -> Self {
        Self::build_with_precision(map, Precision::F32)
    }

    /// Builds the hierarchy of `map` with its bounds stored at `precision`: exact f32, or f16
    /// rounded outward (see [`MlhmHierarchy`]).
    pub fn build_with_precision(map: &Mlhm, precision: Precision) -> Self {
        let (width, height) = (map.width(), map.height());
        let levels = Self::level_shapes(map)
            .map(|(nodes_x, nodes_y, cap)| Level::empty(nodes_x, nodes_y, cap, precision))
            .collect();
        let mut hierarchy = MlhmHierarchy {
            width,
            height,
            precision,
            levels,
            solid_max: f32::NEG_INFINITY,
            water_max: f32::NEG_INFINITY,
        };
        hierarchy.fill(map);
        hierarchy
    }

    /// Rebuilds the hierarchy from `map` (say, after a simulation step) at its precision,
    /// reusing its storage when the map's grid and layer count are those it was built for.
    pub fn rebuild(&mut self, map: &Mlhm) {
        let same = (self.width, self.height) == (map.width(), map.height())
            && Self::level_shapes(map)
                .zip(&self.levels)
                .all(|((nx, ny, cap), l)| (nx, ny, cap) == (l.nodes_x, l.nodes_y, l.cap));
        if same {
            self.fill(map);
        } else {
            *self = Self::build_with_precision(map, self.precision);
        }
    }

    /// Nodes along x and y and the layer cap of each level, from level 1 up.
    fn level_shapes(map: &Mlhm) -> impl Iterator<Item = (usize, usize, usize)> {
        let (width, height) = (map.width(), map.height());
        let count = Self::level_count_for(width, height);
        let mut cap = map.max_layers().max(1);
        (1..=count).map(move |i| {
            if i % 2 == 1 {
                cap = cap.div_ceil(2);
            }
            (width.div_ceil(1 << i), height.div_ceil(1 << i), cap)
        })
    }

    /// Computes every level's bounds from `map`, bottom-up, into storage of the right shape,
    /// and the exact tops of the map: from level 1's bounds before they are rounded to f16, or
    /// from the top level's exact f32 bounds.
    fn fill(&mut self, map: &Mlhm) {
        let rounded_tops = Self::fill_first(&mut self.levels[0], map);
        for i in 1..self.levels.len() {
            let (below, above) = self.levels.split_at_mut(i);
            Self::fill_above(&mut above[0], &below[i - 1]);
        }
        (self.solid_max, self.water_max) = rounded_tops.unwrap_or_else(|| {
            let top = self.levels.last().expect("at least one level");
            let StoredBounds::F32(bounds) = &top.bounds else {
                unreachable!("only f32 bounds keep the tops exact")
            };
            let lowest = (f32::NEG_INFINITY, f32::NEG_INFINITY);
            bounds.layers.iter().fold(lowest, |t, l| (t.0.max(l.solid_max), t.1.max(l.water_max)))
        });
    }

    /// Number of levels above the cells for a grid of `width x height` cells:
    /// `clamp(ceil(log2(max(W, H))) - 1, 1, 11)`.
    pub fn level_count_for(width: usize, height: usize) -> usize {
        let n = width.max(height).max(1);
        let ceil_log2 = (usize::BITS - (n - 1).leading_zeros()) as usize;
        ceil_log2.saturating_sub(1).clamp(1, MAX_HIERARCHY_LEVELS)
    }

    /// Level 1, from the map's cells; returns the exact highest solid and water tops when
    /// the stored bounds are rounded.
    fn fill_first(level: &mut Level, map: &Mlhm) -> Option<(f32, f32)> {
        let (w, h) = (map.width(), map.height());
        let (columns, counts, plane) = (map.raw_columns(), map.layer_counts(), w * h);
        let count = |cell: usize| usize::from(counts[cell]);
        let layer = |cell: usize, j: usize| {
            let c = columns[cell + j * plane];
            let water_top = c.water_top();
            MlhmNodeLayer {
                water_max: water_top,
                ceiling_min: c.ceiling,
                solid_max: c.solid_top(),
                air_min: water_top,
            }
        };
        // The open sky starts at the top column's water top.
        let sky = |cell: usize| columns[cell + (count(cell) - 1) * plane].water_top();
        let (nodes_x, cap) = (level.nodes_x, level.cap);
        let counts = &mut level.counts;
        match &mut level.bounds {
            StoredBounds::F32(b) => {
                // Stored as they are: merged in place.
                let layer = |cell: usize, j: usize| StoredLayer::<f32>::store(layer(cell, j));
                Self::merge_children(b, counts, nodes_x, cap, (w, h), count, layer, sky)
            }
            StoredBounds::F16(b) => {
                Self::merge_children(b, counts, nodes_x, cap, (w, h), count, layer, sky)
            }
        }
    }

    /// The level above `below`, merging its 2 x 2 nodes.
    fn fill_above(level: &mut Level, below: &Level) {
        let count = |child: usize| usize::from(below.counts[child]);
        let children = (below.nodes_x, below.nodes_y);
        let (nodes_x, cap, below_cap) = (level.nodes_x, level.cap, below.cap);
        let counts = &mut level.counts;
        match (&mut level.bounds, &below.bounds) {
            (StoredBounds::F32(b), StoredBounds::F32(c)) => {
                let layer = |child: usize, j: usize| c.layers[child * below_cap + j];
                let sky = |child: usize| c.sky[child].widen();
                Self::merge_children(b, counts, nodes_x, cap, children, count, layer, sky);
            }
            (StoredBounds::F16(b), StoredBounds::F16(c)) => {
                let layer = |child: usize, j: usize| c.layers[child * below_cap + j];
                let sky = |child: usize| c.sky[child].widen();
                Self::merge_children(b, counts, nodes_x, cap, children, count, layer, sky);
            }
            _ => unreachable!("every level of a hierarchy has its precision"),
        }
    }

    /// Fills every node of a level (`nodes_x` nodes a row, `cap` layers a node; `bounds` and
    /// `counts` its storage) from its (up to) 2 x 2 children in a grid of `children` (x, y): a
    /// child has `count(child)` layers, bottom to top, bounded by `layer(child, j)`, and its
    /// open sky starts at `sky(child)`. Layers past the level's cap fold into its top kept
    /// layer. Merges exactly, as `L`, and stores each bound rounded outward; returns the
    /// highest solid and water tops merged when `L` knows them exactly before rounding.
    #[allow(clippy::too_many_arguments)]
    fn merge_children<S: BoundScalar, L: MergedLayer<S>>(
        bounds: &mut LevelBounds<S>,
        counts: &mut [u8],
        nodes_x: usize,
        cap: usize,
        children: (usize, usize),
        count: impl Fn(usize) -> usize + Sync,
        layer: impl Fn(usize, usize) -> L + Sync,
        sky: impl Fn(usize) -> f32 + Sync,
    ) -> Option<(f32, f32)> {
        let (children_x, children_y) = children;
        let max_pair = |a: Option<(f32, f32)>, b: Option<(f32, f32)>| match (a, b) {
            (Some(a), Some(b)) => Some((a.0.max(b.0), a.1.max(b.1))),
            (a, b) => a.or(b),
        };
        bounds
            .layers
            .par_chunks_mut(nodes_x * cap)
            .zip(counts.par_chunks_mut(nodes_x))
            .zip(bounds.sky.par_chunks_mut(nodes_x))
            .enumerate()
            .map(|(ny, ((layers, node_counts), node_sky))| {
                let mut lowest_sky = vec![f32::INFINITY; nodes_x];
                // A row at a time, so that f16 rounding runs in bulk.
                let tops = L::merge_row(layers, |merged| {
                    for nx in 0..nodes_x {
                        let merged = &mut merged[nx * cap..(nx + 1) * cap];
                        merged.fill(L::EMPTY);
                        let lowest_sky = &mut lowest_sky[nx];
                        let mut used = 0;
                        for y in 2 * ny..(2 * ny + 2).min(children_y) {
                            for x in 2 * nx..(2 * nx + 2).min(children_x) {
                                let child = x + y * children_x;
                                let n = count(child);
                                for j in 0..n {
                                    let k = j.min(cap - 1);
                                    merged[k] = merged[k].merge(layer(child, j));
                                }
                                *lowest_sky = lowest_sky.min(sky(child));
                                used = used.max(n.min(cap));
                            }
                        }
                        node_counts[nx] = used as u8;
                    }
                });
                S::store_lower(&lowest_sky, node_sky);
                tops
            })
            .reduce(|| None, max_pair)
    }

    /// Cells along x and y of the map it was built from.
    pub fn cells(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The precision its bounds are stored at.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// Bytes its node storage takes: per node a layer count (1 byte) and the open sky's
    /// start, and per layer slot ([`layer_cap`](MlhmHierarchy::layer_cap) a node) four bounds;
    /// a bound is 4 bytes at [`Precision::F32`] and 2 at [`Precision::F16`].
    pub fn memory_bytes(&self) -> usize {
        self.levels
            .iter()
            .map(|l| {
                l.counts.len()
                    + match &l.bounds {
                        StoredBounds::F32(b) => b.memory_bytes(),
                        StoredBounds::F16(b) => b.memory_bytes(),
                    }
            })
            .sum()
    }

    /// Number of levels above the cells (level 0); levels are numbered `1..=level_count()`.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    fn level(&self, level: usize) -> &Level {
        assert!(
            (1..=self.levels.len()).contains(&level),
            "level {level} outside 1..={}",
            self.levels.len()
        );
        &self.levels[level - 1]
    }

    /// Nodes along x and y of `level` (`1..=level_count()`).
    ///
    /// # Panics
    /// When `level` is out of range (as every accessor below).
    pub fn nodes(&self, level: usize) -> (usize, usize) {
        let l = self.level(level);
        (l.nodes_x, l.nodes_y)
    }

    /// Layers kept per node at `level`.
    pub fn layer_cap(&self, level: usize) -> usize {
        self.level(level).cap
    }

    /// Number of layers node `(x, y)` of `level` holds (at most the level's cap).
    ///
    /// # Panics
    /// Also when `(x, y)` is outside the level.
    pub fn layer_count(&self, level: usize, x: usize, y: usize) -> usize {
        let l = self.level(level);
        assert!(x < l.nodes_x && y < l.nodes_y, "node ({x}, {y}) outside level {level}");
        usize::from(l.counts[x + y * l.nodes_x])
    }

    /// The bounds of layer `k` of node `(x, y)` of `level`, as stored (at f16 precision,
    /// exactly the f16 values).
    ///
    /// # Panics
    /// Also when `k >= layer_count(level, x, y)`.
    pub fn node_layer(&self, level: usize, x: usize, y: usize, k: usize) -> MlhmNodeLayer {
        let n = self.layer_count(level, x, y);
        assert!(k < n, "layer {k} of node ({x}, {y}) of level {level}, which has {n}");
        let l = self.level(level);
        let slot = (x + y * l.nodes_x) * l.cap + k;
        match &l.bounds {
            StoredBounds::F32(b) => b.layers[slot].load(),
            StoredBounds::F16(b) => b.layers[slot].load(),
        }
    }

    /// The lowest water top of the topmost column of any cell under node `(x, y)` of `level`:
    /// where the open sky above the node begins at the lowest (rounded down at f16).
    pub fn sky_min(&self, level: usize, x: usize, y: usize) -> f32 {
        let _ = self.layer_count(level, x, y);
        let l = self.level(level);
        let node = x + y * l.nodes_x;
        match &l.bounds {
            StoredBounds::F32(b) => b.sky[node].widen(),
            StoredBounds::F16(b) => b.sky[node].widen(),
        }
    }

    /// Highest box top over the map in `mode` (`+inf` for [`MlhmMode::SolidsAir`]); exact at
    /// either precision.
    pub fn top(&self, mode: MlhmMode) -> f64 {
        match mode {
            MlhmMode::Solids => self.solid_max as f64,
            MlhmMode::SolidsWater => self.water_max as f64,
            MlhmMode::SolidsAir => f64::INFINITY,
        }
    }

    /// Calls `f` with each interval `[bottom, top]` that encloses node `(x, y)` of `level` in
    /// `mode` (see [`MlhmNodeLayer`]), bottom to top; stops when `f` returns `true`, and
    /// returns whether it did.
    ///
    /// # Panics
    /// When the level or node is out of range.
    #[inline]
    pub fn for_each_interval(
        &self,
        level: usize,
        x: usize,
        y: usize,
        mode: MlhmMode,
        f: impl FnMut(f64, f64) -> bool,
    ) -> bool {
        let l = &self.levels[level - 1];
        let node = x + y * l.nodes_x;
        let n = usize::from(l.counts[node]);
        match &l.bounds {
            StoredBounds::F32(b) => b.for_each_interval(node, l.cap, n, mode, f),
            StoredBounds::F16(b) => b.for_each_interval(node, l.cap, n, mode, f),
        }
    }
}

impl Level {
    fn empty(nodes_x: usize, nodes_y: usize, cap: usize, precision: Precision) -> Level {
        let nodes = nodes_x * nodes_y;
        Level {
            nodes_x,
            nodes_y,
            cap,
            counts: vec![0; nodes],
            bounds: match precision {
                Precision::F32 => StoredBounds::F32(LevelBounds::empty(nodes, cap)),
                Precision::F16 => StoredBounds::F16(LevelBounds::empty(nodes, cap)),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::MlhmColumn;

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

    #[test]
    fn f16_hierarchy_is_the_f32_one_rounded_outward_at_half_the_size() {
        let mut map = Mlhm::new(64, 1, 8, 1.0).unwrap();
        let columns: Vec<MlhmColumn> = (0..8)
            .map(|k| {
                let ceiling = if k == 7 { f32::INFINITY } else { 3.1 * k as f32 + 2.2 };
                MlhmColumn::new(3.1 * k as f32 + 1.1, 0.55, 0.25, ceiling)
            })
            .collect();
        map.set_cell(0, 0, &columns).unwrap();
        map.set_cell(5, 0, &[MlhmColumn::new(80000.3, 0.0, 0.0, f32::INFINITY)]).unwrap();
        let exact = MlhmHierarchy::build(&map);
        let half = MlhmHierarchy::build_with_precision(&map, Precision::F16);
        assert_eq!((exact.precision(), half.precision()), (Precision::F32, Precision::F16));
        for level in 1..=exact.level_count() {
            let (nodes_x, nodes_y) = exact.nodes(level);
            assert_eq!(half.nodes(level), (nodes_x, nodes_y));
            for x in 0..nodes_x {
                let n = exact.layer_count(level, x, 0);
                assert_eq!(half.layer_count(level, x, 0), n);
                for k in 0..n {
                    let (e, h) =
                        (exact.node_layer(level, x, 0, k), half.node_layer(level, x, 0, k));
                    let expected = StoredLayer::<f16>::store(e).load();
                    assert_eq!(h, expected, "level {level} node {x} layer {k}");
                }
                let sky = exact.sky_min(level, x, 0);
                assert_eq!(half.sky_min(level, x, 0), f16::lower(sky).to_f32());
            }
        }
        // Beyond f16's range: +inf from above; the tops stay exact.
        assert_eq!(half.node_layer(1, 2, 0, 0).solid_max, f32::INFINITY);
        assert_eq!(half.top(MlhmMode::Solids), 80000.3f32 as f64);
        assert_eq!(half.top(MlhmMode::SolidsWater), exact.top(MlhmMode::SolidsWater));
        // Node layers take 8 bytes instead of 16, the sky 2 instead of 4; counts stay.
        let nodes: usize = (1..=exact.level_count()).map(|l| exact.nodes(l).0).sum();
        let slots: usize =
            (1..=exact.level_count()).map(|l| exact.nodes(l).0 * exact.layer_cap(l)).sum();
        assert_eq!(exact.memory_bytes(), nodes * 5 + slots * 16);
        assert_eq!(half.memory_bytes(), nodes * 3 + slots * 8);
        // Rebuilding in place keeps the precision.
        let mut rebuilt =
            MlhmHierarchy::build_with_precision(&Mlhm::new(64, 1, 8, 1.0).unwrap(), Precision::F16);
        rebuilt.rebuild(&map);
        assert_eq!(rebuilt, half);
    }

    #[test]
    fn level_counts_follow_the_reference() {
        assert_eq!(MlhmHierarchy::level_count_for(1, 1), 1);
        assert_eq!(MlhmHierarchy::level_count_for(4, 2), 1);
        assert_eq!(MlhmHierarchy::level_count_for(5, 1), 2);
        assert_eq!(MlhmHierarchy::level_count_for(40, 37), 5);
        assert_eq!(MlhmHierarchy::level_count_for(256, 256), 7);
        assert_eq!(MlhmHierarchy::level_count_for(1 << 20, 3), 11);
    }

    #[test]
    fn caps_halve_at_odd_levels_and_fold_the_excess() {
        let mut map = Mlhm::new(64, 1, 8, 1.0).unwrap();
        let columns: Vec<MlhmColumn> = (0..8)
            .map(|k| {
                let ceiling = if k == 7 { f32::INFINITY } else { 3.0 * k as f32 + 2.0 };
                MlhmColumn::new(3.0 * k as f32 + 1.0, 0.5, 0.25, ceiling)
            })
            .collect();
        map.set_cell(0, 0, &columns).unwrap();
        let h = MlhmHierarchy::build(&map);
        let caps: Vec<usize> = (1..=h.level_count()).map(|i| h.layer_cap(i)).collect();
        assert_eq!(caps, vec![4, 4, 2, 2, 1]);
        assert_eq!(h.layer_count(1, 0, 0), 4);
        // Layer 3 of level 1 holds columns 3..8: the top of column 7, the ceiling of 3.
        let top = h.node_layer(1, 0, 0, 3);
        assert_eq!((top.solid_max, top.water_max), (22.5, 22.75));
        assert_eq!((top.ceiling_min, top.air_min), (11.0, 10.75));
        // The open sky begins lowest over the flat cell (1, 0) beside it.
        assert_eq!(h.sky_min(1, 0, 0), 0.0);
        assert_eq!(h.layer_count(5, 0, 0), 1);
        assert_eq!(h.node_layer(5, 0, 0, 0).water_max, 22.75);
        // The neighbour node holds flat ground only.
        assert_eq!(h.layer_count(1, 1, 0), 1);
        assert_eq!(h.top(MlhmMode::SolidsWater), 22.75);
    }
}
