//! The MLHM's 2D hierarchy of conservative column bounds (Nilles & Müller 2025, section 4.2):
//! its levels, layer caps and folding, and its parallel bottom-up build.

use crate::MlhmMode;
use rayon::prelude::*;
use relief_core::Mlhm;

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

/// One level of the hierarchy above the cells.
#[derive(Debug, Clone, PartialEq)]
struct Level {
    nodes_x: usize,
    nodes_y: usize,
    /// Layers kept per node at this level.
    cap: usize,
    /// Per node, how many of its `cap` layer slots hold bounds.
    counts: Vec<u8>,
    /// Per node, `cap` layer slots, node-major (node `i`'s layers at `i * cap..`).
    layers: Vec<MlhmNodeLayer>,
    /// Per node, the lowest water top of the topmost column of any cell it covers.
    sky: Vec<f32>,
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
/// Every bound is exact f32 (maxima and minima of the map's own f32 sums), so each node
/// layer's interval in each [`MlhmMode`] contains every child interval it stands for, and a
/// ray that misses all of a node's intervals misses every box of its cells.
///
/// The build runs bottom-up, each level's rows in parallel (rayon); it is cheap enough to
/// redo every frame of a simulation.
///
/// ```
/// use relief_core::{Mlhm, MlhmColumn};
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
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MlhmHierarchy {
    width: usize,
    height: usize,
    levels: Vec<Level>,
    solid_max: f32,
    water_max: f32,
}

/// Largest number of levels above the cells.
pub const MAX_HIERARCHY_LEVELS: usize = 11;

impl MlhmHierarchy {
    /// Builds the hierarchy of `map`.
    pub fn build(map: &Mlhm) -> Self {
        let (width, height) = (map.width(), map.height());
        let levels = Self::level_shapes(map)
            .map(|(nodes_x, nodes_y, cap)| Level::empty(nodes_x, nodes_y, cap))
            .collect();
        let mut hierarchy = MlhmHierarchy {
            width,
            height,
            levels,
            solid_max: f32::NEG_INFINITY,
            water_max: f32::NEG_INFINITY,
        };
        hierarchy.fill(map);
        hierarchy
    }

