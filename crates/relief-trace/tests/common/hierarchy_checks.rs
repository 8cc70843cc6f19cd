//! Checks of an MLHM hierarchy against its definition, shared by the hierarchy's tests: node
//! bounds enclosing their children and cells, f16 bounds as the f32 ones rounded outward, and
//! random placements and grid sizes.

use half::f16;
use proptest::prelude::*;
use relief_core::{DVec2, Mlhm, MlhmColumn, Precision};
use relief_trace::{MlhmBacktrack, MlhmHierarchy, MlhmHierarchyTracer, MlhmMode, MlhmNodeLayer};
use std::sync::{Arc, OnceLock};

/// The hierarchy tracers of `map`: both back-tracking variants at both precisions.
pub fn hierarchy_tracers(map: &Arc<Mlhm>, origin: DVec2) -> [MlhmHierarchyTracer; 4] {
    let exact = MlhmHierarchyTracer::new(map.clone(), origin);
    let half = MlhmHierarchyTracer::new_with_precision(map.clone(), origin, Precision::F16);
    let miss = MlhmBacktrack::MissCounter;
    [exact.clone(), exact.with_backtrack(miss), half.clone(), half.with_backtrack(miss)]
}

/// A short name of a tracer's variant for messages.
pub fn variant(tracer: &MlhmHierarchyTracer) -> String {
    format!("{} {:?}", tracer.backtrack(), tracer.hierarchy().precision())
}

/// Every f16 value but NaN (one zero), as f32, ascending from `-inf` to `+inf`.
pub fn f16_values() -> &'static [f32] {
    static VALUES: OnceLock<Vec<f32>> = OnceLock::new();
    VALUES.get_or_init(|| {
        let mut all: Vec<f32> = (0..=u16::MAX)
            .filter(|&bits| bits != 0x8000) // -0: one zero is enough
            .map(|bits| f16::from_bits(bits).to_f32())
            .filter(|v| !v.is_nan())
            .collect();
        all.sort_by(f32::total_cmp);
        all
    })
}

/// The smallest f16 `>= v`, searched for among all of them (independently of the library's
/// rounding).
pub fn f16_above(v: f32) -> f32 {
    let all = f16_values();
    all[all.partition_point(|&a| a < v)]
}

/// The largest f16 `<= v`.
pub fn f16_below(v: f32) -> f32 {
    let all = f16_values();
    all[all.partition_point(|&a| a <= v) - 1]
}

/// Checks that the f16 hierarchy is the f32 one with every bound rounded outward to an f16:
/// maxima to the f16 at or above, minima (and the sky) to the f16 at or below.
pub fn check_f16_is_f32_rounded_outward(
    exact: &MlhmHierarchy,
    half: &MlhmHierarchy,
) -> Result<(), String> {
    for mode in MlhmMode::ALL {
        if half.top(mode) != exact.top(mode) {
            return Err(format!("{mode} top {} != {}", half.top(mode), exact.top(mode)));
        }
    }
    for level in 1..=exact.level_count() {
        let (nodes_x, nodes_y) = exact.nodes(level);
        if half.nodes(level) != (nodes_x, nodes_y)
            || half.layer_cap(level) != exact.layer_cap(level)
        {
            return Err(format!("shape of level {level}"));
        }
        for ny in 0..nodes_y {
            for nx in 0..nodes_x {
                let n = exact.layer_count(level, nx, ny);
                if half.layer_count(level, nx, ny) != n {
                    return Err(format!("layer count of node ({nx}, {ny}) of level {level}"));
                }
                for k in 0..n {
                    let e = exact.node_layer(level, nx, ny, k);
                    let expected = MlhmNodeLayer {
                        water_max: f16_above(e.water_max),
                        ceiling_min: f16_below(e.ceiling_min),
                        solid_max: f16_above(e.solid_max),
                        air_min: f16_below(e.air_min),
                    };
                    let got = half.node_layer(level, nx, ny, k);
                    if got != expected {
                        return Err(format!(
                            "level {level} node ({nx}, {ny}) layer {k}: f16 {got:?}, f32 {e:?}"
                        ));
                    }
                }
                let sky = exact.sky_min(level, nx, ny);
                if half.sky_min(level, nx, ny) != f16_below(sky) {
                    return Err(format!("sky of node ({nx}, {ny}) of level {level}"));
                }
            }
        }
    }
    Ok(())
}

/// `map` with every height multiplied by `2^exponent` (exactly: the invariants hold).
pub fn scaled(map: &Mlhm, exponent: i32) -> Mlhm {
    let factor = 2f32.powi(exponent);
    let columns = map
        .raw_columns()
        .iter()
        .map(|c| MlhmColumn::from_array(c.to_array().map(|v| v * factor)))
        .collect();
    Mlhm::from_parts(
        map.width(),
        map.height(),
        map.max_layers(),
        map.cell_size(),
        map.layer_counts().to_vec(),
        columns,
    )
    .unwrap()
}

/// The intervals of node `(x, y)` of `level` in `mode`.
pub fn intervals(
    h: &MlhmHierarchy,
    level: usize,
    x: usize,
    y: usize,
    mode: MlhmMode,
) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    h.for_each_interval(level, x, y, mode, |lo, hi| {
        out.push((lo, hi));
        false
    });
    out
}

