//! The build of an [`MlhmHierarchy`] (Nilles & Müller 2025, section 4.2): the shape of its
//! levels, each level merged from the 2 x 2 nodes below it (level 1 from the cells, padded by
//! a ring of cells for the smooth surface), bottom-up and each level's rows in parallel, with
//! layers past a level's cap folded.

use super::bounds::{pad_down, BoundScalar, LevelBounds, MergedLayer, StoredBounds, StoredLayer};
use super::hierarchy::{Level, MlhmNodeLayer, MAX_HIERARCHY_LEVELS};
use crate::MlhmHierarchy;
use rayon::prelude::*;
use relief_core::{Mlhm, MlhmColumn, Precision};

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

/// The stored f32 layer of merged lanes in the order of [`StoredLayer`]'s fields.
#[inline(always)]
fn stored([water_max, ceiling_min, solid_max, air_min]: [f32; 4]) -> StoredLayer<f32> {
    StoredLayer { water_max, ceiling_min, solid_max, air_min }
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

/// The merged bounds of four children's layers, each and the result in the order of
/// [`StoredLayer`]'s fields: water top, ceiling, solid top, start of air.
#[inline(always)]
fn merge_lanes(a: [f32; 4], b: [f32; 4], c: [f32; 4], d: [f32; 4]) -> [f32; 4] {
    let larger = |x: f32, y: f32| if x >= y { x } else { y };
    let smaller = |x: f32, y: f32| if x <= y { x } else { y };
    let (top, bottom) = (
        |i: usize| larger(larger(a[i], b[i]), larger(c[i], d[i])),
        |i: usize| smaller(smaller(a[i], b[i]), smaller(c[i], d[i])),
    );
    [top(0), bottom(1), top(2), bottom(3)]
}

/// [`merge_lanes`] of four one-column cells, whose layer's bounds are their water top,
/// ceiling, solid top and water top again. The water top is `(bedrock + sand) + water`, in
/// f32, as [`MlhmColumn::water_top`] computes it.
#[inline(always)]
fn merge_columns(cells: [MlhmColumn; 4]) -> [f32; 4] {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: SSE2 is part of x86_64; `MlhmColumn` is `repr(C)`, four f32.
        unsafe { merge_columns_sse2(&cells) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let lanes = |c: MlhmColumn| [c.water_top(), c.ceiling, c.solid_top(), c.water_top()];
        let [a, b, c, d] = cells;
        merge_lanes(lanes(a), lanes(b), lanes(c), lanes(d))
    }
}

/// [`merge_columns`] in SSE2: each column's four values in one register.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn merge_columns_sse2(cells: &[MlhmColumn; 4]) -> [f32; 4] {
    use std::arch::x86_64::*;
    // Lanes [water top, ceiling, solid top, water top] of a column [bedrock, sand, water,
    // ceiling]: ([b, c, b, b] + [s, 0, s, s]) + [w, 0, 0, w]. Adding zero keeps every value
    // but the sign of a zero ceiling, which compares equal.
    let keep =
        |mask: [i32; 4]| _mm_castsi128_ps(_mm_setr_epi32(mask[0], mask[1], mask[2], mask[3]));
    let (sand_mask, water_mask) = (keep([-1, 0, -1, -1]), keep([-1, 0, 0, -1]));
    let lanes = |c: &MlhmColumn| {
        let v = _mm_loadu_ps(std::ptr::from_ref(c).cast::<f32>());
        let base = _mm_shuffle_ps::<0b00_00_11_00>(v, v);
        let sand = _mm_and_ps(_mm_shuffle_ps::<0b01_01_01_01>(v, v), sand_mask);
        let water = _mm_and_ps(_mm_shuffle_ps::<0b10_10_10_10>(v, v), water_mask);
        _mm_add_ps(_mm_add_ps(base, sand), water)
    };
    let [a, b, c, d] = [&cells[0], &cells[1], &cells[2], &cells[3]].map(lanes);
    let top = _mm_max_ps(_mm_max_ps(a, b), _mm_max_ps(c, d));
    let bottom = _mm_min_ps(_mm_min_ps(a, b), _mm_min_ps(c, d));
    let maxima = keep([-1, 0, -1, 0]);
    let merged = _mm_or_ps(_mm_and_ps(maxima, top), _mm_andnot_ps(maxima, bottom));
    let mut out = [0f32; 4];
    _mm_storeu_ps(out.as_mut_ptr(), merged);
    out
}