    /// Rebuilds the hierarchy from `map` (say, after a simulation step), reusing its storage
    /// when the map's grid and layer count are those it was built for.
    pub fn rebuild(&mut self, map: &Mlhm) {
        let same = (self.width, self.height) == (map.width(), map.height())
            && Self::level_shapes(map)
                .zip(&self.levels)
                .all(|((nx, ny, cap), l)| (nx, ny, cap) == (l.nodes_x, l.nodes_y, l.cap));
        if same {
            self.fill(map);
        } else {
            *self = Self::build(map);
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

    /// Computes every level's bounds from `map`, bottom-up, into storage of the right shape.
    fn fill(&mut self, map: &Mlhm) {
        Self::fill_first(&mut self.levels[0], map);
        for i in 1..self.levels.len() {
            let (below, above) = self.levels.split_at_mut(i);
            Self::fill_above(&mut above[0], &below[i - 1]);
        }
        let top = self.levels.last().expect("at least one level");
        let mut solid_max = f32::NEG_INFINITY;
        let mut water_max = f32::NEG_INFINITY;
        for l in &top.layers {
            solid_max = solid_max.max(l.solid_max);
            water_max = water_max.max(l.water_max);
        }
        (self.solid_max, self.water_max) = (solid_max, water_max);
    }

    /// Number of levels above the cells for a grid of `width x height` cells:
    /// `clamp(ceil(log2(max(W, H))) - 1, 1, 11)`.
    pub fn level_count_for(width: usize, height: usize) -> usize {
        let n = width.max(height).max(1);
        let ceil_log2 = (usize::BITS - (n - 1).leading_zeros()) as usize;
        ceil_log2.saturating_sub(1).clamp(1, MAX_HIERARCHY_LEVELS)
    }

    /// Level 1, from the map's cells.
    fn fill_first(level: &mut Level, map: &Mlhm) {
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
        Self::merge_children(level, (w, h), count, layer, sky);
    }

    /// The level above `below`, merging its 2 x 2 nodes.
    fn fill_above(level: &mut Level, below: &Level) {
        let count = |child: usize| usize::from(below.counts[child]);
        let layer = |child: usize, j: usize| below.layers[child * below.cap + j];
        let sky = |child: usize| below.sky[child];
        Self::merge_children(level, (below.nodes_x, below.nodes_y), count, layer, sky);
    }

    /// Fills every node of `level` from its (up to) 2 x 2 children in a grid of `children`
    /// (x, y): a child has `count(child)` layers, bottom to top, bounded by `layer(child, j)`,
    /// and its open sky starts at `sky(child)`. Layers past the level's cap fold into its top
    /// kept layer.
    fn merge_children(
        level: &mut Level,
        children: (usize, usize),
        count: impl Fn(usize) -> usize + Sync,
        layer: impl Fn(usize, usize) -> MlhmNodeLayer + Sync,
        sky: impl Fn(usize) -> f32 + Sync,
    ) {
        let (nodes_x, cap) = (level.nodes_x, level.cap);
        let (children_x, children_y) = children;
        level
            .layers
            .par_chunks_mut(nodes_x * cap)
            .zip(level.counts.par_chunks_mut(nodes_x))
            .zip(level.sky.par_chunks_mut(nodes_x))
            .enumerate()
            .for_each(|(ny, ((layers, node_counts), node_sky))| {
                for nx in 0..nodes_x {
                    let slots = &mut layers[nx * cap..(nx + 1) * cap];
                    slots.fill(MlhmNodeLayer::EMPTY);
                    node_sky[nx] = f32::INFINITY;
                    let mut used = 0;
                    for y in 2 * ny..(2 * ny + 2).min(children_y) {
                        for x in 2 * nx..(2 * nx + 2).min(children_x) {
                            let child = x + y * children_x;
                            let n = count(child);
                            for j in 0..n {
                                let k = j.min(cap - 1);
                                slots[k] = slots[k].merge(layer(child, j));
                            }
                            node_sky[nx] = node_sky[nx].min(sky(child));
                            used = used.max(n.min(cap));
                        }
                    }
                    node_counts[nx] = used as u8;
                }
            });
    }

    /// Cells along x and y of the map it was built from.
    pub fn cells(&self) -> (usize, usize) {
        (self.width, self.height)
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

    /// The bounds of layer `k` of node `(x, y)` of `level`.
    ///
    /// # Panics
    /// Also when `k >= layer_count(level, x, y)`.
    pub fn node_layer(&self, level: usize, x: usize, y: usize, k: usize) -> MlhmNodeLayer {
        let n = self.layer_count(level, x, y);
        assert!(k < n, "layer {k} of node ({x}, {y}) of level {level}, which has {n}");
        let l = self.level(level);
        l.layers[(x + y * l.nodes_x) * l.cap + k]
    }

    /// The lowest water top of the topmost column of any cell under node `(x, y)` of `level`:
    /// where the open sky above the node begins at the lowest.
    pub fn sky_min(&self, level: usize, x: usize, y: usize) -> f32 {
        let _ = self.layer_count(level, x, y);
        let l = self.level(level);
        l.sky[x + y * l.nodes_x]
    }

    /// Highest box top over the map in `mode` (`+inf` for [`MlhmMode::SolidsAir`]).
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
        mut f: impl FnMut(f64, f64) -> bool,
    ) -> bool {
        let l = &self.levels[level - 1];
        let node = x + y * l.nodes_x;
        let n = usize::from(l.counts[node]);
        let layers = &l.layers[node * l.cap..][..n];
        let mut below: Option<&MlhmNodeLayer> = None;
        for layer in layers {
            let (bottom, top) = match mode {
                MlhmMode::Solids => {
                    (below.map_or(f32::NEG_INFINITY, |b| b.ceiling_min), layer.solid_max)
                }
                MlhmMode::SolidsWater => {
                    (below.map_or(f32::NEG_INFINITY, |b| b.ceiling_min), layer.water_max)
                }
                MlhmMode::SolidsAir => {
                    (below.map_or(f32::NEG_INFINITY, |b| b.air_min), layer.solid_max)
                }
            };
            if f(bottom as f64, top as f64) {
                return true;
            }
            below = Some(layer);
        }
        mode == MlhmMode::SolidsAir && f(l.sky[node] as f64, f64::INFINITY)
    }
}

impl Level {
    fn empty(nodes_x: usize, nodes_y: usize, cap: usize) -> Level {
        Level {
            nodes_x,
            nodes_y,
            cap,
            counts: vec![0; nodes_x * nodes_y],
            layers: vec![MlhmNodeLayer::EMPTY; nodes_x * nodes_y * cap],
            sky: vec![f32::INFINITY; nodes_x * nodes_y],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::MlhmColumn;

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
