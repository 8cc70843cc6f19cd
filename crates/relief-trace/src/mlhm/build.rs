//! The build of an [`MlhmHierarchy`] (Nilles & Müller 2025, section 4.2): the shape of its
//! levels, each level merged from the 2 x 2 nodes below it (level 1 from the cells, padded by
//! a ring of cells for the smooth surface), bottom-up and each level's rows in parallel, with
//! layers past a level's cap folded.

use super::bounds::{pad_down, BoundScalar, LevelBounds, MergedLayer, StoredBounds, StoredLayer};
use super::hierarchy::{Level, MAX_HIERARCHY_LEVELS};
use super::node_layer::MlhmNodeLayer;
use super::single_layer_merge::{merge_one_column_cells, merge_single_layer_row, SingleSlotLevel};
use crate::MlhmHierarchy;
use rayon::prelude::*;
use relief_core::{Mlhm, Precision};

impl MlhmHierarchy {
    /// Builds the hierarchy of `map` with exact f32 bounds ([`Precision::F32`]).
    pub fn build(map: &Mlhm) -> Self {
        Self::build_with_precision(map, Precision::F32)
    }

    /// Builds the hierarchy of `map` with its bounds stored at `precision`: exact f32, or f16
    /// rounded outward (see [`MlhmHierarchy`]).
    pub fn build_with_precision(map: &Mlhm, precision: Precision) -> Self {
        Self::build_inner(map, precision, 0.0)
    }

    /// Builds the hierarchy of `map` for the smooth implicit surface of smoothing radius
    /// `radius` (σ, metres: the half-size of the cube whose terrain volume defines the
    /// surface; Nilles & Müller 2025, 3.3 and 4.3), with its bounds stored at `precision`.
    ///
    /// Every point whose cube holds terrain lies within `radius`, along every axis, of some
    /// terrain box, so level 1 is built wider than for the boxes: layer `k` of a level-1 node
    /// merges layer `k` of its 2 x 2 cells and of a ring of `ceil(radius / cell size)` cells
    /// around them (clipped to the grid), and then every maximum (`water_max`, `solid_max`)
    /// is raised by `radius` and every minimum (`ceiling_min`, `air_min` and the sky's start,
    /// [`sky_min`](MlhmHierarchy::sky_min)) lowered by it. The padding is computed in f64 and
    /// rounded outward to f32 (maxima up, minima down), and at [`Precision::F16`] then to f16,
    /// outward again. Layers beyond a cap fold as in [`build`](MlhmHierarchy::build), the
    /// levels above take the plain maxima and minima of their 2 x 2 children, and the scene
    /// tops ([`top`](MlhmHierarchy::top)) are raised by `radius` too. Everything else reads
    /// as on a box hierarchy; [`rebuild`](MlhmHierarchy::rebuild) keeps the padding.
    ///
    /// The bounds cover the grid's footprint only: the smooth surface also reaches up to
    /// `radius` beyond the grid's edges, which no node stands for.
    ///
    /// A `radius` of 0 gives the box hierarchy, as
    /// [`build_with_precision`](MlhmHierarchy::build_with_precision) builds it.
    ///
    /// # Panics
    /// When `radius` is negative, infinite or NaN.
    ///
    /// ```
    /// use relief_core::{Mlhm, MlhmColumn, Precision};
    /// use relief_trace::{MlhmHierarchy, MlhmMode};
    /// let mut map = Mlhm::new(8, 8, 2, 1.0)?;
    /// map.set_cell(2, 0, &[MlhmColumn::new(3.0, 0.0, 0.5, f32::INFINITY)])?;
    /// let padded = MlhmHierarchy::build_padded(&map, 0.5, Precision::F32);
    /// assert_eq!(padded.padding(), 0.5);
    /// // Node (0, 0) of level 1 (cells 0..2) takes in cell 2, one ring cell away.
    /// let layer = padded.node_layer(1, 0, 0, 0);
    /// assert_eq!((layer.solid_max, layer.water_max), (3.5, 4.0));
    /// assert_eq!(padded.sky_min(1, 0, 0), -0.5);
    /// assert_eq!(padded.top(MlhmMode::Solids), 3.5);
    /// // Node (2, 0) (cells 4..6) is two cells away: flat ground, padded.
    /// assert_eq!(padded.node_layer(1, 2, 0, 0).solid_max, 0.5);
    /// # Ok::<(), relief_core::CoreError>(())
    /// ```
    pub fn build_padded(map: &Mlhm, radius: f64, precision: Precision) -> Self {
        assert!(
            radius.is_finite() && radius >= 0.0,
            "smoothing radius {radius} is not finite and >= 0"
        );
        Self::build_inner(map, precision, radius)
    }

