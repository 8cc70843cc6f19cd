//! The naive MLHM box tracer against an independent brute-force tracer on random MLHMs and rays
//! of every kind, in all three intersection modes, for first hits and shadow rays; and a
//! single-column MLHM against the same height field's `boxes` surface.

mod common;

use common::mlhm_reference::{
    agree, first_hit, random_mlhm, random_ray, MlhmRayKind, Rng, MLHM_RAY_KINDS,
};
use proptest::prelude::*;
use relief_core::{DVec2, DVec3, GridGeometry, HeightField, Mlhm, MlhmColumn, Ray, Surface};
use relief_trace::{MlhmMaterial, MlhmMode, MlhmNaiveTracer, MlhmTracer, NaiveTracer, Tracer};
use std::sync::Arc;

const RAYS_PER_KIND: usize = 6;

/// A random placement: cell size and origin.
fn placement() -> impl Strategy<Value = (f64, DVec2)> {
    (prop_oneof![Just(1.0), 0.1f64..3.0], -50.0f64..50.0, -50.0f64..50.0)
        .prop_map(|(s, x, y)| (s, DVec2::new(x, y)))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn naive_tracer_agrees_with_brute_force_in_every_mode(
        width in 1usize..6,
        height in 1usize..6,
        max_columns in 1usize..=8,
        (cell_size, origin) in placement(),
        seed in any::<u64>(),
        t_max_fraction in prop_oneof![0.05f64..0.95, 1.05f64..1.5],
    ) {
        let mut rng = Rng::new(seed);
        let map = Arc::new(random_mlhm(&mut rng, width, height, max_columns, cell_size));
        let tracer = MlhmNaiveTracer::new(map.clone(), origin);
        for i in 0..MLHM_RAY_KINDS.len() * RAYS_PER_KIND {
            let kind = MLHM_RAY_KINDS[i % MLHM_RAY_KINDS.len()];
            let ray = random_ray(&mut rng, &map, origin, kind);
            for mode in MlhmMode::ALL {
                let hit = tracer.intersect_mode(&ray, mode);
                let expected = first_hit(&map, origin, mode, &ray);
                prop_assert!(agree(hit.map(|h| h.hit.t), expected.map(|e| e.0), 1e-5),
                    "{mode} {kind:?} {ray:?}: tracer {hit:?} brute force {expected:?}");
                if let (Some(h), Some((_, material))) = (hit, expected) {
                    prop_assert_eq!(h.material, material, "{} {:?} {:?}: {:?}", mode, kind, ray, h);
                    prop_assert!((h.hit.normal.length() - 1.0).abs() < 1e-9, "{:?}", h);
                    prop_assert!(h.hit.normal.dot(ray.dir) <= 0.0, "normal faces the ray {:?}", h);
                    prop_assert!((h.hit.position - ray.at(h.hit.t)).length() < 1e-9);
                    let (cx, cy) = h.cell;
                    prop_assert!(h.column < map.layer_count(cx, cy));
                }
                // Shadow rays: a finite range, judged against the brute force's first hit.
                let reach = expected.map(|e| e.0).unwrap_or(1.0).max(1e-3);
                let shadow = ray.with_range(ray.t_min, reach * t_max_fraction);
                let blocked = first_hit(&map, origin, mode, &shadow).is_some();
                prop_assert_eq!(tracer.occluded_mode(&shadow, mode), blocked,
                    "{} shadow {:?} {:?}", mode, kind, shadow);
            }
            // As a Tracer, the default mode is the visible surface.
            let visible = tracer.intersect_mode(&ray, MlhmMode::SolidsWater).map(|h| h.hit);
            prop_assert_eq!(tracer.intersect(&ray), visible);
        }
    }

    #[test]
    fn rays_inside_water_leave_it_where_the_brute_force_says(
        width in 1usize..5,
        height in 1usize..5,
        max_columns in 1usize..=8,
        (cell_size, origin) in placement(),
        seed in any::<u64>(),
    ) {
        let mut rng = Rng::new(seed);
        let map = Arc::new(random_mlhm(&mut rng, width, height, max_columns, cell_size));
        let tracer = MlhmNaiveTracer::new(map.clone(), origin).with_mode(MlhmMode::SolidsAir);
        for _ in 0..24 {
            let ray = random_ray(&mut rng, &map, origin, MlhmRayKind::InWater);
            let hit = tracer.intersect_mode(&ray, MlhmMode::SolidsAir);
            let expected = first_hit(&map, origin, MlhmMode::SolidsAir, &ray);
            prop_assert!(agree(hit.map(|h| h.hit.t), expected.map(|e| e.0), 1e-5),
                "{ray:?}: tracer {hit:?} brute force {expected:?}");
            prop_assert_eq!(hit.map(|h| h.material), expected.map(|e| e.1));
            prop_assert_eq!(tracer.intersect(&ray), hit.map(|h| h.hit));
        }
    }

    #[test]
    fn single_column_map_is_hit_like_the_height_field_boxes(
        width in 1usize..7,
        height in 1usize..7,
        (cell_size, origin) in placement(),
        seed in any::<u64>(),
    ) {
        let mut rng = Rng::new(seed);
        let map = Arc::new(random_mlhm(&mut rng, width, height, 1, cell_size));
        let tracer = MlhmNaiveTracer::new(map.clone(), origin);
        let geometry = GridGeometry { dx: cell_size, dy: cell_size, z_scale: 1.0, origin };
        for mode in [MlhmMode::Solids, MlhmMode::SolidsWater] {
            let solids = mode == MlhmMode::Solids;
            let top = |c: MlhmColumn| if solids { c.solid_top() } else { c.water_top() };
            let samples = (0..width * height).map(|i| top(map.column(i % width, i / width, 0)));
            let field = HeightField::new(width, height, samples.collect(), geometry).unwrap();
            let max = field.max_sample() as f64;
            let naive = NaiveTracer::new(Arc::new(field), Surface::Boxes);
            for _ in 0..40 {
                // From above the highest top, over the footprint: such a ray meets a column
                // before it could sink below the field's lowest sample.
                let (u, v) = (rng.range(0.0, width as f64), rng.range(0.0, height as f64));
                let p = origin + DVec2::new(u, v) * cell_size;
                let mut d = rng.unit();
                d.z = if rng.chance(0.1) { -1.0 } else { -d.z.abs() };
                let ray = Ray::new(p.extend(max + rng.range(0.01, 3.0)), d.normalize());
                let m = tracer.intersect_mode(&ray, mode).map(|h| h.hit);
                let f = naive.intersect(&ray);
                prop_assert!(agree(m.map(|h| h.t), f.map(|h| h.t), 1e-12),
                    "{mode} {ray:?}: mlhm {m:?} height field {f:?}");
                if let (Some(m), Some(f)) = (m, f) {
                    prop_assert!((m.normal - f.normal).length() < 1e-12,
                        "{mode} {ray:?}: {m:?} {f:?}");
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn any_ray_is_answered_without_panicking(
        origin in prop::array::uniform3(prop_oneof![any::<f64>(), -5.0f64..5.0]),
        dir in prop::array::uniform3(prop_oneof![any::<f64>(), -1.0f64..1.0, Just(0.0)]),
        range in prop::array::uniform2(prop_oneof![any::<f64>(), 0.0f64..10.0]),
    ) {
        let t = arch();
        let ray = Ray::new(DVec3::from(origin), DVec3::from(dir)).with_range(range[0], range[1]);
        for mode in MlhmMode::ALL {
            let hit = t.intersect_mode(&ray, mode);
            if let Some(h) = hit {
                prop_assert!(h.hit.t >= ray.t_min && h.hit.t <= ray.t_max, "{:?}", h);
            }
            // A shadow ray is blocked exactly where the same ray finds a first hit.
            prop_assert_eq!(t.occluded_mode(&ray, mode), hit.is_some(), "{}", mode);
        }
    }
}

/// A 3 x 1 map: ground; an arch over a cave with a pond in it; ground again.
fn arch() -> MlhmNaiveTracer {
    let inf = f32::INFINITY;
    let mut map = Mlhm::new(3, 1, 3, 1.0).unwrap();
    map.set_cell(0, 0, &[MlhmColumn::new(1.0, 0.0, 0.0, inf)]).unwrap();
    map.set_cell(
        1,
        0,
        &[MlhmColumn::new(0.5, 0.25, 0.5, 3.0), MlhmColumn::new(4.0, 0.5, 0.0, inf)],
    )
    .unwrap();
    map.set_cell(2, 0, &[MlhmColumn::new(1.0, 0.0, 0.0, inf)]).unwrap();
    MlhmNaiveTracer::new(Arc::new(map), DVec2::ZERO)
}

#[test]
fn ray_from_inside_the_cave_hits_the_pond_and_the_arch() {
    let t = arch();
    let o = DVec3::new(1.5, 0.5, 2.0);
    let down = t.intersect_mode(&Ray::new(o, -DVec3::Z), MlhmMode::SolidsWater).unwrap();
    assert_eq!((down.hit.t, down.material, down.hit.normal), (0.75, MlhmMaterial::Water, DVec3::Z));
    let up = t.intersect_mode(&Ray::new(o, DVec3::Z), MlhmMode::Solids).unwrap();
    assert_eq!(
        (up.hit.t, up.material, up.column, up.hit.normal),
        (1.0, MlhmMaterial::Bedrock, 1, -DVec3::Z)
    );
    // Out of the cave sideways, past the low ground beside it.
    assert!(t.intersect_mode(&Ray::new(o, DVec3::X), MlhmMode::Solids).is_none());
    let west = t.intersect_mode(&Ray::new(DVec3::new(1.5, 0.5, 0.9), -DVec3::X), MlhmMode::Solids);
    let west = west.unwrap();
    assert_eq!((west.hit.t, west.cell, west.hit.normal), (0.5, (0, 0), DVec3::X));
}

#[test]
fn ray_under_water_leaves_through_the_surface_or_meets_the_ground() {
    let t = arch();
    let o = DVec3::new(1.5, 0.5, 1.0);
    let up = t.intersect_mode(&Ray::new(o, DVec3::Z), MlhmMode::SolidsAir).unwrap();
    assert_eq!(
        (up.hit.t, up.material, up.column, up.hit.normal),
        (0.25, MlhmMaterial::Air, 0, -DVec3::Z)
    );
    let down = t.intersect_mode(&Ray::new(o, -DVec3::Z), MlhmMode::SolidsAir).unwrap();
    assert_eq!((down.hit.t, down.material), (0.25, MlhmMaterial::Sand));
    // Sideways the pond is walled by the ground of the next cells, whose top is at 1 m.
    let side = t.intersect_mode(&Ray::new(o, DVec3::X), MlhmMode::SolidsAir).unwrap();
    assert_eq!((side.hit.t, side.cell, side.material), (0.5, (2, 0), MlhmMaterial::Bedrock));
    // A ray that starts in the air is out of the water at once.
    let air = Ray::new(DVec3::new(1.5, 0.5, 2.0), DVec3::X);
    let hit = t.intersect_mode(&air, MlhmMode::SolidsAir).unwrap();
    assert_eq!((hit.hit.t, hit.material), (0.0, MlhmMaterial::Air));
    assert_eq!(hit.hit.normal, -DVec3::X);
}

#[test]
fn rays_starting_inside_solid_hit_at_t_min() {
    let t = arch();
    let ray = Ray::new(DVec3::new(0.5, 0.5, -10.0), DVec3::new(1.0, 0.0, 1.0)).with_range(0.5, 9.0);
    for mode in MlhmMode::ALL {
        let hit = t.intersect_mode(&ray, mode).unwrap();
        assert_eq!((hit.hit.t, hit.material), (0.5, MlhmMaterial::Bedrock), "{mode}");
    }
    assert!(t.occluded(&ray));
    // Rays below the map, outside its footprint, miss: the columns reach down only inside it.
    assert!(!t.occluded(&Ray::new(DVec3::new(-0.5, 0.5, -10.0), -DVec3::X)));
}