/// A level at f32 with one slot a node: its bounds, its nodes' layer counts and its nodes
/// along x.
type SingleSlotLevel<'a> = (&'a mut LevelBounds<f32>, &'a mut [u8], usize);

/// Level 1 (one slot a node) of `map`, whose cells hold one column each, and with `second`
/// level 2 as well, in the same pass: each level-1 node the merge of its (up to) 2 x 2 cells
/// by [`merge_columns`] (an odd grid's last row or column merged with itself), its sky at the
/// merged start of air; each level-2 row by [`merge_single_layer_row`] from the two rows of
/// level 1 just written, still in cache. Rows of the top level in parallel. Where the CPU has
/// AVX2, two cells to a register, and blocks of 4 x 4 cells merged into both levels at once
/// ([`merge_column_blocks_avx2`]).
fn merge_one_column_cells(
    (first, first_counts, nodes_x): SingleSlotLevel,
    second: Option<SingleSlotLevel>,
    map: &Mlhm,
) {
    let (width, height) = (map.width(), map.height());
    #[cfg(target_arch = "x86_64")]
    let avx2 = std::is_x86_feature_detected!("avx2");
    let columns = &map.raw_columns()[..width * height];
    let row = |y: usize| &columns[y.min(height - 1) * width..][..width];
    // Level-1 row `ny` from node `start` on.
    let level_one_row = |ny: usize, nodes: &mut [StoredLayer<f32>], sky: &mut [f32], start| {
        let (low, high) = (row(2 * ny), row(2 * ny + 1));
        let mut done = start;
        #[cfg(target_arch = "x86_64")]
        if avx2 {
            let (nodes, sky) = (&mut nodes[start..], &mut sky[start..]);
            let (low, high) = (&low[2 * start..], &high[2 * start..]);
            // SAFETY: the CPU has AVX2 (checked above).
            done += unsafe { merge_column_pairs_avx2(low, high, nodes, sky) };
        }
        for nx in done..nodes.len() {
            let (x0, x1) = (2 * nx, (2 * nx + 1).min(width - 1));
            let merged = merge_columns([low[x0], low[x1], high[x0], high[x1]]);
            nodes[nx] = stored(merged);
            sky[nx] = merged[3];
        }
    };
    first_counts.fill(1);
    let Some((second, second_counts, second_x)) = second else {
        first
            .layers
            .par_chunks_mut(nodes_x)
            .zip(first.sky.par_chunks_mut(nodes_x))
            .enumerate()
            .for_each(|(ny, (nodes, sky))| level_one_row(ny, nodes, sky, 0));
        return;
    };
    second_counts.fill(1);
    let first_rows =
        first.layers.par_chunks_mut(2 * nodes_x).zip(first.sky.par_chunks_mut(2 * nodes_x));
    let second_rows =
        second.layers.par_chunks_mut(second_x).zip(second.sky.par_chunks_mut(second_x));
    first_rows.zip(second_rows).enumerate().for_each(|(ny, ((nodes, sky), (above, above_sky)))| {
        // Whole blocks of 4 x 4 cells first, both levels from registers; then the rest.
        let mut done = 0;
        #[cfg(target_arch = "x86_64")]
        if avx2 && 4 * ny + 3 < height && nodes.len() == 2 * nodes_x {
            let cells = [row(4 * ny), row(4 * ny + 1), row(4 * ny + 2), row(4 * ny + 3)];
            let (low, high) = nodes.split_at_mut(nodes_x);
            let (low_sky, high_sky) = sky.split_at_mut(nodes_x);
            let first = [(low, low_sky), (high, high_sky)];
            // SAFETY: the CPU has AVX2 (checked above).
            done = unsafe { merge_column_blocks_avx2(cells, first, (above, above_sky)) };
        }
        for (r, (nodes, sky)) in nodes.chunks_mut(nodes_x).zip(sky.chunks_mut(nodes_x)).enumerate()
        {
            level_one_row(2 * ny + r, nodes, sky, 2 * done);
        }
        // Level 2 from the one or two rows of level 1 just merged.
        let last = nodes.len() - nodes_x;
        let low = (&nodes[2 * done..nodes_x], &sky[2 * done..nodes_x]);
        let high = (&nodes[last + 2 * done..], &sky[last + 2 * done..]);
        merge_single_layer_row(&mut above[done..], &mut above_sky[done..], 1, low, high, 1);
    });
}

