//! Geometry clipmaps cover the field without holes: on a flat field every pixel the exact
//! tracer sees is drawn, at its distance; on rough fields, seen from straight above, every pixel
//! over the field is covered exactly once (the levels' borders join without cracks).

use proptest::prelude::*;
use relief_core::{Camera, DVec2, DVec3, GridGeometry, HeightField, Projection, Surface};
use relief_mesh::{Clipmap, ClipmapParams, RasterTarget, Rasterizer};
use relief_trace::{NaiveTracer, Tracer};
use std::sync::Arc;

/// Small rings whose coarsest level (14 x 32 = 448 samples) covers every field of the tests
/// from any viewer over it.
const PARAMS: ClipmapParams = ClipmapParams { ring_vertices: 15, levels: 6, transition: 3 };

fn geometry(g: (f64, f64, f64, f64)) -> GridGeometry {
    GridGeometry { dx: g.0, dy: g.1, z_scale: 1.0, origin: DVec2::new(g.2, g.3) }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]

    #[test]
    fn a_flat_field_is_drawn_wherever_the_exact_tracer_sees_it(
        (w, h) in (20usize..140, 20usize..140),
        g in (0.5..2.0f64, 0.5..2.0f64, -50.0..50.0f64, -50.0..50.0f64),
        level in -3.0..3.0f32,
        eye in (0.0..1.0f64, 0.0..1.0f64, 0.5..60.0f64),
        target in (-0.2..1.2f64, -0.2..1.2f64),
        fov in 30.0..90.0f64,
    ) {
        let field = HeightField::new(w, h, vec![level; w * h], geometry(g)).unwrap();
        let bounds = field.world_bounds(Surface::Triangles);
        let size = bounds.max - bounds.min;
        let at = |fx: f64, fy: f64, z: f64| DVec3::new(bounds.min.x + fx * size.x, bounds.min.y + fy * size.y, z);
        let eye = at(eye.0, eye.1, level as f64 + eye.2);
        let Ok(camera) = Camera::look_at(eye, at(target.0, target.1, level as f64), DVec3::Z, fov, 40, 30) else {
            return Ok(());
        };
        let clipmap = Clipmap::new(&field, PARAMS).unwrap();
        let mesh = clipmap.mesh(&camera);
        let mut image = RasterTarget::for_camera(&camera);
        Rasterizer::new().draw(&camera, &mesh, 0, &mut image).unwrap();
        let tracer = NaiveTracer::new(Arc::new(field), Surface::Triangles);
        let margin = 1e-6 * size.length();
        for j in 0..30 {
            for i in 0..40 {
                let ray = camera.ray(i, j);
                // Where the ray meets the plane, and whether that is clearly inside or outside
                // the samples' footprint.
                let t = (level as f64 - ray.origin.z) / ray.dir.z;
                if t > 0.0 {
                    let p = ray.at(t);
                    let d = (p.x - bounds.min.x).min(bounds.max.x - p.x).min(p.y - bounds.min.y).min(bounds.max.y - p.y);
                    if d.abs() < margin {
                        continue;
                    }
                }
                let exact = tracer.intersect(&ray).map(|hit| hit.t);
                let drawn = image.get(i as usize, j as usize).map(|(d, _)| d as f64);
                match (exact, drawn) {
                    (None, None) => {}
                    (Some(t), Some(d)) => prop_assert!((t - d).abs() <= 1e-5 * t, "pixel ({}, {}): {} vs {}", i, j, t, d),
                    (exact, drawn) => prop_assert!(false, "pixel ({}, {}): exact {:?} drawn {:?}", i, j, exact, drawn),
                }
            }
        }
    }

    #[test]
    fn rough_fields_are_covered_once_from_above(
        (w, h) in (20usize..120, 20usize..120),
        samples in prop::collection::vec(-20.0f32..20.0, 120 * 120),
        centre in (0.0..1.0f64, 0.0..1.0f64),
    ) {
        let field = HeightField::new(w, h, samples[..w * h].to_vec(), GridGeometry::unit()).unwrap();
        let bounds = field.world_bounds(Surface::Triangles);
        let (cx, cy) = (centre.0 * w as f64, centre.1 * h as f64);
        // One pixel per half sample, looking straight down over the whole field.
        let (px, py) = (2 * w as u32 + 8, 2 * h as u32 + 8);
        let middle = DVec3::new(w as f64 / 2.0, h as f64 / 2.0, 0.0);
        let ortho = Projection::Orthographic { height: py as f64 / 2.0 };
        let camera = Camera::new(middle + DVec3::Z * 100.0, middle, DVec3::Y, ortho, px, py).unwrap();
        let clipmap = Clipmap::new(&field, PARAMS).unwrap();
        let mesh = clipmap.mesh_around(cx, cy);
        let counts = Rasterizer::new().coverage_counts(&camera, &mesh);
        for j in 0..py {
            for i in 0..px {
                let p = camera.ray(i, j).origin;
                let inside = p.x > bounds.min.x && p.x < bounds.max.x && p.y > bounds.min.y && p.y < bounds.max.y;
                let on_border = [p.x - bounds.min.x, bounds.max.x - p.x, p.y - bounds.min.y, bounds.max.y - p.y]
                    .iter()
                    .any(|d| d.abs() < 1e-9);
                if !on_border {
                    prop_assert_eq!(counts[(i + j * px) as usize], inside as u32, "pixel ({}, {})", i, j);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]

    /// Seen obliquely, a ray that enters over the field above its highest point and leaves
    /// it below its lowest crosses the surface an odd number of times: a crack between levels
    /// (heights not morphed to the coarser level at a border) would let some through evenly.
    #[test]
    fn levels_join_without_cracks(
        (w, h) in (20usize..120, 20usize..120),
        samples in prop::collection::vec(-3.0f32..3.0, 120 * 120),
        centre in (0.0..1.0f64, 0.0..1.0f64),
        azimuth in 0.0..std::f64::consts::TAU,
        elevation in 0.6..1.4f64,
    ) {
        let field = HeightField::new(w, h, samples[..w * h].to_vec(), GridGeometry::unit()).unwrap();
        let bounds = field.world_bounds(Surface::Triangles);
        let middle = DVec3::new(w as f64 / 2.0, h as f64 / 2.0, 0.0);
        let towards_eye = DVec3::new(azimuth.cos() * elevation.cos(), azimuth.sin() * elevation.cos(), elevation.sin());
        let ortho = Projection::Orthographic { height: 1.2 * w.max(h) as f64 };
        let camera = Camera::new(middle + towards_eye * 500.0, middle, DVec3::Z, ortho, 120, 120).unwrap();
        let clipmap = Clipmap::new(&field, PARAMS).unwrap();
        let mesh = clipmap.mesh_around(centre.0 * w as f64, centre.1 * h as f64);
        let counts = Rasterizer::new().coverage_counts(&camera, &mesh);
        let (z_low, z_high) = (-3.5, 3.5);
        let mut checked = 0;
        for j in 0..120u32 {
            for i in 0..120u32 {
                let ray = camera.ray(i, j);
                let over = |z: f64| {
                    let p = ray.at((z - ray.origin.z) / ray.dir.z);
                    p.x > bounds.min.x + 1e-6 && p.x < bounds.max.x - 1e-6 && p.y > bounds.min.y + 1e-6 && p.y < bounds.max.y - 1e-6
                };
                if over(z_low) && over(z_high) {
                    checked += 1;
                    prop_assert_eq!(counts[(i + 120 * j) as usize] % 2, 1, "pixel ({}, {})", i, j);
                }
            }
        }
        prop_assert!(checked > 50, "{} pixels checked", checked);
    }
}

#[test]
fn refuses_bad_parameters_and_keeps_level_zero_exact() {
    let field =
        HeightField::new(9, 9, (0..81).map(|k| (k % 7) as f32).collect(), GridGeometry::unit())
            .unwrap();
    for params in [
        ClipmapParams { ring_vertices: 16, ..PARAMS },
        ClipmapParams { ring_vertices: 7, ..PARAMS },
        ClipmapParams { levels: 0, ..PARAMS },
        ClipmapParams { transition: 0, ..PARAMS },
        ClipmapParams { transition: 5, ..PARAMS },
    ] {
        assert!(Clipmap::new(&field, params).is_err(), "{params:?}");
    }
    assert!(ClipmapParams::default().validate().is_ok());
    // A field inside level 0 is the triangles surface itself: equal to the exact tracer from
    // above wherever it is not the walls'.
    let clipmap = Clipmap::new(&field, PARAMS).unwrap();
    let mesh = clipmap.mesh_around(4.0, 4.0);
    assert_eq!(mesh.triangle_count(), 8 * 8 * 2);
    let camera = Camera::look_at(
        DVec3::new(2.0, -3.0, 14.0),
        DVec3::new(4.5, 4.5, 0.0),
        DVec3::Z,
        50.0,
        64,
        48,
    )
    .unwrap();
    let mut image = RasterTarget::for_camera(&camera);
    Rasterizer::new().draw(&camera, &mesh, 0, &mut image).unwrap();
    let tracer = NaiveTracer::new(Arc::new(field), Surface::Triangles);
    let mut compared = 0;
    for j in 0..48 {
        for i in 0..64 {
            if let (Some(hit), Some((d, _))) =
                (tracer.intersect(&camera.ray(i, j)), image.get(i as usize, j as usize))
            {
                if hit.normal.z > 0.0 {
                    compared += 1;
                    assert!((hit.t - d as f64).abs() <= 1e-5 * hit.t, "pixel ({i}, {j})");
                }
            }
        }
    }
    assert!(compared > 500);
}