    /// The hierarchy of `map` at `precision`, level 1 padded by `padding` metres.
    fn build_inner(map: &Mlhm, precision: Precision, padding: f64) -> Self {
        let (width, height) = (map.width(), map.height());
        let largest = largest_layer_count(map.layer_counts());
        let levels = Self::level_shapes(map, largest)
            .map(|(nodes_x, nodes_y, cap)| Level::empty(nodes_x, nodes_y, cap, precision))
            .collect();
        let mut hierarchy = MlhmHierarchy {
            width,
            height,
            precision,
            levels,
            solid_max: f32::NEG_INFINITY,
            water_max: f32::NEG_INFINITY,
            padding,
        };
        hierarchy.fill(map, largest, Merge::Fast);
        hierarchy
    }

    /// Rebuilds the hierarchy from `map` (say, after a simulation step) at its precision and
    /// with its [`padding`](MlhmHierarchy::padding), reusing its storage when the map's grid and layer count are those it was built for.
    pub fn rebuild(&mut self, map: &Mlhm) {
        let largest = largest_layer_count(map.layer_counts());
        let same = (self.width, self.height) == (map.width(), map.height())
            && Self::level_shapes(map, largest)
                .zip(&self.levels)
                .all(|((nx, ny, cap), l)| (nx, ny, cap) == (l.nodes_x, l.nodes_y, l.cap));
        if same {
            self.fill(map, largest, Merge::Fast);
        } else {
            *self = Self::build_inner(map, self.precision, self.padding);
        }
    }

    /// Nodes along x and y and the layer cap of each level, from level 1 up, for a map whose
    /// fullest cell holds `largest` columns.
    ///
    /// The caps halve from the map's layer capacity (see [`MlhmHierarchy`]); no node of a
    /// level holds more layers than the fullest cell under it, so a level stores at most
    /// `largest` slots a node. The bounds are those of the halved caps, in less memory: a map
    /// of one column per cell (a height field, a scene before its first split) stores one
    /// slot a node, and its rebuild writes half the bytes of one with two.
    fn level_shapes(map: &Mlhm, largest: usize) -> impl Iterator<Item = (usize, usize, usize)> {
        let (width, height) = (map.width(), map.height());
        let count = Self::level_count_for(width, height);
        let mut cap = map.max_layers().max(1);
        let largest = largest.max(1);
        (1..=count).map(move |i| {
            if i % 2 == 1 {
                cap = cap.div_ceil(2);
            }
            (width.div_ceil(1 << i), height.div_ceil(1 << i), cap.min(largest))
        })
    }

