//! The exact far field of the hybrid renderer: the exact first hit between the nearest
//! ray-cast box and the rasterized near field's depth, against the naive tracer; and a whole
//! hybrid image with it (the mesh cells drawn by an exact stand-in for the rasterizer) equal
//! to the exact tracer's on every pixel.

mod common;

use common::scenes::{agree, ray_for, terrain, ALL_KINDS};
use proptest::prelude::*;
use relief_core::{Camera, DVec3, Surface};
use relief_trace::hybrid::{
    box_entry, exact_far_hit, exact_far_hits, project_box, CellChoice, HybridCells,
    HybridHeuristic, HybridParams,
};
use relief_trace::{MipmapTracer, NaiveTracer, Tracer};
use std::sync::Arc;

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn the_far_field_is_the_exact_hit_within_its_range(
        field in terrain(),
        numbers in prop::collection::vec(prop::array::uniform8(0.001f64..0.999), ALL_KINDS.len() * 2),
        fractions in prop::collection::vec((0.0f64..1.0, 0.0f64..2.0, any::<bool>()), ALL_KINDS.len() * 2),
    ) {
        let field = Arc::new(field);
        for surface in Surface::ALL {
            let naive = NaiveTracer::new(field.clone(), surface);
            let mipmap = MipmapTracer::new(field.clone(), surface);
            let (mut rays, mut t0s, mut t1s, mut singles) = (vec![], vec![], vec![], vec![]);
            for (i, (u, &(f0, f1, open))) in numbers.iter().zip(&fractions).enumerate() {
                let ray = ray_for(&field, ALL_KINDS[i % ALL_KINDS.len()], *u);
                let full = naive.intersect(&ray);
                if let Some(hit) = full {
                    // Bounds around the true first hit, as the renderer has them: the same hit.
                    let t1 = if open { f64::INFINITY } else { hit.t * (1.0 + f1) };
                    let far = exact_far_hit(&mipmap, &ray, hit.t * f0, t1);
                    prop_assert!(agree(far.map(|h| h.t), Some(hit.t), 1e-5),
                        "{surface} {ray:?} [{}, {t1}]: {far:?} vs {hit:?}", hit.t * f0);
                }
                // Any range: the naive tracer on the restricted ray.
                let reach = full.map_or(10.0, |h| h.t.max(1e-3));
                let (t0, t1) = (reach * 2.0 * f0, if open { f64::INFINITY } else { reach * f1 });
                let far = exact_far_hit(&mipmap, &ray, t0, t1);
                let want = if t0 <= t1 { naive.intersect(&ray.with_range(t0, t1)) } else { None };
                prop_assert!(agree(far.map(|h| h.t), want.map(|h| h.t), 1e-5),
                    "{surface} {ray:?} [{t0}, {t1}]: {far:?} vs {want:?}");
                rays.push(ray);
                t0s.push(t0);
                t1s.push(t1);
                singles.push(far);
            }
            // In packets, the same hits.
            let mut batch = vec![None; rays.len()];
            exact_far_hits(&mipmap, &rays, &t0s, &t1s, &mut batch);
            for (k, (b, s)) in batch.iter().zip(&singles).enumerate() {
                prop_assert!(agree(b.map(|h| h.t), s.map(|h| h.t), 1e-9), "{surface} ray {k}: {b:?} vs {s:?}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// The renderer's pass, with the parts of this module: cells chosen by the heuristic,
    /// found per pixel by projecting their boxes; a mesh cell's depth is the exact surface
    /// inside its box (what the rasterizer draws), the far field the exact hit between the
    /// nearest ray-cast box and the mesh depth. Every pixel equals the exact tracer.
    #[test]
    fn with_the_exact_far_field_every_pixel_equals_the_exact_tracer(
        field in terrain(),
        n in 2usize..=9,
        u in prop::array::uniform8(0.0f64..1.0),
        threshold in prop_oneof![0.01f64..1.0, 1.0f64..300.0],
    ) {
        let field = Arc::new(field);
        let b = field.world_bounds(Surface::Boxes);
        let size = (b.max - b.min).max_element().max(1.0);
        let eye = b.center() + DVec3::new(u[0] - 0.5, u[1] - 0.5, 0.05 + u[2]) * 2.0 * size;
        let target = DVec3::new(
            b.min.x + u[3] * (b.max.x - b.min.x),
            b.min.y + u[4] * (b.max.y - b.min.y),
            b.min.z + u[6] * (b.max.z - b.min.z),
        );
        let Ok(camera) = Camera::look_at(eye, target, DVec3::Z, 20.0 + 80.0 * u[5], 16, 12) else {
            return Ok(());
        };
        let heuristic =
            HybridHeuristic::new(HybridParams { cell: n, threshold, ..HybridParams::default() }).unwrap();
        for surface in Surface::ALL {
            let exact = MipmapTracer::new(field.clone(), surface);
            let mut cells = HybridCells::new(&field, surface, n).unwrap();
            cells.set_floor_everywhere(cells.bottom_visible(&camera));
            let choices = heuristic.choose(&cells, &camera);
            let rects: Vec<_> = (0..cells.len())
                .map(|k| cells.proxy_box(k).and_then(|b| project_box(&camera, &b).pixels(16, 12)))
                .collect();
            for j in 0..camera.height() {
                for i in 0..camera.width() {
                    let ray = camera.ray(i, j);
                    let want = exact.intersect(&ray);
                    if want.is_some_and(|h| h.t == 0.0) {
                        continue; // the eye inside the solid: no box holds it
                    }
                    let (mut mesh, mut t0) = (f64::INFINITY, f64::INFINITY);
                    for (k, rect) in rects.iter().enumerate() {
                        let drawn = rect.is_some_and(|r| (r.i0..=r.i1).contains(&i) && (r.j0..=r.j1).contains(&j));
                        let entry = box_entry(&cells, &field, k, &ray);
                        match (choices[k], drawn, entry) {
                            (CellChoice::Mesh, true, Some((enter, exit))) => {
                                // A wall on the box's face (the side of a hole in the cell) may
                                // round a hair past the exit the box clip computes.
                                let slack = 1e-9 * exit.abs().max(1.0);
                                if let Some(hit) = exact.intersect(&ray.with_range(enter - slack, exit + slack)) {
                                    mesh = mesh.min(hit.t);
                                }
                            }
                            (CellChoice::RayCast { .. }, true, Some((enter, _))) => t0 = t0.min(enter),
                            _ => {}
                        }
                    }
                    let far = exact_far_hit(&exact, &ray, t0, mesh).map_or(f64::INFINITY, |h| h.t);
                    let got = Some(mesh.min(far)).filter(|t| t.is_finite());
                    prop_assert!(agree(got, want.map(|h| h.t), 1e-9),
                        "{surface} n {n} pixel ({i}, {j}): hybrid {got:?}, exact {want:?}");
                }
            }
        }
    }
}
