//! The fast merge of an MLHM hierarchy's lowest levels where every cell holds one column
//! (the common case of a height map): SSE2 and AVX2 merges of whole rows of cells into
//! levels 1 and 2 at once, and of single-layer rows above, bit for bit what the general
//! merge of [`super::build`] computes.

use super::bounds::{LevelBounds, MergedLayer, StoredLayer};
use rayon::prelude::*;
use relief_core::{Mlhm, MlhmColumn};

/// The stored f32 layer of merged lanes in the order of [`StoredLayer`]'s fields.
#[inline(always)]
fn stored([water_max, ceiling_min, solid_max, air_min]: [f32; 4]) -> StoredLayer<f32> {
    StoredLayer { water_max, ceiling_min, solid_max, air_min }
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
///
/// # Safety
/// None beyond running on x86-64, which always has SSE2: the function is `unsafe` only
/// because the intrinsics it calls are.
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
pub(super) type SingleSlotLevel<'a> = (&'a mut LevelBounds<f32>, &'a mut [u8], usize);

/// Level 1 (one slot a node) of `map`, whose cells hold one column each, and with `second`
/// level 2 as well, in the same pass: each level-1 node the merge of its (up to) 2 x 2 cells
/// by [`merge_columns`] (an odd grid's last row or column merged with itself), its sky at the
/// merged start of air; each level-2 row by [`merge_single_layer_row`] from the two rows of
/// level 1 just written, still in cache. Rows of the top level in parallel. Where the CPU has
/// AVX2, two cells to a register, and blocks of 4 x 4 cells merged into both levels at once
/// ([`merge_column_blocks_avx2`]).
pub(super) fn merge_one_column_cells(
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
///
/// # Safety
/// The processor must support AVX2 (the caller detects it at run time first). The slices
/// may have any lengths: only the nodes whose children all lie within them are merged.
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
pub(super) fn merge_single_layer_row(
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
///
/// # Safety
/// The processor must support AVX2 (the caller detects it at run time first). The slices
/// may have any lengths: only the nodes whose children all lie within them are merged.
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
///
/// # Safety
/// The processor must support AVX2 (the caller detects it at run time first). The slices
/// may have any lengths: only the nodes whose children all lie within them are merged.
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
