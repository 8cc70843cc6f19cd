//! Property tests of the safety-shape tracer: every variant that claims exactness equals the
//! naive triangle tracer on the rays it admits, on random terrains; thin walls and spikes
//! render with no holes; the strictly positive variant reports its wrong-pixel rate.

mod common;

use common::scenes::{agree, ray_for, terrain, ALL_KINDS};
use proptest::prelude::*;
use relief_core::{Camera, DVec3, GridGeometry, HeightField, Ray, Surface};
use relief_trace::safety::{FinalTest, SafetyOptions, SafetyShapes, SafetyTracer, ShapeLayout};
use relief_trace::{NaiveTracer, Tracer};
use std::sync::Arc;

const VARIANTS: [&str; 6] = [
    "cyl_all",
    "cyl_all+cone_all",
    "cyl_all+cone_exact",
    "cyl_ext",
    "cyl_ext+cone_all",
    "cyl_ext+cone_ext",
];

/// A random terrain cropped to at most 24 x 24 and without holes (safety shapes refuse them).
fn whole(field: HeightField) -> HeightField {
    let (w, h) = (field.width().min(24), field.height().min(24));
    let samples = (0..w * h).map(|k| field.sample(k % w, k / w)).collect();
    HeightField::new(w, h, samples, *field.geometry()).unwrap()
}

/// A ray from outside the bounding box towards a random point inside it.
fn exterior_ray(field: &HeightField, u: [f64; 8]) -> Ray {
    let b = field.world_bounds(Surface::Triangles);
    let size = (b.max - b.min).max(DVec3::splat(1.0));
    let target = b.min + (b.max - b.min) * DVec3::new(u[0], u[1], u[2]);
    let (az, el) = (u[3] * std::f64::consts::TAU, (u[4] * 100.0 - 15.0_f64).to_radians());
    let towards = DVec3::new(az.cos() * el.cos(), az.sin() * el.cos(), el.sin());
    let origin = b.center() + towards * size.length() * (1.0 + u[5]);
    Ray::new(origin, (target - origin).normalize())
}

fn options(variant: &str, phi_max: Option<f64>, isotropic: bool, reach: u16) -> SafetyOptions {
    let mut o: SafetyOptions = variant.parse().unwrap();
    o.phi_max_deg = phi_max;
    o.layout = if isotropic { ShapeLayout::Isotropic } else { ShapeLayout::Directional };
    o.reach = reach;
    o
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, ..ProptestConfig::default() })]

    #[test]
    fn exact_variants_equal_the_naive_tracer(
        field in terrain(),
        numbers in prop::collection::vec(prop::array::uniform8(0.001f64..0.999), 48),
        phi_max in prop_oneof![Just(None), (-70.0f64..-20.0).prop_map(Some)],
        isotropic in any::<bool>(),
        reach in prop_oneof![Just(128u16), 1u16..6],
    ) {
        let field = Arc::new(whole(field));
        let naive = NaiveTracer::new(field.clone(), Surface::Triangles);
        for variant in VARIANTS {
            let options = options(variant, phi_max, isotropic, reach);
            let shapes = Arc::new(SafetyShapes::build(&field, options, &|_, _| {}).unwrap());
            let tracer = SafetyTracer::new(field.clone(), shapes, FinalTest::Triangles).unwrap();
            let mut admitted = 0;
            for (k, u) in numbers.iter().enumerate() {
                let ray = if k % 2 == 0 {
                    exterior_ray(&field, *u)
                } else {
                    ray_for(&field, ALL_KINDS[(k / 2) % ALL_KINDS.len()], *u)
                };
                // Rays the shapes were not built for are traced cell by cell: still exact.
                admitted += tracer.admits(&ray) as usize;
                let want = naive.intersect(&ray);
                let got = tracer.intersect(&ray);
                prop_assert!(agree(want.map(|h| h.t), got.map(|h| h.t), 1e-5),
                    "{options}: {ray:?}: naive {want:?} safety {got:?}");
                if let (Some(a), Some(b)) = (want, got) {
                    prop_assert!(a.t != b.t || (a.normal - b.normal).length() < 1e-9);
                }
                // Shadow rays over part of the way.
                let reach_t = want.map_or(1.0, |h| h.t).max(1e-3) * (0.3 + 0.9 * u[7]);
                let shadow = ray.with_range(ray.t_min, reach_t);
                prop_assert_eq!(tracer.occluded(&shadow), naive.occluded(&shadow),
                    "{}: shadow {:?}", options, shadow);
            }
            // The test must exercise the shapes, not only the fallback.
            if phi_max.is_none() {
                prop_assert!(admitted >= numbers.len() / 2, "{options}: {admitted} rays admitted");
            }
        }
    }
}

