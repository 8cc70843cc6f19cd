//! The MLHM renderer's light behaves as section 4.6 of Nilles & Müller (2025) says: shadow
//! rays darken what a wall hides from the sun, the geometric AO leaves open ground alone and
//! darkens a trench, deep water absorbs red first, and the picture does not depend on the
//! number of threads.

use relief_core::{Camera, DVec2, DVec3, Mlhm, MlhmColumn};
use relief_shade::mlhm::{render_mlhm, MlhmPreset, MlhmShading};
use relief_shade::Sun;
use relief_trace::MlhmHierarchyTracer;
use std::sync::Arc;

const INF: f32 = f32::INFINITY;

/// A `size` x `size` map of 1 m cells of bedrock at 1 m, with `cells` replaced.
fn map_with(size: usize, cells: &[((usize, usize), Vec<MlhmColumn>)]) -> Arc<Mlhm> {
    let mut map = Mlhm::new(size, size, 2, 1.0).unwrap();
    for y in 0..size {
        for x in 0..size {
            map.set_cell(x, y, &[MlhmColumn::new(1.0, 0.0, 0.0, INF)]).unwrap();
        }
    }
    for (cell, columns) in cells {
        map.set_cell(cell.0, cell.1, columns).unwrap();
    }
    Arc::new(map)
}

/// The radiance of the one pixel looking straight down at world `(x, y)` from 30 m.
fn radiance_down(map: &Arc<Mlhm>, x: f64, y: f64, shading: &MlhmShading) -> DVec3 {
    let tracer = MlhmHierarchyTracer::new(map.clone(), DVec2::ZERO);
    let camera =
        Camera::look_at(DVec3::new(x, y, 30.0), DVec3::new(x, y, 0.0), DVec3::Y, 0.01, 1, 1)
            .unwrap();
    let image = render_mlhm(&tracer, &camera, shading, &|_| {}).unwrap();
    DVec3::from(image.radiance[0].map(f64::from))
}

/// The mid preset with the sun in the east, 30 degrees up.
fn mid() -> MlhmShading {
    let mut shading = MlhmShading::new(MlhmPreset::Mid);
    shading.sun = Sun { azimuth_deg: 90.0, elevation_deg: 30.0, ..shading.sun };
    shading
}

#[test]
fn a_wall_shadows_the_ground_west_of_it_only() {
    // A wall 10 m high along x = 10 (cells (10, y)).
    let wall: Vec<_> =
        (0..20).map(|y| ((10, y), vec![MlhmColumn::new(11.0, 0.0, 0.0, INF)])).collect();
    let map = map_with(20, &wall);
    let mut unshadowed = mid();
    unshadowed.quality.shadows = false;
    // West of the wall, within its shadow (10 m / tan 30 = 17 m long): darker with shadows.
    let (lit, shadowed) =
        (radiance_down(&map, 5.5, 10.5, &unshadowed), radiance_down(&map, 5.5, 10.5, &mid()));
    assert!(shadowed.x < 0.5 * lit.x, "{shadowed} vs {lit}");
    // East of the wall, in the sun: the same either way.
    assert_eq!(
        radiance_down(&map, 15.5, 10.5, &mid()),
        radiance_down(&map, 15.5, 10.5, &unshadowed)
    );
}

#[test]
fn ambient_occlusion_leaves_open_ground_alone_and_darkens_a_trench() {
    // A trench one cell wide and 3 m deep along x = 10.
    let trench: Vec<_> =
        (0..20).map(|y| ((10, y), vec![MlhmColumn::new(-2.0, 0.0, 0.0, INF)])).collect();
    let map = map_with(20, &trench);
    let mut shading = mid();
    shading.sun.irradiance = 0.0;
    let mut no_ao = shading.clone();
    no_ao.quality.ao_radius = None;
    let open = radiance_down(&map, 4.5, 10.5, &shading);
    assert_eq!(open, radiance_down(&map, 4.5, 10.5, &no_ao), "the cube above open ground is empty");
    let (dark, bright) =
        (radiance_down(&map, 10.5, 10.5, &shading), radiance_down(&map, 10.5, 10.5, &no_ao));
    assert!(dark.x < 0.5 * bright.x, "{dark} vs {bright}");
    // The larger cube of the max preset reaches more of the trench walls.
    let mut wide = shading.clone();
    wide.quality.ao_radius = Some(2.0);
    assert!(radiance_down(&map, 10.5, 10.5, &wide).x < dark.x);
}

#[test]
fn deep_water_absorbs_red_more_than_blue() {
    // Bedrock at 1 m under 0.5 m of water at (5, 5) and under 20 m of water at (14, 14), each
    // in a pool one cell wide walled by the map's ground raised to 30 m around it.
    let mut cells = Vec::new();
    for y in 0..20 {
        for x in 0..20 {
            cells.push(((x, y), vec![MlhmColumn::new(30.0, 0.0, 0.0, INF)]));
        }
    }
    cells.push(((5, 5), vec![MlhmColumn::new(1.0, 0.0, 0.5, INF)]));
    cells.push(((14, 14), vec![MlhmColumn::new(1.0, 0.0, 20.0, INF)]));
    let map = map_with(20, &cells);
    let mut shading = mid();
    shading.quality.shadows = false;
    shading.quality.ao_radius = None;
    // High, but away from the mirror direction: no glint on the water.
    shading.sun.elevation_deg = 60.0;
    let shallow = radiance_down(&map, 5.5, 5.5, &shading);
    let deep = radiance_down(&map, 14.5, 14.5, &shading);
    assert!(deep.x < shallow.x && deep.z < shallow.z, "{deep} vs {shallow}");
    assert!(deep.x / deep.z < shallow.x / shallow.z, "bluer when deep: {deep} vs {shallow}");
}

#[test]
fn the_picture_does_not_depend_on_the_thread_count() {
    let map = Arc::new(relief_sim::carved_scene(relief_sim::CarvedScene::Combined, 32, 4).unwrap());
    let tracer = MlhmHierarchyTracer::new(map, DVec2::ZERO);
    let camera = Camera::look_at(
        DVec3::new(-20.0, -30.0, 60.0),
        DVec3::new(128.0, 128.0, 0.0),
        DVec3::Z,
        45.0,
        40,
        30,
    )
    .unwrap();
    let shading = MlhmShading::new(MlhmPreset::Max);
    let render = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| render_mlhm(&tracer, &camera, &shading, &|_| {}).unwrap())
    };
    let (one, two) = (render(1), render(2));
    assert_eq!(one, two);
    assert!(one.counts.rays() > 40 * 30);
}
