//! The MLHM hierarchy and its traversal: every node bound encloses its children's and every
//! cell box, with exact f32 bounds and with f16 bounds rounded outward; both back-tracking
//! variants at both precisions return the naive tracer's hits on random MLHMs and rays of
//! every kind, in all three modes, for first hits and shadow rays.

mod common;

use common::hierarchy_checks::*;
use common::mlhm_reference::{agree, random_mlhm, random_ray, Rng, MLHM_RAY_KINDS};
use half::f16;
use proptest::prelude::*;
use relief_core::{DVec2, DVec3, Mlhm, MlhmColumn, Precision, Ray};
use relief_trace::{MlhmBacktrack, MlhmHierarchy, MlhmMode, MlhmNaiveTracer, MlhmTracer, Tracer};
use std::sync::Arc;
use std::time::Instant;

const RAYS_PER_KIND: usize = 8;

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
            prop_assert!(false, "f32: {}", e);
        }
        let half = MlhmHierarchy::build_with_precision(&map, Precision::F16);
        if let Err(e) = check_bounds(&map, &half) {
            prop_assert!(false, "f16: {}", e);
        }
        if let Err(e) = check_f16_is_f32_rounded_outward(&h, &half) {
            prop_assert!(false, "{}", e);
        }
    }

    /// Heights scaled by a power of two: f16 steps of up to 64 m, and values beyond f16's
    /// range (+-65504), whose maxima become +inf and minima -inf or -65504.
    #[test]
    fn f16_bounds_enclose_on_scaled_maps_and_give_the_naive_hits(
        (width, height) in grid_size(),
        max_columns in 1usize..=8,
        exponent in prop_oneof![Just(7), Just(13), -20i32..14],
        seed in any::<u64>(),
    ) {
        let mut rng = Rng::new(seed);
        let map = Arc::new(scaled(&random_mlhm(&mut rng, width, height, max_columns, 1.0), exponent));
        let h = MlhmHierarchy::build(&map);
        let half = MlhmHierarchy::build_with_precision(&map, Precision::F16);
        for (e, name) in [(check_bounds(&map, &h), "f32"), (check_bounds(&map, &half), "f16")] {
            if let Err(e) = e {
                prop_assert!(false, "{}: {}", name, e);
            }
        }
        if let Err(e) = check_f16_is_f32_rounded_outward(&h, &half) {
            prop_assert!(false, "{}", e);
        }
        let naive = MlhmNaiveTracer::new(map.clone(), DVec2::ZERO);
        let tracers = hierarchy_tracers(&map, DVec2::ZERO);
        for i in 0..MLHM_RAY_KINDS.len() * 2 {
            let kind = MLHM_RAY_KINDS[i % MLHM_RAY_KINDS.len()];
            let ray = random_ray(&mut rng, &map, DVec2::ZERO, kind);
            for mode in MlhmMode::ALL {
                let expected = naive.intersect_mode(&ray, mode);
                for tracer in &tracers[2..] {
                    prop_assert_eq!(tracer.intersect_mode(&ray, mode), expected,
                        "{} {} {:?} {:?}", variant(tracer), mode, kind, ray);
                }
            }
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
        let tracers = hierarchy_tracers(&map, origin);
        for i in 0..MLHM_RAY_KINDS.len() * RAYS_PER_KIND {
            let kind = MLHM_RAY_KINDS[i % MLHM_RAY_KINDS.len()];
            let ray = random_ray(&mut rng, &map, origin, kind);
            for mode in MlhmMode::ALL {
                let expected = naive.intersect_mode(&ray, mode);
                let reach = expected.map(|e| e.hit.t).unwrap_or(1.0).max(1e-3);
                let shadow = ray.with_range(ray.t_min, reach * t_max_fraction);
                let blocked = naive.occluded_mode(&shadow, mode);
                for tracer in &tracers {
                    let b = variant(tracer);
                    let hit = tracer.intersect_mode(&ray, mode);
                    prop_assert!(agree(hit.map(|h| h.hit.t), expected.map(|e| e.hit.t), 1e-5),
                        "{b} {mode} {kind:?} {ray:?}: hierarchy {hit:?} naive {expected:?}");
                    prop_assert_eq!(hit.map(|h| h.material), expected.map(|e| e.material),
                        "{} {} {:?} {:?}", b, mode, kind, ray);
                    // Bit for bit: distance, position, normal, cell and column.
                    prop_assert_eq!(hit, expected, "{} {} {:?} {:?}", b, mode, kind, ray);
                    prop_assert_eq!(tracer.occluded_mode(&shadow, mode), blocked,
                        "{} {} shadow {:?} {:?}", b, mode, kind, shadow);
                }
            }
            let visible = naive.intersect(&ray);
            for tracer in &tracers {
                prop_assert_eq!(tracer.intersect(&ray), visible, "{}", variant(tracer));
            }
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
        let ray = Ray::new(DVec3::from(origin), DVec3::from(dir)).with_range(range[0], range[1]);
        for tracer in &hierarchy_tracers(&map, DVec2::ZERO) {
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
    let tracers = hierarchy_tracers(&map, origin);
    let mut naive_steps = 0u32;
    let mut steps = [0u32; 4];
    for i in 0..2000 {
        let kind = MLHM_RAY_KINDS[i % MLHM_RAY_KINDS.len()];
        let ray = random_ray(&mut rng, &map, origin, kind);
        for mode in MlhmMode::ALL {
            let expected = naive.intersect_mode_counted(&ray, mode, &mut naive_steps);
            for (tracer, count) in tracers.iter().zip(&mut steps) {
                let hit = tracer.intersect_mode_counted(&ray, mode, count);
                assert_eq!(hit, expected, "{} {mode} {ray:?}", variant(tracer));
            }
        }
    }
    println!(
        "steps: naive {naive_steps}, exit stack {}, miss counter {} (f16 bounds: {}, {})",
        steps[0], steps[1], steps[2], steps[3]
    );
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

/// Rebuilding f16 bounds in place, or for a map of another shape, keeps the precision and
/// gives what a fresh build gives.
#[test]
fn f16_hierarchy_rebuilds_in_place_and_from_scratch() {
    let mut rng = Rng::new(5);
    let (map, other) =
        (random_mlhm(&mut rng, 64, 40, 4, 1.0), random_mlhm(&mut rng, 64, 40, 4, 1.0));
    let mut h = MlhmHierarchy::build_with_precision(&other, Precision::F16);
    let bytes = h.memory_bytes();
    h.rebuild(&map);
    assert_eq!(h, MlhmHierarchy::build_with_precision(&map, Precision::F16));
    assert_eq!(h.memory_bytes(), bytes);
    let exact = MlhmHierarchy::build(&map);
    assert!(2 * h.memory_bytes() < exact.memory_bytes() + 64 * 40);
    let small = scaled(&random_mlhm(&mut rng, 5, 9, 8, 1.0), 12);
    h.rebuild(&small);
    assert_eq!(h.precision(), Precision::F16);
    assert_eq!(h, MlhmHierarchy::build_with_precision(&small, Precision::F16));
    check_bounds(&small, &h).unwrap();
}

/// Heights between two f16s whose nearest f16 lies on the wrong side: a top of 1000.2 m
/// (nearest f16 1000.0, below it) and a floor of 1000.3 m (nearest 1000.5, above it). Rounded
/// to nearest, a node would claim nothing reaches 1000.1 m and nothing hangs below 1000.5 m,
/// and cull the rays below; rounded outward it keeps them, and the hits are the naive ones.
#[test]
fn f16_bounds_keep_what_round_to_nearest_would_cull() {
    let (top, floor) = (1000.2f32, 1000.3f32);
    assert!(f16::from_f32(top).to_f32() < top && f16::from_f32(floor).to_f32() > floor);
    // Room for 4 layers, so that levels 1 and 2 keep 2 layers a node: the slab's floor bounds
    // the second layer there.
    let mut map = Mlhm::new(64, 64, 4, 1.0).unwrap();
    // A tower at (40, 21) whose top is at 1000.2 m; over cell (20, 41) a slab hangs from
    // 1000.3 m to 1002 m, 0.5 m above a 999.8 m pillar.
    map.set_cell(40, 21, &[MlhmColumn::new(top, 0.0, 0.0, f32::INFINITY)]).unwrap();
    map.set_cell(
        20,
        41,
        &[
            MlhmColumn::new(999.8, 0.0, 0.0, floor),
            MlhmColumn::new(1002.0, 0.0, 0.0, f32::INFINITY),
        ],
    )
    .unwrap();
    let map = Arc::new(map);
    let naive = MlhmNaiveTracer::new(map.clone(), DVec2::ZERO);
    let rays = [
        // At about 1000.1 m, just under the tower's top, from the west: level and descending.
        Ray::new(DVec3::new(-5.0, 21.5, 1000.1), DVec3::X),
        Ray::new(DVec3::new(0.5, 21.5, 1000.15), DVec3::new(1.0, 0.0, -0.001).normalize()),
        // Under the slab at 1000.4 m, between its floor and its nearest f16, from the east.
        Ray::new(DVec3::new(70.0, 41.5, 1000.4), -DVec3::X),
    ];
    for ray in rays {
        for mode in MlhmMode::ALL {
            let expected = naive.intersect_mode(&ray, mode);
            if mode != MlhmMode::SolidsAir {
                assert!(expected.is_some(), "{mode} {ray:?}");
            }
            for tracer in &hierarchy_tracers(&map, DVec2::ZERO)[2..] {
                let hit = tracer.intersect_mode(&ray, mode);
                assert_eq!(hit, expected, "{} {mode} {ray:?}", variant(tracer));
            }
        }
    }
    // The stored bounds, rounded outward.
    let half = MlhmHierarchy::build_with_precision(&map, Precision::F16);
    check_bounds(&map, &half).unwrap();
    for level in 1..=half.level_count() {
        let tower = half.node_layer(level, 40 >> level, 21 >> level, 0);
        assert_eq!(tower.solid_max, 1000.5, "level {level}");
    }
    for level in 1..=2 {
        assert_eq!(half.layer_count(level, 20 >> level, 41 >> level), 2);
        let below_slab = half.node_layer(level, 20 >> level, 41 >> level, 0);
        assert_eq!(below_slab.ceiling_min, 1000.0, "level {level}");
    }
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
        let tracers = hierarchy_tracers(&map, DVec2::ZERO);
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
                for tracer in &tracers {
                    let hit = tracer.intersect_mode(&ray, mode);
                    assert_eq!(hit, expected, "{} {mode} {ray:?}", variant(tracer));
                }
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
    let tracers = hierarchy_tracers(&map, DVec2::ZERO);
    let eye = DVec3::new(-10.0, -20.0, 25.0);
    for mode in MlhmMode::ALL {
        let mut naive_steps = 0u32;
        let mut steps = [0u32; 4];
        for j in 0..48 {
            for i in 0..64 {
                let target = DVec3::new(2.0 * i as f64, 2.7 * j as f64, 0.0);
                let ray = Ray::new(eye, (target - eye).normalize());
                let expected = naive.intersect_mode_counted(&ray, mode, &mut naive_steps);
                for (tracer, count) in tracers.iter().zip(&mut steps) {
                    let hit = tracer.intersect_mode_counted(&ray, mode, count);
                    assert_eq!(hit, expected, "{} {mode} {ray:?}", variant(tracer));
                }
            }
        }
        println!(
            "{mode} steps: naive {naive_steps}, exit stack {}, miss counter {} (f16 bounds: {}, \
             {})",
            steps[0], steps[1], steps[2], steps[3]
        );
        // From the sky, rays inside water (solids + air) are out of it at once.
        if mode != MlhmMode::SolidsAir {
            assert!(steps.iter().all(|&s| 2 * s < naive_steps), "{mode} {steps:?}");
        }
    }
}