/// The level-1 and level-2 nodes of the blocks of 4 x 4 one-column cells of the four rows of
/// cells `cells` whose columns all exist (`4 nx + 3 < width`): each block's four level-1 nodes
/// as [`merge_column_pairs_avx2`] merges them, into the two rows `first` (nodes and skies),
/// and its level-2 node from those four still in registers, into `second`, as
/// [`merge_layer_pairs_avx2`] merges it; returns the level-2 nodes done. (Writing the level-1
/// nodes past the cache with streaming stores made the 4096² rebuild three times slower.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn merge_column_blocks_avx2(
    cells: [&[MlhmColumn]; 4],
    first: [(&mut [StoredLayer<f32>], &mut [f32]); 2],
    (second, second_sky): (&mut [StoredLayer<f32>], &mut [f32]),
) -> usize {
    use std::arch::x86_64::*;
    let width = cells.iter().map(|r| r.len()).min().unwrap_or(0);
    let first_x = first.iter().map(|(n, s)| n.len().min(s.len())).min().unwrap_or(0);
    let blocks = (width / 4).min(first_x / 2).min(second.len()).min(second_sky.len());
    let node = |low: &[MlhmColumn], high: &[MlhmColumn], x: usize| {
        column_pair_node(&low[x..x + 2], &high[x..x + 2])
    };
    let [(low, low_sky), (high, high_sky)] = first;
    let put = |out: &mut [StoredLayer<f32>], sky: &mut [f32], i: usize, v: __m128| {
        let lanes = lanes_of(v);
        out[i] = stored(lanes);
        sky[i] = lanes[3];
    };
    for nx in 0..blocks {
        let x = 4 * nx;
        let a = node(cells[0], cells[1], x);
        let b = node(cells[0], cells[1], x + 2);
        let c = node(cells[2], cells[3], x);
        let d = node(cells[2], cells[3], x + 2);
        put(low, low_sky, 2 * nx, a);
        put(low, low_sky, 2 * nx + 1, b);
        put(high, high_sky, 2 * nx, c);
        put(high, high_sky, 2 * nx + 1, d);
        // As merge_lanes: larger(larger(a, b), larger(c, d)), larger(x, y) = max_ps(y, x).
        let top = _mm_max_ps(_mm_max_ps(d, c), _mm_max_ps(b, a));
        let bottom = _mm_min_ps(_mm_min_ps(d, c), _mm_min_ps(b, a));
        put(second, second_sky, nx, maxima_and_minima(top, bottom));
    }
    blocks
}

