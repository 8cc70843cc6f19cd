//! Property tests of the hybrid renderer's cells and heuristic: an edit then an update equals
//! a rebuild, bit for bit; every point of the solid an exact tracer hits lies in some proxy
//! box; and the heuristic never culls, nor projects away from its pixel, a box holding a
//! pixel's exact hit.

mod common;

use common::scenes::{ray_for, terrain, ALL_KINDS};
use proptest::prelude::*;
use relief_core::{Camera, DVec3, HeightField, SampleRegion, Surface};
use relief_trace::hybrid::{project_box, CellChoice, HybridCells, HybridHeuristic, HybridParams};
use relief_trace::{NaiveTracer, Tracer};
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
    fn an_edit_then_an_update_equals_a_rebuild(
        field in terrain(),
        n in 2usize..=9,
        edits in prop::collection::vec((prop::array::uniform4(0.0f64..1.0), -30.0f32..30.0), 1..5),
        whole in any::<bool>(),
    ) {
        for surface in Surface::ALL {
            let mut field = field.clone();
            let mut cells = HybridCells::new(&field, surface, n).unwrap();
            for (u, delta) in &edits {
                let (w, h) = (field.width() as f64, field.height() as f64);
                let (c0, r0) = ((u[0] * w) as usize, (u[1] * h) as usize);
                let (c1, r1) = (c0 + 1 + (u[2] * w / 3.0) as usize, r0 + 1 + (u[3] * h / 3.0) as usize);
                let region = SampleRegion::new(c0, r0, c1, r1);
                // A bump that lifts some samples and lowers others, past the range or not.
                let changed = field
                    .edit_region(region, |c, r, v| v + delta * (((c + 2 * r) % 3) as f32 - 0.5))
                    .unwrap();
                cells.update(&field, changed);
                prop_assert_eq!(&cells, &HybridCells::new(&field, surface, n).unwrap(), "{} {:?}", surface, changed);
            }
            if whole {
                let samples = field.samples().iter().map(|v| 0.5 * v + 1.0).collect();
                field.replace_samples(samples).unwrap();
                cells.update(&field, SampleRegion::whole(field.width(), field.height()));
                prop_assert_eq!(&cells, &HybridCells::new(&field, surface, n).unwrap());
            }
        }
    }

    #[test]
    fn every_exact_hit_lies_in_a_proxy_box(
        field in terrain(),
        n in 2usize..=9,
        numbers in prop::collection::vec(prop::array::uniform8(0.001f64..0.999), ALL_KINDS.len() * 3),
    ) {
        let field = Arc::new(field);
        for surface in Surface::ALL {
            let mut cells = HybridCells::new(&field, surface, n).unwrap();
            let naive = NaiveTracer::new(field.clone(), surface);
            let floor = field.min_sample() as f64 * field.geometry().z_scale;
            for (i, u) in numbers.iter().enumerate() {
                let ray = ray_for(&field, ALL_KINDS[i % ALL_KINDS.len()], *u);
                // From below the lowest sample the solid's bottom face is in view.
                cells.set_floor_everywhere(ray.origin.z < floor);
                // A ray starting inside the solid hits where it starts, in the solid's interior
                // that no box holds (the renderer tests the eye itself).
                if let Some(hit) = naive.intersect(&ray).filter(|h| h.t > ray.t_min) {
                    prop_assert!(!cells_holding(&cells, &field, hit.position).is_empty(),
                        "{surface} n {n}: {hit:?} of {ray:?} lies in no box");
                }
            }
        }
    }

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
            cells.set_floor_everywhere(cells.bottom_visible(&camera));
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
