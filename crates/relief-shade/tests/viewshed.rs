//! Viewsheds against ground truth: every sample's answer equals its line of sight traced by
//! an independent brute-force tracer (property tests on random terrains with flats, spikes,
//! cliffs, integer steps and voids), cumulative counts are sums of single viewsheds, and
//! analytic scenes (a plane, a wall, a pit) are seen as their geometry says.

#[path = "../../relief-trace/tests/common/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use proptest::prelude::*;
use relief_core::{DVec3, GridGeometry, HeightField, Ray, Surface};
use relief_shade::shade_map::surface_origin;
use relief_shade::viewshed::{viewshed, Observer, Viewshed, ViewshedParams};
use relief_trace::conformance::{first_hit, Floor, GRAZE_RELATIVE};
use relief_trace::{build_tracer, TracerKind};
use std::sync::Arc;

/// Whether the brute-force tracer finds the segment from the target point of (`col`, `row`)
/// to `eye` unobstructed; `None` where the segment grazes the solid (touches an edge or a
/// corner within rounding: the reference with every face grown by a billionth of the scene
/// and with every face shrunk by it disagree), where either answer is exact.
fn brute_force_sees(
    field: &HeightField,
    surface: Surface,
    eye: DVec3,
    col: usize,
    row: usize,
    target_height: f64,
) -> Option<bool> {
    let target = surface_origin(field, col, row) + DVec3::new(0.0, 0.0, target_height);
    let ray = Ray::new(target, eye - target).with_range(0.0, 1.0);
    let g = field.geometry();
    let extent = (field.width() as f64 * g.dx).max(field.height() as f64 * g.dy)
        + f64::from(field.max_sample().abs().max(field.min_sample().abs())) * g.z_scale.abs();
    let graze = GRAZE_RELATIVE * (extent + target.length() + eye.length());
    let sees = |margin: f64| first_hit(field, surface, Floor::LowestSample, &ray, margin).is_none();
    let (grown, shrunk) = (sees(graze), sees(-graze));
    (grown == shrunk).then_some(grown)
}

/// Whether (`col`, `row`) lies on the grid's border or next to a hole: lines of sight from
/// there leave over the solid's wall within a few lifts of its top edge, grazing ties where
/// either answer is exact.
fn near_a_wall(field: &HeightField, col: usize, row: usize) -> bool {
    let border = col == 0 || row == 0 || col + 1 == field.width() || row + 1 == field.height();
    border
        || (0..9).any(|k| {
            let (c, r) = ((col + k % 3).wrapping_sub(1), (row + k / 3).wrapping_sub(1));
            c < field.width() && r < field.height() && field.is_hole(c, r)
        })
}

/// The world point at fractions (`u`, `v`) of the field's footprint.
fn point_in(field: &HeightField, u: f64, v: f64) -> (f64, f64) {
    let g = field.geometry();
    (g.origin.x + u * field.width() as f64 * g.dx, g.origin.y + v * field.height() as f64 * g.dy)
}