/// One row of nodes (`cap` slots a node) of a level whose children all hold one f32 layer:
/// node `nx` merges children `2 nx` and `2 nx + 1` (the last one twice on an odd row, which
/// changes nothing) of the two rows of children `low` and `high` (each its layers,
/// `below_cap` slots a child, and its skies; the same row twice for an odd last row) by
/// [`merge_lanes`], and the lowest start of their open sky, as
/// [`MlhmHierarchy::merge_children`] would merge them, in a loop the compiler keeps in
/// registers; the node's other slots are emptied.
#[inline]
fn merge_single_layer_row(
    nodes: &mut [StoredLayer<f32>],
    sky: &mut [f32],
    cap: usize,
    (low, low_sky): (&[StoredLayer<f32>], &[f32]),
    (high, high_sky): (&[StoredLayer<f32>], &[f32]),
    below_cap: usize,
) {
    let empty = <StoredLayer<f32> as MergedLayer<f32>>::EMPTY;
    let children_x = low_sky.len();
    let lanes = |row: &[StoredLayer<f32>], x: usize| {
        let l = row[x * below_cap];
        [l.water_max, l.ceiling_min, l.solid_max, l.air_min]
    };
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if cap == 1 && below_cap == 1 && std::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked above).
        done = unsafe { merge_layer_pairs_avx2(nodes, sky, (low, low_sky), (high, high_sky)) };
    }
    let nodes = nodes.chunks_exact_mut(cap).zip(sky).enumerate().skip(done);
    for (nx, (node, node_sky)) in nodes {
        let (x0, x1) = (2 * nx, (2 * nx + 1).min(children_x - 1));
        let merged = merge_lanes(lanes(low, x0), lanes(low, x1), lanes(high, x0), lanes(high, x1));
        node[0] = stored(merged);
        node[1..].fill(empty);
        *node_sky = low_sky[x0].min(low_sky[x1]).min(high_sky[x0].min(high_sky[x1]));
    }
}

/// The level-1 bounds of the 2 x 2 one-column cells `low[0..2]` and `high[0..2]` (two cells of
/// a row in one register), in the lanes of [`merge_columns`]: the same operations as
/// [`merge_columns_sse2`], so the same bits.
///
/// # Panics
/// When a row holds fewer than two cells.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn column_pair_node(low: &[MlhmColumn], high: &[MlhmColumn]) -> std::arch::x86_64::__m128 {
    use std::arch::x86_64::*;
    let (low, high) = (&low[..2], &high[..2]);
    let keep = |m: [i32; 4]| {
        _mm256_castsi256_ps(_mm256_setr_epi32(m[0], m[1], m[2], m[3], m[0], m[1], m[2], m[3]))
    };
    let (sand_mask, water_mask) = (keep([-1, 0, -1, -1]), keep([-1, 0, 0, -1]));
    // Per 128-bit half (one column): [b, s, w, c] -> [b + s + w, c, b + s, b + s + w].
    let lanes = |v: __m256| {
        let base = _mm256_shuffle_ps::<0b00_00_11_00>(v, v);
        let sand = _mm256_and_ps(_mm256_shuffle_ps::<0b01_01_01_01>(v, v), sand_mask);
        let water = _mm256_and_ps(_mm256_shuffle_ps::<0b10_10_10_10>(v, v), water_mask);
        _mm256_add_ps(_mm256_add_ps(base, sand), water)
    };
    // SAFETY: two cells of each row (sliced above); `MlhmColumn` is `repr(C)`, four f32, so
    // two of them are eight.
    let (a, b) = unsafe {
        (_mm256_loadu_ps(low.as_ptr().cast::<f32>()), _mm256_loadu_ps(high.as_ptr().cast::<f32>()))
    };
    let (a, b) = (lanes(a), lanes(b));
    let (top, bottom) = (_mm256_max_ps(a, b), _mm256_min_ps(a, b));
    let top = _mm_max_ps(_mm256_castps256_ps128(top), _mm256_extractf128_ps::<1>(top));
    let bottom = _mm_min_ps(_mm256_castps256_ps128(bottom), _mm256_extractf128_ps::<1>(bottom));
    maxima_and_minima(top, bottom)
}