/// The boxes `[bottom, top]` of cell `(x, y)` in `mode`, from the columns (independently of
/// the tracers' code), dropping empty ones.
pub fn cell_boxes(map: &Mlhm, x: usize, y: usize, mode: MlhmMode) -> Vec<(f64, f64)> {
    let columns: Vec<MlhmColumn> = map.cell_columns(x, y).collect();
    let mut out = Vec::new();
    for (k, c) in columns.iter().enumerate() {
        let floor = if k == 0 { f64::NEG_INFINITY } else { columns[k - 1].ceiling as f64 };
        let air = if k == 0 { f64::NEG_INFINITY } else { columns[k - 1].water_top() as f64 };
        out.push(match mode {
            MlhmMode::Solids => (floor, c.solid_top() as f64),
            MlhmMode::SolidsWater => (floor, c.water_top() as f64),
            MlhmMode::SolidsAir => (air, c.solid_top() as f64),
        });
    }
    if mode == MlhmMode::SolidsAir {
        out.push((columns[columns.len() - 1].water_top() as f64, f64::INFINITY));
    }
    out.retain(|(lo, hi)| hi > lo);
    out
}

/// Checks that every node layer encloses the child layers folded into it, and that every box
/// of every cell lies within an interval of each of its ancestors, in every mode.
pub fn check_bounds(map: &Mlhm, h: &MlhmHierarchy) -> Result<(), String> {
    let contains = |outer: MlhmNodeLayer, inner: MlhmNodeLayer| {
        outer.water_max >= inner.water_max
            && outer.solid_max >= inner.solid_max
            && outer.ceiling_min <= inner.ceiling_min
            && outer.air_min <= inner.air_min
    };
    for level in 1..=h.level_count() {
        let (nodes_x, nodes_y) = h.nodes(level);
        let cap = h.layer_cap(level);
        for ny in 0..nodes_y {
            for nx in 0..nodes_x {
                let n = h.layer_count(level, nx, ny);
                if n == 0 || n > cap {
                    return Err(format!("node ({nx}, {ny}) of level {level} has {n} layers"));
                }
                let (children_x, children_y) =
                    if level == 1 { (map.width(), map.height()) } else { h.nodes(level - 1) };
                for cy in 2 * ny..(2 * ny + 2).min(children_y) {
                    for cx in 2 * nx..(2 * nx + 2).min(children_x) {
                        let child: Vec<MlhmNodeLayer> = if level == 1 {
                            map.cell_columns(cx, cy)
                                .map(|c| MlhmNodeLayer {
                                    water_max: c.water_top(),
                                    ceiling_min: c.ceiling,
                                    solid_max: c.solid_top(),
                                    air_min: c.water_top(),
                                })
                                .collect()
                        } else {
                            (0..h.layer_count(level - 1, cx, cy))
                                .map(|k| h.node_layer(level - 1, cx, cy, k))
                                .collect()
                        };
                        for (j, &inner) in child.iter().enumerate() {
                            let outer = h.node_layer(level, nx, ny, j.min(cap - 1));
                            if !contains(outer, inner) {
                                return Err(format!(
                                    "level {level} node ({nx}, {ny}) layer {} {outer:?} does not \
                                     enclose child ({cx}, {cy}) layer {j} {inner:?}",
                                    j.min(cap - 1)
                                ));
                            }
                        }
                        let child_sky = if level == 1 {
                            map.cell_columns(cx, cy).last().unwrap().water_top()
                        } else {
                            h.sky_min(level - 1, cx, cy)
                        };
                        if h.sky_min(level, nx, ny) > child_sky {
                            return Err(format!("sky of level {level} node ({nx}, {ny})"));
                        }
                    }
                }
            }
        }
    }
    for y in 0..map.height() {
        for x in 0..map.width() {
            for mode in MlhmMode::ALL {
                for (lo, hi) in cell_boxes(map, x, y, mode) {
                    for level in 1..=h.level_count() {
                        let (nx, ny) = (x >> level, y >> level);
                        let inside = intervals(h, level, nx, ny, mode)
                            .iter()
                            .any(|&(a, b)| a <= lo && hi <= b);
                        if !inside {
                            return Err(format!(
                                "{mode} box [{lo}, {hi}] of cell ({x}, {y}) outside node \
                                 ({nx}, {ny}) of level {level}: {:?}",
                                intervals(h, level, nx, ny, mode)
                            ));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}

/// A random placement: cell size and origin.
pub fn placement() -> impl Strategy<Value = (f64, DVec2)> {
    (prop_oneof![Just(1.0), 0.1f64..3.0], -50.0f64..50.0, -50.0f64..50.0)
        .prop_map(|(s, x, y)| (s, DVec2::new(x, y)))
}

/// Grid sizes from 1 x 1 to 40 x 37, small ones often.
pub fn grid_size() -> impl Strategy<Value = (usize, usize)> {
    prop_oneof![(1usize..6, 1usize..6), (1usize..=40, 1usize..=37)]
}
