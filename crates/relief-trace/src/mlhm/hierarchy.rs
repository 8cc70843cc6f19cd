//! The MLHM's 2D hierarchy of conservative column bounds (Nilles & Müller 2025, section 4.2):
//! its levels and layer caps, its bounds stored as exact f32 or as f16 rounded outward, and
//! their access; its parallel bottom-up build is in [`super::build`].

use super::bounds::{BoundScalar, StoredBounds};
use super::node_layer::MlhmNodeLayer;
use crate::MlhmMode;
use relief_core::Precision;

/// One level of the hierarchy above the cells.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Level {
    pub(super) nodes_x: usize,
    pub(super) nodes_y: usize,
    /// Layers kept per node at this level.
    pub(super) cap: usize,
    /// Per node, how many of its `cap` layer slots hold bounds.
    pub(super) counts: Vec<u8>,
    /// Per node, its layers' bounds and where its open sky begins.
    pub(super) bounds: StoredBounds,
}

/// A hierarchy of conservative bounds over an [`Mlhm`](relief_core::Mlhm)'s cells, for the
/// hierarchical box traversal ([`crate::MlhmHierarchyTracer`]).
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
/// own [`Mlhm::precision`](relief_core::Mlhm::precision)), and the scene top
/// ([`MlhmHierarchy::top`]) is exact at both.
///
/// For the smooth implicit surface, [`build_padded`](MlhmHierarchy::build_padded) widens
/// level 1 by the smoothing radius, so that the same intervals enclose every point the smooth
/// surface can reach.
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
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) precision: Precision,
    pub(super) levels: Vec<Level>,
    /// Exact highest solid top over the map.
    pub(super) solid_max: f32,
    /// Exact highest water top over the map.
    pub(super) water_max: f32,
    /// The smoothing radius level 1 is padded by, metres (0: the box hierarchy).
    pub(super) padding: f64,
}

/// Largest number of levels above the cells.
pub const MAX_HIERARCHY_LEVELS: usize = 11;

impl MlhmHierarchy {
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

    /// The smoothing radius level 1 is padded by, metres
    /// ([`build_padded`](MlhmHierarchy::build_padded)); 0 for the box hierarchy
    /// ([`build`](MlhmHierarchy::build),
    /// [`build_with_precision`](MlhmHierarchy::build_with_precision)).
    pub fn padding(&self) -> f64 {
        self.padding
    }

    /// Highest box top over the map in `mode` (`+inf` for [`MlhmMode::SolidsAir`]); exact at
    /// either precision, and on a padded hierarchy
    /// ([`build_padded`](MlhmHierarchy::build_padded)) raised by the padding, rounded up to an
    /// f32.
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

#[cfg(test)]
mod tests {
    use super::super::bounds::StoredLayer;
    use super::*;
    use half::f16;
    use relief_core::{Mlhm, MlhmColumn};

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
}