fn run(field: &Arc<HeightField>, surface: Surface, params: &ViewshedParams) -> Viewshed {
    let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
    viewshed(field, &*tracer, None, params, &|_| {}).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn every_sample_equals_its_brute_force_line_of_sight(
        field in scenes::terrain(),
        place in (0.0f64..1.0, 0.0f64..1.0),
        eye_height in prop_oneof![Just(0.0f64), 0.0f64..30.0],
        target_height in prop_oneof![Just(0.0f64), 0.0f64..5.0],
        radius in prop_oneof![Just(None), (1.0f64..40.0).prop_map(Some)],
    ) {
        let field = Arc::new(field);
        let (x, y) = point_in(&field, place.0, place.1);
        let observer = Observer::new(x, y, eye_height);
        let params = ViewshedParams { observers: vec![observer], target_height, radius };
        for surface in Surface::ALL {
            let naive = build_tracer(field.clone(), surface, TracerKind::Naive);
            let eye = match observer.eye(&field, &*naive, None) {
                Ok(eye) => eye,
                // Only an observer on a hole is refused.
                Err(e) => {
                    prop_assert!(e.to_string().contains("void"), "{}", e);
                    continue;
                }
            };
            let result = run(&field, surface, &params);
            let mut compared = 0;
            for row in 0..field.height() {
                for col in 0..field.width() {
                    let value = result.counts[col + row * field.width()];
                    if field.is_hole(col, row) {
                        prop_assert!(value.is_nan());
                        continue;
                    }
                    let p = surface_origin(&field, col, row);
                    let far = radius.is_some_and(|r| (eye.x - p.x).hypot(eye.y - p.y) > r);
                    if far {
                        prop_assert_eq!(value, 0.0, "beyond the radius at ({}, {})", col, row);
                        continue;
                    }
                    if near_a_wall(&field, col, row) {
                        continue;
                    }
                    let Some(sees) =
                        brute_force_sees(&field, surface, eye, col, row, target_height)
                    else {
                        // A graze: either answer is exact.
                        compared += 1;
                        continue;
                    };
                    prop_assert_eq!(value, f32::from(u8::from(sees)),
                        "{} at ({}, {}), eye {:?}", surface, col, row, eye);
                    compared += 1;
                }
            }
            prop_assert!(compared > 0 || field.width() < 3 || field.height() < 3
                || radius.is_some() || field.hole_count() > 0);
        }
    }

    #[test]
    fn cumulative_counts_are_sums_of_single_viewsheds(
        field in scenes::terrain(),
        places in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..10.0), 1..5),
        target_height in 0.0f64..2.0,
    ) {
        let field = Arc::new(field);
        let observers: Vec<Observer> = places
            .iter()
            .map(|&(u, v, h)| {
                let (x, y) = point_in(&field, u, v);
                Observer::new(x, y, h)
            })
            .collect();
        let params = ViewshedParams { observers: observers.clone(), target_height, radius: None };
        let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
        let Ok(all) = viewshed(&field, &*tracer, None, &params, &|_| {}) else {
            // An observer on a hole: refused whole.
            prop_assert!(observers.iter().any(|o| o.eye(&field, &*tracer, None).is_err()));
            return Ok(());
        };
        let mut sum = vec![0.0f32; field.width() * field.height()];
        for observer in observers {
            let one = ViewshedParams { observers: vec![observer], ..params.clone() };
            let single = viewshed(&field, &*tracer, None, &one, &|_| {}).unwrap();
            for (s, v) in sum.iter_mut().zip(&single.counts) {
                prop_assert!(v.is_nan() || *v == 0.0 || *v == 1.0);
                *s += v;
            }
        }
        for (k, (a, b)) in all.counts.iter().zip(&sum).enumerate() {
            prop_assert!(a == b || (a.is_nan() && b.is_nan()), "sample {}: {} and {}", k, a, b);
        }
    }
}

/// A `w` x `h` field of `height(col, row)` with cells `dx` wide, origin at zero.
fn field_of(w: usize, h: usize, dx: f64, height: impl Fn(f64, f64) -> f64) -> Arc<HeightField> {
    let samples = (0..w * h).map(|i| height((i % w) as f64, (i / w) as f64) as f32).collect();
    let geometry = GridGeometry { dx, dy: dx, ..GridGeometry::unit() };
    Arc::new(HeightField::new(w, h, samples, geometry).unwrap())
}

fn one_observer(x: f64, y: f64, height: f64) -> ViewshedParams {
    ViewshedParams {
        observers: vec![Observer::new(x, y, height)],
        target_height: 0.0,
        radius: None,
    }
}

#[test]
fn a_flat_plane_is_seen_whole_even_from_the_ground() {
    let field = field_of(33, 21, 2.0, |_, _| 7.0);
    for height in [0.0, 1.7] {
        let result = run(&field, Surface::Triangles, &one_observer(20.0, 13.0, height));
        assert!(result.counts.iter().all(|&v| v == 1.0), "eye height {height}");
    }
}

#[test]
fn a_wall_hides_the_ground_behind_it_up_to_its_shadow_line() {
    // Cells 1 m wide; a wall 10 m high on column 20 (its crest at x = 20.5); the eye 5 m
    // above the ground at x = 10.5, below the crest: everything behind the wall is hidden.
    let field = field_of(40, 9, 1.0, |x, _| if x == 20.0 { 10.0 } else { 0.0 });
    let result = run(&field, Surface::Triangles, &one_observer(10.5, 4.5, 5.0));
    for row in 0..9 {
        for col in 0..40 {
            let seen = result.counts[col + row * 40];
            let expected = if col <= 20 { 1.0 } else { 0.0 };
            assert_eq!(seen, expected, "({col}, {row})");
        }
    }
    // From 30 m up, the ground comes back into view where the line over the crest lands:
    // z = 30 - 20 (x - 10.5) / 10 = 0 at x = 25.5, so samples from column 25 on are seen.
    let result = run(&field, Surface::Triangles, &one_observer(10.5, 4.5, 30.0));
    for col in 0..40 {
        let seen = result.counts[col + 4 * 40];
        let expected = if col <= 20 || col >= 25 { 1.0 } else { 0.0 };
        assert_eq!(seen, expected, "column {col}");
    }
}

#[test]
fn a_target_height_raises_what_is_seen_behind_a_wall() {
    // As above, eye 30 m up: with targets 2 m tall the line over the crest (falling 2 m per
    // metre) meets them at x = 24.5: columns from 24 on.
    let field = field_of(40, 9, 1.0, |x, _| if x == 20.0 { 10.0 } else { 0.0 });
    let params = ViewshedParams { target_height: 2.0, ..one_observer(10.5, 4.5, 30.0) };
    let result = run(&field, Surface::Triangles, &params);
    for col in 0..40 {
        let expected = if col <= 20 || col >= 24 { 1.0 } else { 0.0 };
        assert_eq!(result.counts[col + 4 * 40], expected, "column {col}");
    }
}