/// The lanes of a stored layer from `top` and `bottom`: the maxima (water top, solid top) from
/// `top`, the minima (ceiling, start of air) from `bottom`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn maxima_and_minima(
    top: std::arch::x86_64::__m128,
    bottom: std::arch::x86_64::__m128,
) -> std::arch::x86_64::__m128 {
    use std::arch::x86_64::*;
    let maxima = _mm_castsi128_ps(_mm_setr_epi32(-1, 0, -1, 0));
    _mm_or_ps(_mm_and_ps(maxima, top), _mm_andnot_ps(maxima, bottom))
}

/// The four lanes of `v`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn lanes_of(v: std::arch::x86_64::__m128) -> [f32; 4] {
    let mut out = [0f32; 4];
    // SAFETY: `out` holds four f32.
    unsafe { std::arch::x86_64::_mm_storeu_ps(out.as_mut_ptr(), v) };
    out
}

/// The nodes of one row of [`merge_one_column_cells`] whose two columns of cells exist
/// (`2 nx + 1 < low.len()`), two cells of a row in one AVX2 register; returns how many it
/// merged. The same lanes and operations as [`merge_columns_sse2`], so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn merge_column_pairs_avx2(
    low: &[MlhmColumn],
    high: &[MlhmColumn],
    nodes: &mut [StoredLayer<f32>],
    sky: &mut [f32],
) -> usize {
    let pairs = (low.len() / 2).min(high.len() / 2).min(nodes.len()).min(sky.len());
    for nx in 0..pairs {
        let x = 2 * nx;
        let merged = lanes_of(column_pair_node(&low[x..x + 2], &high[x..x + 2]));
        nodes[nx] = stored(merged);
        sky[nx] = merged[3];
    }
    pairs
}

/// The nodes of one row of [`merge_single_layer_row`] with one slot a node and a child
/// (`cap` and `below_cap` 1) whose two columns of children exist, a node's two children of a
/// row in one AVX2 register; returns how many it merged. The same maxima and minima as
/// [`merge_lanes`] (`larger(x, y)` is `max_ps(y, x)`), taken in another order, which for
/// bounds that are never NaN changes at most the sign of a zero.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn merge_layer_pairs_avx2(
    nodes: &mut [StoredLayer<f32>],
    sky: &mut [f32],
    (low, low_sky): (&[StoredLayer<f32>], &[f32]),
    (high, high_sky): (&[StoredLayer<f32>], &[f32]),
) -> usize {
    use std::arch::x86_64::*;
    let pairs = (low.len() / 2).min(high.len() / 2).min(nodes.len()).min(sky.len());
    let pairs = pairs.min(low_sky.len() / 2).min(high_sky.len() / 2);
    let maxima = _mm_castsi128_ps(_mm_setr_epi32(-1, 0, -1, 0));
    for nx in 0..pairs {
        // SAFETY: children 2 nx and 2 nx + 1 exist in both rows (`pairs` above);
        // `StoredLayer<f32>` is `repr(C)`, four f32, so two of them are eight.
        let (a, b) = unsafe {
            (
                _mm256_loadu_ps(low.as_ptr().add(2 * nx).cast::<f32>()),
                _mm256_loadu_ps(high.as_ptr().add(2 * nx).cast::<f32>()),
            )
        };
        let (top, bottom) = (_mm256_max_ps(b, a), _mm256_min_ps(b, a));
        let top = _mm_max_ps(_mm256_extractf128_ps::<1>(top), _mm256_castps256_ps128(top));
        let bottom = _mm_min_ps(_mm256_extractf128_ps::<1>(bottom), _mm256_castps256_ps128(bottom));
        let merged = _mm_or_ps(_mm_and_ps(maxima, top), _mm_andnot_ps(maxima, bottom));
        let mut out = [0f32; 4];
        // SAFETY: `out` holds four f32.
        unsafe { _mm_storeu_ps(out.as_mut_ptr(), merged) };
        nodes[nx] = stored(out);
        let (x0, x1) = (2 * nx, 2 * nx + 1);
        sky[nx] = low_sky[x0].min(low_sky[x1]).min(high_sky[x0].min(high_sky[x1]));
    }
    pairs
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