    /// Computes every level's bounds from `map`, bottom-up, into storage of the right shape,
    /// and the exact tops of the map (on a padded hierarchy the padded tops, rounded up to
    /// f32): from level 1's bounds before they are rounded to f16, or from the top level's
    /// f32 bounds.
    fn fill(&mut self, map: &Mlhm, largest: usize, merge: Merge) {
        // A map of one column a cell at f32: levels 1 and 2 in one pass.
        let one_column = merge == Merge::Fast
            && self.padding == 0.0
            && largest == 1
            && self.precision == Precision::F32;
        let (rounded_tops, next) = if one_column {
            let (first, rest) = self.levels.split_first_mut().expect("at least one level");
            let second = rest.first_mut().map(Level::single_slot);
            let next = if second.is_some() { 2 } else { 1 };
            merge_one_column_cells(first.single_slot(), second, map);
            (None, next)
        } else {
            (Self::fill_first(&mut self.levels[0], map, self.padding), 1)
        };
        for i in next..self.levels.len() {
            let (below, above) = self.levels.split_at_mut(i);
            Self::fill_above(&mut above[0], &below[i - 1], merge);
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

    /// Level 1, from the map's cells, padded by `padding` metres (see
    /// [`build_padded`](MlhmHierarchy::build_padded)); returns the highest solid and water
    /// tops (padded, rounded up) when the stored bounds are rounded or padded.
    fn fill_first(level: &mut Level, map: &Mlhm, padding: f64) -> Option<(f32, f32)> {
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
        let children = Children::padded(w, h, padding, map.cell_size());
        match &mut level.bounds {
            StoredBounds::F32(b) if padding == 0.0 => {
                // Stored as they are: merged in place.
                let layer = |cell: usize, j: usize| StoredLayer::<f32>::store(layer(cell, j));
                Self::merge_children(b, counts, nodes_x, cap, children, count, layer, sky)
            }
            // Padded exactly, then rounded outward to f32 (and returning the padded tops).
            StoredBounds::F32(b) => {
                Self::merge_children(b, counts, nodes_x, cap, children, count, layer, sky)
            }
            StoredBounds::F16(b) => {
                Self::merge_children(b, counts, nodes_x, cap, children, count, layer, sky)
            }
        }
    }

    /// The level above `below`, merging its 2 x 2 nodes.
    fn fill_above(level: &mut Level, below: &Level, merge: Merge) {
        let count = |child: usize| usize::from(below.counts[child]);
        let children = Children::plain(below.nodes_x, below.nodes_y);
        let (nodes_x, cap, below_cap) = (level.nodes_x, level.cap, below.cap);
        let counts = &mut level.counts;
        match (&mut level.bounds, &below.bounds) {
            (StoredBounds::F32(b), StoredBounds::F32(c))
                if merge == Merge::Fast && counts_all_one(&below.counts) =>
            {
                let children = (c, below_cap, below.nodes_x, below.nodes_y);
                Self::merge_single_layers(b, counts, (nodes_x, cap), children);
            }
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

    /// A level at exact f32 bounds whose children all hold one layer (a level above one whose
    /// nodes hold one layer each): each node the merge of its (up to) 2 x 2 children (`below`,
    /// `below_cap` slots a node, in a grid of `children_x` by `children_y`) by
    /// [`merge_single_layer_row`], rows in parallel. This is what a simulation pays every
    /// frame: the 4096² RiversRain rebuild took 58 to 98 ms with this merge against 257 to
    /// 454 ms with the general merge alone, run beside each other
    /// (`examples/hierarchy_rebuild.rs`).
    fn merge_single_layers(
        bounds: &mut LevelBounds<f32>,
        counts: &mut [u8],
        (nodes_x, cap): (usize, usize),
        (below, below_cap, children_x, children_y): (&LevelBounds<f32>, usize, usize, usize),
    ) {
        let row = |y: usize| {
            let y = y.min(children_y - 1) * children_x;
            (
                &below.layers[y * below_cap..(y + children_x) * below_cap],
                &below.sky[y..y + children_x],
            )
        };
        bounds
            .layers
            .par_chunks_mut(nodes_x * cap)
            .zip(counts.par_chunks_mut(nodes_x))
            .zip(bounds.sky.par_chunks_mut(nodes_x))
            .enumerate()
            .for_each(|(ny, ((layers, node_counts), node_sky))| {
                node_counts.fill(1);
                let (low, high) = (row(2 * ny), row(2 * ny + 1));
                merge_single_layer_row(layers, node_sky, cap, low, high, below_cap);
            });
    }

    /// Fills every node of a level (`nodes_x` nodes a row, `cap` layers a node; `bounds` and
    /// `counts` its storage) from its (up to) 2 x 2 children in a grid of `children`, and the
    /// ring of children around them and the padding `children` asks for: a child has `count(child)` layers, bottom to top, bounded by `layer(child, j)`, and its
    /// open sky starts at `sky(child)`. Layers past the level's cap fold into its top kept
    /// layer. Merges exactly, as `L`, and stores each bound rounded outward; returns the
    /// highest solid and water tops merged when `L` knows them exactly before rounding.
    #[allow(clippy::too_many_arguments)]
    fn merge_children<S: BoundScalar, L: MergedLayer<S>>(
        bounds: &mut LevelBounds<S>,
        counts: &mut [u8],
        nodes_x: usize,
        cap: usize,
        children: Children,
        count: impl Fn(usize) -> usize + Sync,
        layer: impl Fn(usize, usize) -> L + Sync,
        sky: impl Fn(usize) -> f32 + Sync,
    ) -> Option<(f32, f32)> {
        let Children { x: children_x, y: children_y, ring, padding } = children;
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
                        let lowest_sky = &mut lowest_sky[nx];
                        // The common case, fast: four children of one layer each, no ring.
                        let first = 2 * nx + 2 * ny * children_x;
                        let (c0, c1, c2, c3) =
                            (first, first + 1, first + children_x, first + children_x + 1);
                        if ring == 0
                            && 2 * nx + 1 < children_x
                            && 2 * ny + 1 < children_y
                            && count(c0) == 1
                            && count(c1) == 1
                            && count(c2) == 1
                            && count(c3) == 1
                        {
                            let (a, b) = (layer(c0, 0).merge(layer(c1, 0)), layer(c2, 0));
                            merged[0] = a.merge(b.merge(layer(c3, 0)));
                            merged[1..].fill(L::EMPTY);
                            let (a, b) = (sky(c0).min(sky(c1)), sky(c2).min(sky(c3)));
                            *lowest_sky = a.min(b);
                            node_counts[nx] = 1;
                            continue;
                        }
                        merged.fill(L::EMPTY);
                        let mut used = 0;
                        let ys = (2 * ny).saturating_sub(ring)..(2 * ny + 2 + ring).min(children_y);
                        for y in ys {
                            let xs =
                                (2 * nx).saturating_sub(ring)..(2 * nx + 2 + ring).min(children_x);
                            for x in xs {
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
                        if padding > 0.0 {
                            for m in merged {
                                *m = m.padded(padding);
                            }
                            *lowest_sky = pad_down(*lowest_sky, padding);
                        }
                    }
                });
                S::store_lower(&lowest_sky, node_sky);
                tops
            })
            .reduce(|| None, max_pair)
    }
}

/// Which merges a build may use: the fast one where every child holds one layer
/// ([`MlhmHierarchy::merge_single_layers`]), or (for the tests that compare the two) only the
/// general one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Merge {
    Fast,
    #[cfg(test)]
    General,
}