/// Rays of a phi-max view: all steeper than the bound, from above.
#[test]
fn phi_max_variants_are_exact_on_the_rays_they_admit() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    for _ in 0..12 {
        let field = Arc::new(whole(terrain().new_tree(&mut runner).unwrap().current()));
        let naive = NaiveTracer::new(field.clone(), Surface::Triangles);
        let bounds = field.world_bounds(Surface::Triangles);
        for variant in VARIANTS {
            let options = options(variant, Some(-45.0), false, 128);
            let shapes = Arc::new(SafetyShapes::build(&field, options, &|_, _| {}).unwrap());
            let tracer = SafetyTracer::new(field.clone(), shapes, FinalTest::Triangles).unwrap();
            let camera = Camera::frame_from(&bounds, 200.0, 75.0, 25.0, 40, 30).unwrap();
            let mut admitted = 0;
            for j in 0..30 {
                for i in 0..40 {
                    let ray = camera.ray(i, j);
                    admitted += tracer.admits(&ray) as usize;
                    let (want, got) = (naive.intersect(&ray), tracer.intersect(&ray));
                    assert!(
                        agree(want.map(|h| h.t), got.map(|h| h.t), 1e-5),
                        "{options} pixel ({i}, {j}): naive {want:?} safety {got:?}"
                    );
                }
            }
            assert_eq!(admitted, 1200, "{options}: the whole view is within phi max");
        }
    }
}

/// The paper's Fig. 11: a 64 x 64 field with walls one texel wide and single-texel spikes.
fn thin_features() -> HeightField {
    let n = 64;
    let samples = (0..n * n)
        .map(|k| {
            let (x, y) = (k % n, k / n);
            let wall = x == 20 || y == 40 || (x + y) % 23 == 0 && x > 30;
            let spike = x % 9 == 4 && y % 7 == 3;
            if wall {
                12.0
            } else if spike {
                20.0
            } else {
                ((x as f32 * 0.3).sin() + (y as f32 * 0.2).cos()) * 0.5
            }
        })
        .collect();
    HeightField::new(n, n, samples, GridGeometry::unit()).unwrap()
}

#[test]
fn thin_walls_and_spikes_render_with_no_holes() {
    let field = Arc::new(thin_features());
    let naive = NaiveTracer::new(field.clone(), Surface::Triangles);
    let bounds = field.world_bounds(Surface::Triangles);
    let views = [(225.0, 30.0), (20.0, 12.0), (120.0, 55.0), (300.0, 5.0)];
    for variant in VARIANTS {
        for isotropic in [false, true] {
            let options = options(variant, None, isotropic, 128);
            let shapes = Arc::new(SafetyShapes::build(&field, options, &|_, _| {}).unwrap());
            let tracer = SafetyTracer::new(field.clone(), shapes, FinalTest::Triangles).unwrap();
            for (az, el) in views {
                let camera = Camera::frame_from(&bounds, az, el, 40.0, 96, 64).unwrap();
                tracer.check_view(camera.eye(), std::iter::empty(), None).unwrap();
                for j in 0..64 {
                    for i in 0..96 {
                        let ray = camera.ray(i, j);
                        let (want, got) = (naive.intersect(&ray), tracer.intersect(&ray));
                        assert!(
                            agree(want.map(|h| h.t), got.map(|h| h.t), 1e-5),
                            "{options} view ({az}, {el}) pixel ({i}, {j}): {want:?} vs {got:?}"
                        );
                    }
                }
            }
        }
    }
}

/// Section 7's approximations are not exact: report how many pixels they get wrong.
#[test]
fn approximate_variants_report_their_wrong_pixel_rate() {
    let field = Arc::new(thin_features());
    let naive = NaiveTracer::new(field.clone(), Surface::Triangles);
    let bounds = field.world_bounds(Surface::Triangles);
    let camera = Camera::frame_from(&bounds, 225.0, 30.0, 40.0, 160, 120).unwrap();
    let mut positive = options("cyl_all+cone_all", None, false, 128);
    positive.strictly_positive = true;
    let exact = options("cyl_all+cone_all", None, false, 128);
    for (name, options, final_test) in [
        ("strictly positive", positive, FinalTest::Triangles),
        ("linear surface", exact, FinalTest::Linear),
    ] {
        let shapes = Arc::new(SafetyShapes::build(&field, options, &|_, _| {}).unwrap());
        let tracer = SafetyTracer::new(field.clone(), shapes, final_test).unwrap();
        let (mut wrong, mut total) = (0, 0);
        for j in 0..120 {
            for i in 0..160 {
                let ray = camera.ray(i, j);
                let (want, got) = (naive.intersect(&ray), tracer.intersect(&ray));
                total += 1;
                wrong += !agree(want.map(|h| h.t), got.map(|h| h.t), 1e-4) as usize;
            }
        }
        let rate = wrong as f64 / total as f64;
        println!(
            "{name}: {wrong} of {total} pixels differ from the exact depth ({:.3}%)",
            rate * 100.0
        );
        assert!(rate < 0.05, "{name}: {rate}");
    }
}