#[test]
fn a_radius_limits_what_is_seen() {
    let field = field_of(30, 30, 1.0, |_, _| 0.0);
    let params = ViewshedParams { radius: Some(6.0), ..one_observer(15.0, 15.0, 1.0) };
    let result = run(&field, Surface::Triangles, &params);
    for row in 0..30 {
        for col in 0..30 {
            let d = (col as f64 + 0.5 - 15.0).hypot(row as f64 + 0.5 - 15.0);
            assert_eq!(result.counts[col + row * 30], f32::from(u8::from(d <= 6.0)));
        }
    }
}

#[test]
fn voids_are_nan_and_observers_are_checked() {
    let field = field_of(16, 16, 1.0, |x, y| (x * 0.3).sin() * 3.0 + y * 0.1);
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    let mut void = vec![false; 256];
    for k in [0, 17, 100, 255] {
        void[k] = true;
    }
    let params = one_observer(8.0, 8.0, 1.7);
    let result = viewshed(&field, &*tracer, Some(&void), &params, &|_| {}).unwrap();
    for (k, v) in result.counts.iter().enumerate() {
        assert_eq!(v.is_nan(), void[k], "sample {k}");
    }
    let refused = |params: &ViewshedParams, void: Option<&[bool]>| {
        viewshed(&field, &*tracer, void, params, &|_| {}).unwrap_err().to_string()
    };
    assert!(refused(&one_observer(4.5, 6.5, 1.0), Some(&void)).contains("void"));
    assert!(refused(&one_observer(16.5, 3.0, 1.0), None).contains("outside the DEM"));
    assert!(refused(&one_observer(3.0, -0.1, 1.0), None).contains("outside the DEM"));
    assert!(refused(&one_observer(3.0, 3.0, -1.0), None).contains("observer height"));
    assert!(refused(&one_observer(3.0, 3.0, f64::NAN), None).contains("observer height"));
    assert!(refused(&one_observer(f64::NAN, 3.0, 1.0), None).contains("observer"));
    let nobody = ViewshedParams { observers: vec![], ..params.clone() };
    assert!(refused(&nobody, None).contains("at least one"));
    let negative = ViewshedParams { target_height: -1.0, ..params.clone() };
    assert!(refused(&negative, None).contains("target height"));
    let zero = ViewshedParams { radius: Some(0.0), ..params.clone() };
    assert!(refused(&zero, None).contains("radius"));
    assert!(refused(&params, Some(&void[1..])).contains("void mask of 255 samples"));
    // The footprint's edges are inside.
    assert!(viewshed(&field, &*tracer, None, &one_observer(16.0, 0.0, 1.0), &|_| {}).is_ok());
}

#[test]
fn the_viewshed_is_the_same_whatever_the_thread_count() {
    let field = field_of(70, 45, 3.0, |x, y| (x * 0.15).sin() * 20.0 + (y * 0.18).cos() * 15.0);
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    let observers = vec![Observer::new(30.0, 40.0, 2.0), Observer::new(150.0, 100.0, 10.0)];
    let params = ViewshedParams { observers, target_height: 1.0, radius: None };
    let go = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| viewshed(&field, &*tracer, None, &params, &|_| {}).unwrap())
    };
    let one = go(1);
    assert_eq!(one, go(2));
    // Not trivially uniform: some samples are seen by both, some by one, some by neither.
    for count in [0.0, 1.0, 2.0] {
        assert!(one.counts.contains(&count), "no sample seen by {count}");
    }
}

#[test]
fn the_ground_behind_a_wall_is_proven_hidden_without_tracing() {
    // The sweep proves the lines of sight that pass through the wall hidden: only the samples
    // seen and the hidden ones within ten texels behind the wall (where the wall's squares are
    // not yet in the sweep's bins) are traced, and the answer is the geometry's.
    let field = field_of(120, 40, 1.0, |x, _| if (50.0..53.0).contains(&x) { 30.0 } else { 0.0 });
    let result = run(&field, Surface::Triangles, &one_observer(20.5, 20.5, 2.0));
    let seen = result.counts.iter().filter(|&&c| c == 1.0).count() as u64;
    assert!(result.rays < seen + 10 * 40, "{} rays for {seen} samples seen", result.rays);
    for row in 0..40 {
        assert_eq!(result.counts[20 + row * 120], 1.0, "row {row} before the wall");
        assert_eq!(result.counts[100 + row * 120], 0.0, "row {row} behind the wall");
    }
}