/// The most columns (or layers) any cell (or node) of `counts` holds.
fn largest_layer_count(counts: &[u8]) -> usize {
    counts
        .par_chunks(1 << 16)
        .map(|chunk| chunk.iter().copied().max().unwrap_or(0))
        .max()
        .map_or(0, usize::from)
}

/// Whether every cell holds exactly one column.
fn counts_all_one(counts: &[u8]) -> bool {
    /// Eight counts of 1.
    const ONES: u64 = 0x0101_0101_0101_0101;
    counts.par_chunks(1 << 16).all(|chunk| {
        let mut words = chunk.chunks_exact(8);
        words.all(|w| u64::from_ne_bytes(w.try_into().expect("8 bytes")) == ONES)
            && words.remainder().iter().all(|&c| c == 1)
    })
}

/// The grid of children a level's nodes merge, and for level 1 of a padded hierarchy the
/// ring of extra children each node takes in and the padding of its bounds.
#[derive(Debug, Clone, Copy)]
struct Children {
    /// Children along x.
    x: usize,
    /// Children along y.
    y: usize,
    /// Extra children merged on each side of a node's 2 x 2.
    ring: usize,
    /// Metres every merged maximum is raised and minimum lowered by.
    padding: f64,
}

impl Children {
    /// A grid of `x` by `y` children, merged 2 x 2.
    fn plain(x: usize, y: usize) -> Self {
        Children { x, y, ring: 0, padding: 0.0 }
    }

    /// A grid of `x` by `y` cells of `cell_size` metres, padded by `padding` metres: the ring
    /// is the fewest cells at least `padding` wide, `ceil(padding / cell_size)`, checked in
    /// f64 so rounding in the division cannot shrink it (and at most the grid).
    fn padded(x: usize, y: usize, padding: f64, cell_size: f64) -> Self {
        if padding == 0.0 {
            return Self::plain(x, y);
        }
        let most = x.max(y);
        let mut ring = (padding / cell_size).ceil().min(most as f64) as usize;
        if ring < most && (ring as f64) * cell_size < padding {
            ring += 1;
        }
        Children { x, y, ring, padding }
    }
}

