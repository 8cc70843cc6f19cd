//! Property tests of the hybrid renderer's cells: an edit then an update equals a rebuild,
//! bit for bit; every point of the solid an exact tracer hits lies in some proxy box.
//! (relief-shade's tests/hybrid_heuristic.rs checks the heuristic and the box projection.)

mod common;

use common::scenes::{ray_for, terrain, ALL_KINDS};
use proptest::prelude::*;
use relief_core::{DVec3, HeightField, SampleRegion, Surface};
use relief_trace::hybrid::HybridCells;
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
}
