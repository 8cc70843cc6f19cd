//! Property tests: the max-mipmap tracer agrees with the naive tracer, and the naive tracer with
//! an independent brute-force tracer, on random terrains and rays of every kind, for both
//! surfaces, for first hits and for shadow rays.

mod common;

use common::reference::first_hit;
use common::scenes::{agree, ray_for, terrain, ALL_KINDS};
use proptest::prelude::*;
use relief_core::{DVec3, HeightField, Ray, Surface};
use relief_trace::conformance::{self, Floor, NORMAL_TOLERANCE};
use relief_trace::{Hit, MipmapTracer, NaiveTracer, Tracer};
use std::sync::Arc;

const RAYS_PER_KIND: usize = 6;

/// The distinct normals of the faces the brute force meets at the ray's first hit: one on a
/// face, more on an edge or a corner where faces meet.
fn face_normals(field: &HeightField, surface: Surface, ray: &Ray) -> Vec<DVec3> {
    let hit = conformance::first_hit(field, surface, Floor::LowestSample, ray, 0.0);
    let mut distinct: Vec<DVec3> = Vec::new();
    for n in hit.map(|h| h.normals).unwrap_or_default() {
        if !distinct.iter().any(|d| (*d - n).length() < NORMAL_TOLERANCE) {
            distinct.push(n);
        }
    }
    distinct
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    #[test]
    fn mipmap_naive_and_brute_force_agree(
        field in terrain(),
        numbers in prop::collection::vec(prop::array::uniform8(0.001f64..0.999), ALL_KINDS.len() * RAYS_PER_KIND),
        t_max_fraction in prop_oneof![0.05f64..0.95, 1.05f64..1.5],
    ) {
        let field = Arc::new(field);
        for surface in Surface::ALL {
            let naive = NaiveTracer::new(field.clone(), surface);
            let mipmap = MipmapTracer::new(field.clone(), surface);
            for (i, u) in numbers.iter().enumerate() {
                let kind = ALL_KINDS[i % ALL_KINDS.len()];
                let ray = ray_for(&field, kind, *u);
                let n = naive.intersect(&ray);
                let m = mipmap.intersect(&ray);
                let b = first_hit(&field, surface, &ray);
                prop_assert!(agree(n.map(|h| h.t), m.map(|h| h.t), 1e-5),
                    "{surface} {kind:?} {ray:?}: naive {n:?} mipmap {m:?}");
                prop_assert!(agree(n.map(|h| h.t), b, 1e-5),
                    "{surface} {kind:?} {ray:?}: naive {n:?} brute force {b:?}");
                // Normals wherever both tracers hit: each is the normal of a face the brute force
                // meets there, and on a single face (not an edge or corner) the two agree.
                if let (Some(hn), Some(hm)) = (n, m) {
                    let faces = face_normals(&field, surface, &ray);
                    let on_a_face = |h: &Hit| faces.iter().any(|f| (h.normal - *f).length() < NORMAL_TOLERANCE);
                    prop_assert!(on_a_face(&hn) && on_a_face(&hm),
                        "{surface} {kind:?}: a normal of no face hit {hn:?} {hm:?}, faces {faces:?}");
                    prop_assert!(faces.len() > 1 || (hn.normal - hm.normal).length() < NORMAL_TOLERANCE,
                        "{surface} {kind:?}: normals differ on one face {hn:?} {hm:?}");
                }
                // Shadow rays: a finite range, judged against the brute force's first hit.
                let reach = b.or(n.map(|h| h.t)).unwrap_or(1.0).max(1e-3);
                let shadow = ray.with_range(ray.t_min, reach * t_max_fraction);
                let expected = first_hit(&field, surface, &shadow).is_some();
                prop_assert_eq!(naive.occluded(&shadow), expected, "naive shadow {:?} {:?}", kind, shadow);
                prop_assert_eq!(mipmap.occluded(&shadow), expected, "mipmap shadow {:?} {:?}", kind, shadow);
            }
        }
    }
}

/// A whole camera image, as `relief render --depth` computes it, against the brute force:
/// every pixel agrees to 1e-4 relative but a handful of exact grazing ties at silhouettes.
#[test]
fn camera_depth_image_matches_the_brute_force() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    for _ in 0..6 {
        let field = Arc::new(terrain().new_tree(&mut runner).unwrap().current());
        for surface in Surface::ALL {
            let bounds = field.world_bounds(surface);
            let camera = relief_core::Camera::frame(&bounds, 48, 32).unwrap();
            let mipmap = MipmapTracer::new(field.clone(), surface);
            let mut wrong = Vec::new();
            for j in 0..32 {
                for i in 0..48 {
                    let ray = camera.ray(i, j);
                    let got = mipmap.intersect(&ray).map(|h| h.t as f32 as f64);
                    let want = first_hit(&field, surface, &ray);
                    if !agree(got, want, 1e-4) {
                        wrong.push((i, j, got, want));
                    }
                }
            }
            assert!(
                wrong.len() <= 2,
                "{surface} on {}x{}: {wrong:?}",
                field.width(),
                field.height()
            );
        }
    }
}
