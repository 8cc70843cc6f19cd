//! The MLHM hierarchy and its traversal: every node bound encloses its children's and every
//! cell box; both back-tracking variants return the naive tracer's hits on random MLHMs and
//! rays of every kind, in all three modes, for first hits and shadow rays.

mod common;

use common::mlhm_reference::{agree, random_mlhm, random_ray, Rng, MLHM_RAY_KINDS};
use proptest::prelude::*;
use relief_core::{DVec2, DVec3, Mlhm, MlhmColumn, Ray};
use relief_trace::{
    MlhmBacktrack, MlhmHierarchy, MlhmHierarchyTracer, MlhmMode, MlhmNaiveTracer, MlhmNodeLayer,
    MlhmTracer, Tracer,
};
use std::sync::Arc;
use std::time::Instant;

const RAYS_PER_KIND: usize = 8;

/// The intervals of node `(x, y)` of `level` in `mode`.
fn intervals(
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
fn cell_boxes(map: &Mlhm, x: usize, y: usize, mode: MlhmMode) -> Vec<(f64, f64)> {
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
fn check_bounds(map: &Mlhm, h: &MlhmHierarchy) -> Result<(), String> {
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
fn placement() -> impl Strategy<Value = (f64, DVec2)> {
    (prop_oneof![Just(1.0), 0.1f64..3.0], -50.0f64..50.0, -50.0f64..50.0)
        .prop_map(|(s, x, y)| (s, DVec2::new(x, y)))
}

/// Grid sizes from 1 x 1 to 40 x 37, small ones often.
fn grid_size() -> impl Strategy<Value = (usize, usize)> {
    prop_oneof![(1usize..6, 1usize..6), (1usize..=40, 1usize..=37)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, ..ProptestConfig::default() })]

    #[test]
    fn node_bounds_enclose_their_children_and_cells(
        (width, height) in grid_size(),
        max_columns in 1usize..=8,
        seed in any::<u64>(),
    ) {
        let mut rng = Rng::new(seed);
        let map = random_mlhm(&mut rng, width, height, max_columns, 1.0);
        let h = MlhmHierarchy::build(&map);
        prop_assert_eq!(h.level_count(), MlhmHierarchy::level_count_for(width, height));
        for level in 1..=h.level_count() {
            prop_assert_eq!(h.nodes(level), (width.div_ceil(1 << level), height.div_ceil(1 << level)));
        }
        if let Err(e) = check_bounds(&map, &h) {
            prop_assert!(false, "{}", e);
        }
    }

    #[test]
    fn hierarchy_tracer_agrees_with_the_naive_tracer(
        (width, height) in grid_size(),
        max_columns in 1usize..=8,
        (cell_size, origin) in placement(),
        seed in any::<u64>(),
        t_max_fraction in prop_oneof![0.05f64..0.95, 1.05f64..1.5],
    ) {
        let mut rng = Rng::new(seed);
        let map = Arc::new(random_mlhm(&mut rng, width, height, max_columns, cell_size));
        let naive = MlhmNaiveTracer::new(map.clone(), origin);
        let stack = MlhmHierarchyTracer::new(map.clone(), origin);
        let miss = stack.clone().with_backtrack(MlhmBacktrack::MissCounter);
        for i in 0..MLHM_RAY_KINDS.len() * RAYS_PER_KIND {
            let kind = MLHM_RAY_KINDS[i % MLHM_RAY_KINDS.len()];
            let ray = random_ray(&mut rng, &map, origin, kind);
            for mode in MlhmMode::ALL {
                let expected = naive.intersect_mode(&ray, mode);
                let reach = expected.map(|e| e.hit.t).unwrap_or(1.0).max(1e-3);
                let shadow = ray.with_range(ray.t_min, reach * t_max_fraction);
                let blocked = naive.occluded_mode(&shadow, mode);
                for tracer in [&stack, &miss] {
                    let b = tracer.backtrack();
                    let hit = tracer.intersect_mode(&ray, mode);
                    prop_assert!(agree(hit.map(|h| h.hit.t), expected.map(|e| e.hit.t), 1e-5),
                        "{b} {mode} {kind:?} {ray:?}: hierarchy {hit:?} naive {expected:?}");
                    prop_assert_eq!(hit.map(|h| h.material), expected.map(|e| e.material),
                        "{} {} {:?} {:?}", b, mode, kind, ray);
                    prop_assert_eq!(tracer.occluded_mode(&shadow, mode), blocked,
                        "{} {} shadow {:?} {:?}", b, mode, kind, shadow);
                }
            }
            let visible = naive.intersect(&ray);
            prop_assert_eq!(stack.intersect(&ray), visible);
            prop_assert_eq!(miss.intersect(&ray), visible);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn any_ray_is_answered_without_panicking(
        origin in prop::array::uniform3(prop_oneof![any::<f64>(), -5.0f64..40.0]),
        dir in prop::array::uniform3(prop_oneof![any::<f64>(), -1.0f64..1.0, Just(0.0)]),
        range in prop::array::uniform2(prop_oneof![any::<f64>(), 0.0f64..10.0]),
    ) {
        let map = Arc::new(random_mlhm(&mut Rng::new(7), 33, 20, 4, 1.0));
        let stack = MlhmHierarchyTracer::new(map, DVec2::ZERO);
        let miss = stack.clone().with_backtrack(MlhmBacktrack::MissCounter);
        let ray = Ray::new(DVec3::from(origin), DVec3::from(dir)).with_range(range[0], range[1]);
        for tracer in [&stack, &miss] {
            for mode in MlhmMode::ALL {
                if let Some(h) = tracer.intersect_mode(&ray, mode) {
                    prop_assert!(h.hit.t >= ray.t_min && h.hit.t <= ray.t_max, "{:?}", h);
                }
            }
        }
    }
}

/// Long grazing rays over a bigger map, hit exactly as by the naive tracer, bit for bit, in
/// fewer steps.
#[test]
fn long_rays_over_a_large_map_match_the_naive_tracer_bit_for_bit() {
    let mut rng = Rng::new(42);
    let map = Arc::new(random_mlhm(&mut rng, 150, 97, 3, 0.5));
    let origin = DVec2::new(-3.0, 7.0);
    let naive = MlhmNaiveTracer::new(map.clone(), origin);
    let stack = MlhmHierarchyTracer::new(map.clone(), origin);
    let miss = stack.clone().with_backtrack(MlhmBacktrack::MissCounter);
    let (mut naive_steps, mut stack_steps, mut miss_steps) = (0u32, 0u32, 0u32);
    for i in 0..2000 {
        let kind = MLHM_RAY_KINDS[i % MLHM_RAY_KINDS.len()];
        let ray = random_ray(&mut rng, &map, origin, kind);
        for mode in MlhmMode::ALL {
            let expected = naive.intersect_mode_counted(&ray, mode, &mut naive_steps);
            assert_eq!(stack.intersect_mode_counted(&ray, mode, &mut stack_steps), expected);
            assert_eq!(miss.intersect_mode_counted(&ray, mode, &mut miss_steps), expected);
        }
    }
    println!("steps: naive {naive_steps}, exit stack {stack_steps}, miss counter {miss_steps}");
}

#[test]
fn build_time_on_a_256_square_scene() {
    let mut rng = Rng::new(3);
    let map = random_mlhm(&mut rng, 256, 256, 4, 1.0);
    let other = random_mlhm(&mut rng, 256, 256, 4, 1.0);
    let runs = 20;
    let start = Instant::now();
    for _ in 0..runs {
        std::hint::black_box(MlhmHierarchy::build(std::hint::black_box(&map)));
    }
    let build_ms = start.elapsed().as_secs_f64() * 1e3 / runs as f64;
    let mut h = MlhmHierarchy::build(&other);
    let start = Instant::now();
    for _ in 0..runs {
        h.rebuild(std::hint::black_box(&map));
    }
    let rebuild_ms = start.elapsed().as_secs_f64() * 1e3 / runs as f64;
    println!(
        "MlhmHierarchy 256 x 256, 4 layers, {} levels: build {build_ms:.3} ms, rebuild in place \
         {rebuild_ms:.3} ms ({} threads)",
        h.level_count(),
        rayon::current_num_threads()
    );
    assert_eq!(h, MlhmHierarchy::build(&map));
    assert_eq!(h.level_count(), 7);
    assert_eq!(h.nodes(7), (2, 2));
    // A map of another shape is rebuilt from scratch.
    let small = random_mlhm(&mut rng, 5, 9, 8, 1.0);
    h.rebuild(&small);
    assert_eq!(h, MlhmHierarchy::build(&small));
}

#[test]
fn backtrack_names_round_trip() {
    for b in MlhmBacktrack::ALL {
        assert_eq!(b.name().parse::<MlhmBacktrack>(), Ok(b));
    }
    assert!("pop".parse::<MlhmBacktrack>().is_err());
}

/// A map whose values are multiples of 0.5 m: ties between box faces and cell boundaries.
fn quantized_mlhm(rng: &mut Rng, width: usize, height: usize, max_columns: usize) -> Mlhm {
    let q = |rng: &mut Rng, n: usize| rng.below(n) as f32 * 0.5;
    let mut map = Mlhm::new(width, height, max_columns, 1.0).unwrap();
    for y in 0..height {
        for x in 0..width {
            let n = 1 + rng.below(max_columns);
            let mut floor = q(rng, 5) - 1.0;
            let mut columns = Vec::with_capacity(n);
            for k in 0..n {
                let bedrock = floor + if k == 0 { q(rng, 3) } else { q(rng, 2) };
                let mut c = MlhmColumn::new(bedrock, q(rng, 2), q(rng, 3), f32::INFINITY);
                if k + 1 < n {
                    c.ceiling = c.water_top() + q(rng, 4);
                    floor = c.ceiling;
                }
                columns.push(c);
            }
            map.set_cell(x, y, &columns).unwrap();
        }
    }
    map
}

/// Rays through lattice points with directions of exact small components: they cross cell
/// corners, node corners and box edges exactly, where the traversal's ties are decided.
#[test]
fn lattice_rays_through_corners_and_edges_match_the_naive_tracer_bit_for_bit() {
    let mut rng = Rng::new(11);
    let components = [-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0];
    for (width, height, layers) in [(20, 13, 3), (9, 16, 8), (33, 5, 2)] {
        let map = Arc::new(quantized_mlhm(&mut rng, width, height, layers));
        let naive = MlhmNaiveTracer::new(map.clone(), DVec2::ZERO);
        let stack = MlhmHierarchyTracer::new(map.clone(), DVec2::ZERO);
        let miss = stack.clone().with_backtrack(MlhmBacktrack::MissCounter);
        for _ in 0..1500 {
            let o = DVec3::new(
                rng.below(width + 1) as f64 + [0.0, 0.5][rng.below(2)],
                rng.below(height + 1) as f64 + [0.0, 0.5][rng.below(2)],
                rng.below(16) as f64 * 0.5 - 2.0,
            );
            let d = DVec3::new(
                components[rng.below(7)],
                components[rng.below(7)],
                [-1.0, -0.5, 0.0, 0.5][rng.below(4)],
            );
            if d == DVec3::ZERO {
                continue;
            }
            let ray = Ray::new(o, d).with_range(0.0, [f64::INFINITY, 3.0][rng.below(2)]);
            for mode in MlhmMode::ALL {
                let expected = naive.intersect_mode(&ray, mode);
                assert_eq!(stack.intersect_mode(&ray, mode), expected, "stack {mode} {ray:?}");
                assert_eq!(miss.intersect_mode(&ray, mode), expected, "miss {mode} {ray:?}");
            }
        }
    }
}

/// A smooth 128 x 128 valley with an arch over it and a pond: the hierarchy skips most cells,
/// so it takes far fewer steps than the naive DDA (a count, not a timing), with the same hits.
#[test]
fn hierarchy_takes_fewer_steps_on_a_smooth_scene() {
    let n = 128;
    let mut map = Mlhm::new(n, n, 2, 1.0).unwrap();
    for y in 0..n {
        for x in 0..n {
            let (u, v) = (x as f32 / n as f32 - 0.5, y as f32 / n as f32 - 0.5);
            let ground = 20.0 * (u * u + v * v) + (x as f32 * 0.3).sin();
            let water = if ground < 1.0 { 1.0 - ground } else { 0.0 };
            let mut columns = vec![MlhmColumn::new(ground, 0.5, water, f32::INFINITY)];
            if (60..68).contains(&x) {
                columns[0].ceiling = 12.0;
                columns.push(MlhmColumn::new(14.0, 0.0, 0.0, f32::INFINITY));
            }
            map.set_cell(x, y, &columns).unwrap();
        }
    }
    let map = Arc::new(map);
    let naive = MlhmNaiveTracer::new(map.clone(), DVec2::ZERO);
    let stack = MlhmHierarchyTracer::new(map.clone(), DVec2::ZERO);
    let miss = stack.clone().with_backtrack(MlhmBacktrack::MissCounter);
    let eye = DVec3::new(-10.0, -20.0, 25.0);
    for mode in MlhmMode::ALL {
        let (mut naive_steps, mut stack_steps, mut miss_steps) = (0u32, 0u32, 0u32);
        for j in 0..48 {
            for i in 0..64 {
                let target = DVec3::new(2.0 * i as f64, 2.7 * j as f64, 0.0);
                let ray = Ray::new(eye, (target - eye).normalize());
                let expected = naive.intersect_mode_counted(&ray, mode, &mut naive_steps);
                assert_eq!(stack.intersect_mode_counted(&ray, mode, &mut stack_steps), expected);
                assert_eq!(miss.intersect_mode_counted(&ray, mode, &mut miss_steps), expected);
            }
        }
        println!(
            "{mode} steps: naive {naive_steps}, exit stack {stack_steps}, miss counter {miss_steps}"
        );
        // From the sky, rays inside water (solids + air) are out of it at once.
        if mode != MlhmMode::SolidsAir {
            assert!(2 * stack_steps < naive_steps && 2 * miss_steps < naive_steps, "{mode}");
        }
    }
}
