//! The exact far field of the hybrid renderer: the exact first hit between the nearest
//! ray-cast box and the rasterized near field's depth, against the naive tracer; and a whole
//! hybrid image with it (the mesh cells drawn by an exact stand-in for the rasterizer) equal
//! to the exact tracer's on every pixel.

mod common;

use common::scenes::{agree, ray_for, terrain, ALL_KINDS};
use proptest::prelude::*;
use relief_core::Surface;
use relief_trace::hybrid::{exact_far_hit, exact_far_hits};
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
