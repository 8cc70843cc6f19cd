//! The MLHM hierarchy on the 1024 x 1024 RiversRain scene (4 layer slots): building and
//! rebuilding its f32 and f16 bounds, the padded build (one cell of smoothing radius) against
//! the box build, and rendering primary rays with a shadow ray to the sun from each hit, for
//! both precisions and both ways of climbing back up.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec2, DVec3, Mlhm, Precision, Ray};
use relief_trace::{
    MlhmBacktrack, MlhmHierarchy, MlhmHierarchyTracer, MlhmMode, MlhmNaiveTracer, MlhmTracer,
};
use std::sync::Arc;

/// The RiversRain scene, 1024 x 1024 cells with 4 layer slots.
fn rivers_rain() -> Arc<Mlhm> {
    Arc::new(relief_sim::rivers_rain(1024, 4, relief_sim::RIVERS_RAIN_SEED).expect("the scene"))
}

/// Building the hierarchy from scratch, rebuilding it in place, and the padded build.
fn build(c: &mut Criterion) {
    let map = rivers_rain();
    let mut group = c.benchmark_group("mlhm_hierarchy_build");
    group.sample_size(10);
    for precision in [Precision::F32, Precision::F16] {
        let name = format!("{precision:?}");
        group.bench_function(BenchmarkId::new("build", &name), |b| {
            b.iter(|| MlhmHierarchy::build_with_precision(black_box(&map), precision))
        });
        let mut hierarchy = MlhmHierarchy::build_with_precision(&map, precision);
        group.bench_function(BenchmarkId::new("rebuild", &name), |b| {
            b.iter(|| hierarchy.rebuild(black_box(&map)))
        });
        let radius = map.cell_size();
        group.bench_function(BenchmarkId::new("build_padded_one_cell", &name), |b| {
            b.iter(|| MlhmHierarchy::build_padded(black_box(&map), radius, precision))
        });
    }
    group.finish();
}

/// Primary rays of a 1024 x 768 view framed as `relief render` frames it, and a shadow ray to
/// the sun from each hit, on all threads.
fn render(c: &mut Criterion) {
    let map = rivers_rain();
    let world = MlhmNaiveTracer::new(map.clone(), DVec2::ZERO).world_bounds(MlhmMode::SolidsWater);
    let camera = Camera::frame(&Aabb::new(world.min.with_z(0.0), world.max), 1024, 768)
        .expect("a camera on the scene");
    let sun = DVec3::new(1.0, 1.0, 1.2).normalize();
    let pixels: Vec<(u32, u32)> =
        (0..camera.height()).flat_map(|j| (0..camera.width()).map(move |i| (i, j))).collect();
    let pixel = |tracer: &MlhmHierarchyTracer, (i, j): (u32, u32)| {
        let hit = tracer.intersect_mode(&camera.ray(i, j), MlhmMode::SolidsWater)?;
        let shadow = Ray::new(hit.hit.position + 1e-4 * hit.hit.normal, sun);
        Some((hit, tracer.occluded_mode(&shadow, MlhmMode::Solids)))
    };
    let mut group = c.benchmark_group("mlhm_hierarchy_render_1024x768");
    group.sample_size(10);
    for precision in [Precision::F32, Precision::F16] {
        let hierarchy = MlhmHierarchy::build_with_precision(&map, precision);
        for backtrack in MlhmBacktrack::ALL {
            let tracer =
                MlhmHierarchyTracer::with_hierarchy(map.clone(), hierarchy.clone(), DVec2::ZERO)
                    .with_backtrack(backtrack);
            let id = BenchmarkId::new(format!("{precision:?}"), backtrack);
            group.bench_function(id, |b| {
                b.iter(|| pixels.par_iter().map(|&p| pixel(&tracer, p)).collect::<Vec<_>>())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, build, render);
criterion_main!(benches);