impl Level {
    /// This level's storage as [`merge_one_column_cells`] writes it.
    fn single_slot(&mut self) -> SingleSlotLevel<'_> {
        let StoredBounds::F32(bounds) = &mut self.bounds else {
            unreachable!("a one-column merge writes f32 bounds")
        };
        (bounds, &mut self.counts[..], self.nodes_x)
    }

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
    use crate::MlhmMode;
    use relief_core::MlhmColumn;

    #[test]
    fn the_fast_merge_of_one_column_cells_equals_the_general_merge() {
        // Odd and even sides, one-cell grids, a ceiling of -0 and equal heights included.
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        for (w, h) in [(1, 1), (2, 1), (1, 3), (5, 4), (8, 8), (33, 17), (64, 65)] {
            let mut map = Mlhm::new(w, h, 2, 0.5).unwrap();
            for y in 0..h {
                for x in 0..w {
                    let bedrock = (next() * 8.0).round() - 3.0;
                    let column = MlhmColumn::new(bedrock, next(), next() * 0.5, f32::INFINITY);
                    map.set_cell(x, y, &[column]).unwrap();
                }
            }
            let fast = MlhmHierarchy::build(&map);
            let mut general = MlhmHierarchy::build(&map);
            general.fill(&map, largest_layer_count(map.layer_counts()), Merge::General);
            assert_eq!(fast, general, "{w} x {h}");
            // Rebuilt after a change, in place.
            map.set_cell(0, h - 1, &[MlhmColumn::new(40.0, 1.0, 2.0, f32::INFINITY)]).unwrap();
            let mut rebuilt = fast.clone();
            rebuilt.rebuild(&map);
            general.fill(&map, largest_layer_count(map.layer_counts()), Merge::General);
            assert_eq!(rebuilt, general, "{w} x {h}, rebuilt");
            // Cells of two columns: level 1 merges them generally into one layer (its cap),
            // with the lower column's ceiling, and the levels above merge those fast.
            for y in (0..h).step_by(2) {
                let bedrock = next() * 4.0;
                let lower = MlhmColumn::new(bedrock, 0.1, 0.0, bedrock + 1.0 + next());
                map.set_cell(
                    w / 2,
                    y,
                    &[lower, MlhmColumn::new(bedrock + 3.0, 0.2, 0.1, f32::INFINITY)],
                )
                .unwrap();
            }
            rebuilt.rebuild(&map);
            general.fill(&map, largest_layer_count(map.layer_counts()), Merge::General);
            assert_eq!(rebuilt, general, "{w} x {h}, two columns");
        }
    }

    #[test]
    fn a_level_stores_no_more_slots_than_its_fullest_node_needs() {
        // Capacity 8 (caps 4, 4, 2, 2, 1), every cell one column: one slot a node.
        let mut map = Mlhm::new(64, 64, 8, 1.0).unwrap();
        let one_column = MlhmHierarchy::build(&map);
        let caps = |h: &MlhmHierarchy| -> Vec<usize> {
            (1..=h.level_count()).map(|i| h.layer_cap(i)).collect()
        };
        assert_eq!(caps(&one_column), vec![1; 5]);
        // Three columns in one cell: the caps up to 3, and a rebuild equals a fresh build.
        let column = |b: f32, ceiling: f32| MlhmColumn::new(b, 0.5, 0.25, ceiling);
        map.set_cell(5, 9, &[column(1.0, 2.0), column(4.0, 5.0), column(7.0, f32::INFINITY)])
            .unwrap();
        let mut rebuilt = one_column.clone();
        rebuilt.rebuild(&map);
        assert_eq!(rebuilt, MlhmHierarchy::build(&map));
        assert_eq!(caps(&rebuilt), vec![3, 3, 2, 2, 1]);
        assert_eq!(rebuilt.layer_count(1, 2, 4), 3);
        assert_eq!(rebuilt.node_layer(1, 2, 4, 2).solid_max, 7.5);
        // Back to one column everywhere: one slot again.
        map.set_cell(5, 9, &[column(1.0, f32::INFINITY)]).unwrap();
        rebuilt.rebuild(&map);
        assert_eq!(rebuilt, MlhmHierarchy::build(&map));
        assert_eq!(caps(&rebuilt), vec![1; 5]);
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
