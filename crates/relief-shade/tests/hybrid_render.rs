//! The hybrid renderer against the exact tracer: with the exact far field every pixel equals
//! the mipmap tracer's (the near field rasterized, the far field traced from the nearest proxy
//! box); with levels of precision the rasterized pixels still do.

use proptest::prelude::*;
use relief_core::{Camera, DVec3, GridGeometry, HeightField, Surface};
use relief_shade::hybrid::HybridParams;
use relief_shade::{render_gbuffer, FarField, GBuffer, HybridRenderer, PixelSource};
use relief_trace::{MipmapTracer, NaiveTracer};
use std::sync::Arc;

/// A smooth random terrain of `n x n` samples with some relief.
fn terrain(n: usize, seed: u64) -> HeightField {
    let mut s = seed;
    let mut next = move || {
        s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (s >> 40) as f64 / (1u64 << 24) as f64
    };
    let (a, b, c) = (next() * 0.5 + 0.1, next() * 0.5 + 0.1, next() * 6.0);
    let samples = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            ((x * a).sin() * (y * b).cos() * c + next() * 0.8 + 0.05 * x) as f32
        })
        .collect();
    HeightField::new(n, n, samples, GridGeometry::unit()).unwrap()
}

/// Pixels where the two depth images disagree: one hits and the other not, or the distances
/// differ by more than `rel` relative.
fn disagreements(a: &GBuffer, b: &GBuffer, rel: f32) -> usize {
    a.distance
        .iter()
        .zip(&b.distance)
        .filter(|(&x, &y)| {
            if x.is_finite() != y.is_finite() {
                return true;
            }
            x.is_finite() && (x - y).abs() > rel * x.abs().max(y.abs()).max(1.0)
        })
        .count()
}

fn camera(n: f64, eye: (f64, f64, f64), target: (f64, f64), w: u32, h: u32) -> Camera {
    Camera::look_at(
        DVec3::new(eye.0 * n, eye.1 * n, eye.2),
        DVec3::new(target.0 * n, target.1 * n, 0.0),
        DVec3::Z,
        60.0,
        w,
        h,
    )
    .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    #[test]
    fn the_exact_far_field_equals_the_exact_tracer(
        seed in 0u64..1000,
        surface in prop_oneof![Just(Surface::Triangles), Just(Surface::Boxes)],
        cell in prop_oneof![Just(4usize), Just(9), Just(16)],
        threshold in prop_oneof![Just(0.5f64), Just(5.0), Just(70.0)],
        eye in (-0.3f64..1.3, -0.3f64..1.3, -15.0f64..25.0),
        target in (0.0f64..1.0, 0.0f64..1.0),
    ) {
        let n = 40;
        let field = Arc::new(terrain(n, seed));
        let bounds = field.world_bounds(surface);
        let cam = camera(n as f64, eye, target, 96, 64);
        let params = HybridParams { cell, threshold, ..HybridParams::default() };
        let mut hybrid = HybridRenderer::new(field.clone(), surface, params, FarField::Exact).unwrap();
        let mut gbuffer = GBuffer::new(96, 64).unwrap();
        let mut sources = Vec::new();
        hybrid.render_into(&cam, &bounds, &mut gbuffer, Some(&mut sources)).unwrap();
        let naive = NaiveTracer::new(field, surface);
        let (reference, _) = render_gbuffer(&naive, &cam, &bounds, &|_| {}).unwrap();
        let wrong = disagreements(&gbuffer, &reference, 1e-4);
        prop_assert!(wrong <= 2, "{wrong} pixels differ from the exact tracer");
        prop_assert_eq!(sources.len(), 96 * 64);
    }
}

#[test]
fn rasterized_pixels_equal_the_exact_tracer_and_levels_stay_close() {
    let n = 64;
    let field = Arc::new(terrain(n, 7));
    let surface = Surface::Triangles;
    let bounds = field.world_bounds(surface);
    let cam = camera(n as f64, (0.1, 0.05, 9.0), (0.9, 0.9), 160, 100);
    let params = HybridParams { cell: 9, threshold: 5.0, ..HybridParams::default() };
    let mut hybrid = HybridRenderer::new(field.clone(), surface, params, FarField::Lop).unwrap();
    let mut gbuffer = GBuffer::new(160, 100).unwrap();
    let mut sources = Vec::new();
    let stats = hybrid.render_into(&cam, &bounds, &mut gbuffer, Some(&mut sources)).unwrap();
    assert!(stats.mesh_cells > 0 && stats.ray_cast_cells.iter().sum::<usize>() > 0, "{stats:?}");
    let exact = MipmapTracer::new(field, surface);
    let (reference, _) = render_gbuffer(&exact, &cam, &bounds, &|_| {}).unwrap();
    let mesh_pixels: Vec<usize> =
        (0..sources.len()).filter(|&k| sources[k] == PixelSource::Mesh).collect();
    assert!(mesh_pixels.len() > 100, "{} mesh pixels", mesh_pixels.len());
    for &k in &mesh_pixels {
        let (a, b) = (gbuffer.distance[k], reference.distance[k]);
        assert!((a - b).abs() <= 1e-4 * b.abs(), "pixel {k}: mesh {a}, exact {b}");
    }
    let far = (0..sources.len()).filter(|&k| matches!(sources[k], PixelSource::RayCast(_))).count();
    assert!(far > 100, "{far} ray-cast pixels");
}

#[test]
fn an_edit_then_a_render_equals_a_fresh_renderer() {
    let n = 48;
    for far in [FarField::Lop, FarField::Exact] {
        let field = terrain(n, 3);
        let surface = Surface::Triangles;
        let bounds = field.world_bounds(surface);
        let cam = camera(n as f64, (0.05, 0.1, 10.0), (0.8, 0.9), 120, 80);
        let params = HybridParams { cell: 9, threshold: 3.0, ..HybridParams::default() };
        let mut edited =
            HybridRenderer::new(Arc::new(field.clone()), surface, params, far).unwrap();
        let mut gbuffer = GBuffer::new(120, 80).unwrap();
        // A first frame fills the mesh cache, which the edit must then invalidate.
        edited.render_into(&cam, &bounds, &mut gbuffer, None).unwrap();
        let region = relief_core::SampleRegion::new(18, 20, 30, 29);
        edited.edit(|f| f.edit_region(region, |c, r, v| v + 0.3 * ((c + r) % 3) as f32)).unwrap();
        edited.render_into(&cam, &bounds, &mut gbuffer, None).unwrap();

        let mut changed = field;
        changed.edit_region(region, |c, r, v| v + 0.3 * ((c + r) % 3) as f32).unwrap();
        let mut fresh = HybridRenderer::new(Arc::new(changed), surface, params, far).unwrap();
        let mut expected = GBuffer::new(120, 80).unwrap();
        fresh.render_into(&cam, &bounds, &mut expected, None).unwrap();
        assert!(gbuffer == expected, "{far}: the edited renderer's frame differs");
        // The edit moved something on screen.
        let mut before =
            HybridRenderer::new(Arc::new(terrain(n, 3)), surface, params, far).unwrap();
        let mut unedited = GBuffer::new(120, 80).unwrap();
        before.render_into(&cam, &bounds, &mut unedited, None).unwrap();
        assert!(unedited != expected, "{far}: the edit changed nothing visible");
    }
}
