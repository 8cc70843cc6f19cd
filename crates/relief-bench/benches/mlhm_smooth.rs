//! The smooth MLHM tracer on the 256 x 256 carved scene (`Combined`, 4 layer slots), framed as
//! `relief render` frames it, on one thread: 320 x 240 camera rays, and a soft shadow ray to the
//! sun from each hit, with the padded hierarchy (both ways of climbing back up) and without,
//! beside the box hierarchy tracer; and the smooth tracer's build.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use relief_core::{Aabb, Camera, DVec2, DVec3, Mlhm, Ray};
use relief_trace::{
    MlhmBacktrack, MlhmHierarchyTracer, MlhmMode, MlhmNaiveTracer, MlhmSmoothOptions,
    MlhmSmoothTracer, MlhmTracer,
};
use std::sync::Arc;

/// The carved scene and the camera rays of its 320 x 240 view.
fn scene() -> (Arc<Mlhm>, Vec<Ray>) {
    let map = Arc::new(
        relief_sim::carved_scene(relief_sim::CarvedScene::Combined, 256, 4).expect("the scene"),
    );
    let world = MlhmNaiveTracer::new(map.clone(), DVec2::ZERO).world_bounds(MlhmMode::SolidsWater);
    let camera = Camera::frame(&Aabb::new(world.min.with_z(0.0), world.max), 320, 240)
        .expect("a camera on the scene");
    let rays = (0..camera.height())
        .flat_map(|j| (0..camera.width()).map(move |i| (i, j)))
        .map(|(i, j)| camera.ray(i, j))
        .collect();
    (map, rays)
}

/// The smooth tracer's variants: with the padded hierarchy, each way back up, and without.
const VARIANTS: [(bool, MlhmBacktrack); 3] = [
    (true, MlhmBacktrack::ExitStack),
    (true, MlhmBacktrack::MissCounter),
    (false, MlhmBacktrack::ExitStack),
];

/// The name of a variant.
fn variant_name((hierarchy, backtrack): (bool, MlhmBacktrack)) -> String {
    if hierarchy {
        format!("padded hierarchy, {backtrack}")
    } else {
        "no hierarchy".into()
    }
}

/// The smooth tracer of `map` in a variant.
fn smooth(map: &Arc<Mlhm>, (hierarchy, backtrack): (bool, MlhmBacktrack)) -> MlhmSmoothTracer {
    let options = MlhmSmoothOptions { hierarchy, backtrack, ..MlhmSmoothOptions::default() };
    MlhmSmoothTracer::with_options(map.clone(), DVec2::ZERO, options).expect("valid options")
}

/// Camera rays through the box hierarchy tracer and each smooth variant, one thread.
fn camera_rays(c: &mut Criterion) {
    let (map, rays) = scene();
    let mut group = c.benchmark_group("mlhm_smooth_camera_rays_320x240");
    group.sample_size(10);
    let boxes = MlhmHierarchyTracer::new(map.clone(), DVec2::ZERO);
    group.bench_function("boxes, hierarchy", |b| {
        b.iter(|| {
            rays.iter().filter_map(|r| boxes.intersect_mode(r, MlhmMode::SolidsWater)).count()
        })
    });
    for variant in VARIANTS {
        let tracer = smooth(&map, variant);
        group.bench_function(BenchmarkId::new("smooth", variant_name(variant)), |b| {
            b.iter(|| {
                rays.iter().filter_map(|r| tracer.intersect_mode(r, MlhmMode::SolidsWater)).count()
            })
        });
    }
    group.finish();
}

/// Soft shadow rays to the sun from each camera hit, one thread.
fn shadow_rays(c: &mut Criterion) {
    let (map, rays) = scene();
    let sun = DVec3::new(1.0, 1.0, 1.2).normalize();
    let mut group = c.benchmark_group("mlhm_smooth_shadow_rays");
    group.sample_size(10);
    for variant in VARIANTS {
        let tracer = smooth(&map, variant);
        let shadows: Vec<Ray> = rays
            .iter()
            .filter_map(|r| tracer.intersect_mode(r, MlhmMode::SolidsWater))
            .map(|hit| Ray::new(hit.hit.position + 1e-4 * hit.hit.normal, sun))
            .collect();
        group.bench_function(BenchmarkId::new("smooth", variant_name(variant)), |b| {
            b.iter(|| shadows.iter().map(|s| tracer.light_visibility(s, &mut 0)).sum::<f64>())
        });
    }
    group.finish();
}

/// Building the smooth tracer (its padded hierarchy), each variant.
fn build(c: &mut Criterion) {
    let (map, _) = scene();
    let mut group = c.benchmark_group("mlhm_smooth_build");
    group.sample_size(10);
    for variant in VARIANTS {
        group.bench_function(BenchmarkId::new("smooth", variant_name(variant)), |b| {
            b.iter(|| smooth(black_box(&map), variant))
        });
    }
    group.finish();
}

criterion_group!(benches, camera_rays, shadow_rays, build);
criterion_main!(benches);
