//! Property tests of the hybrid renderer's choice per cell for a camera: the heuristic never
//! culls, nor projects away from its pixel, a box holding a pixel's exact hit; and a whole
//! image made the renderer's way with the exact far field (the mesh cells drawn by an exact
//! stand-in for the rasterizer) equals the exact tracer's on every pixel.

#[path = "../../relief-trace/tests/common/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use proptest::prelude::*;
use relief_core::{Camera, DVec3, HeightField, Surface};
use relief_shade::hybrid::{
    bottom_visible, project_box, CellChoice, HybridHeuristic, HybridParams,
};
use relief_trace::hybrid::{box_entry, exact_far_hit, HybridCells};
use relief_trace::{MipmapTracer, NaiveTracer, Tracer};
use scenes::{agree, terrain};
use std::sync::Arc;

/// The cells whose grid-space box holds world point `p`, to a relative tolerance.
fn cells_holding(cells: &HybridCells, field: &HeightField, p: DVec3) -> Vec<usize> {
    let g = field.geometry();
    let q = DVec3::new((p.x - g.origin.x) / g.dx, (p.y - g.origin.y) / g.dy, p.z / g.z_scale);
    (0..cells.len())
        .filter(|&k| {
            cells.grid_box(k).is_some_and(|b| {
                (0..3).all(|a| {
                    let tol = 1e-7 * (1.0 + q[a].abs() + b.min[a].abs() + b.max[a].abs());
                    q[a] >= b.min[a] - tol && q[a] <= b.max[a] + tol
                })
            })
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn the_heuristic_keeps_and_projects_onto_its_pixel_every_box_holding_a_hit(
        field in terrain(),
        n in 2usize..=9,
        u in prop::array::uniform8(0.0f64..1.0),
        threshold in 0.01f64..200.0,
    ) {
        let field = Arc::new(field);
        let b = field.world_bounds(Surface::Boxes);
        let size = (b.max - b.min).max_element().max(1.0);
        let eye = b.center()
            + DVec3::new(u[0] - 0.5, u[1] - 0.5, 0.1 + u[2]) * 2.0 * size;
        let target = DVec3::new(
            b.min.x + u[3] * (b.max.x - b.min.x),
            b.min.y + u[4] * (b.max.y - b.min.y),
            b.min.z,
        );
        let Ok(camera) = Camera::look_at(eye, target, DVec3::Z, 20.0 + 80.0 * u[5], 24, 16) else {
            return Ok(());
        };
        let params = HybridParams { cell: n, threshold, ..HybridParams::default() };
        let heuristic = HybridHeuristic::new(params).unwrap();
        for surface in Surface::ALL {
            let mut cells = HybridCells::new(&field, surface, n).unwrap();
            cells.set_floor_everywhere(bottom_visible(&cells, &camera));
            let choices = heuristic.choose(&cells, &camera);
            let naive = NaiveTracer::new(field.clone(), surface);
            for j in 0..camera.height() {
                for i in 0..camera.width() {
                    let Some(hit) = naive.intersect(&camera.ray(i, j)) else { continue };
                    let holding = cells_holding(&cells, &field, hit.position);
                    let seen = holding.iter().any(|&k| {
                        choices[k] != CellChoice::Culled
                            && project_box(&camera, &cells.proxy_box(k).unwrap())
                                .pixels(camera.width(), camera.height())
                                .is_some_and(|p| (p.i0..=p.i1).contains(&i) && (p.j0..=p.j1).contains(&j))
                    });
                    prop_assert!(seen, "{surface} n {n}: pixel ({i}, {j}) hit {hit:?} in cells {holding:?}");
                }
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
            cells.set_floor_everywhere(bottom_visible(&cells, &camera));
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
