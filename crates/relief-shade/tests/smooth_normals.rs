//! Smooth shading normals: close to an analytic surface's normal at the hits (closer than the
//! facets'), the facets' own on a plane; they change the picture only, not the depth or the
//! normals kept, the same in `f32` lanes as in `f64` within one 8-bit step, and the same on
//! any number of threads.

use std::sync::Arc;

use relief_core::{Camera, DVec2, DVec3, GridGeometry, HeightField, Projection, Surface};
use relief_shade::{
    render_gbuffer, render_to_srgb8, KeptHits, ShadingNormals, ShadingParams, StripRender, Sun,
};
use relief_trace::{build_tracer, Tracer, TracerKind};

/// A field sampling `z(x, y)` (world units) on a grid of `geometry`.
fn sampled(
    w: usize,
    h: usize,
    geometry: GridGeometry,
    z: impl Fn(f64, f64) -> f64,
) -> Arc<HeightField> {
    let samples = (0..w * h)
        .map(|k| {
            let (c, r) = ((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
            let (x, y) = (geometry.origin.x + c * geometry.dx, geometry.origin.y + r * geometry.dy);
            (z(x, y) / geometry.z_scale) as f32
        })
        .collect();
    Arc::new(HeightField::new(w, h, samples, geometry).unwrap())
}

/// A grid of uneven spacing, scale and origin.
fn geometry() -> GridGeometry {
    GridGeometry { dx: 12.0, dy: 9.0, z_scale: 2.5, origin: DVec2::new(-300.0, 150.0) }
}

/// A sine terrain (world units) and its unit normal.
fn sine(x: f64, y: f64) -> f64 {
    40.0 * (x / 70.0).sin() * (y / 55.0).cos() + 0.2 * x
}

fn sine_normal(x: f64, y: f64) -> DVec3 {
    let gx = 40.0 / 70.0 * (x / 70.0).cos() * (y / 55.0).cos() + 0.2;
    let gy = -40.0 / 55.0 * (x / 70.0).sin() * (y / 55.0).sin();
    DVec3::new(-gx, -gy, 1.0).normalize()
}

/// A camera looking down at the terrain from the south-west, `w x h` pixels.
fn camera(field: &HeightField, w: u32, h: u32) -> Camera {
    let b = field.world_bounds(Surface::Triangles);
    let (c, size) = (b.center(), b.max - b.min);
    let eye = c + DVec3::new(-0.5 * size.x, -0.7 * size.y, 0.6 * size.x.max(size.y));
    Camera::new(eye, c, DVec3::Z, Projection::Perspective { fov_deg: 50.0 }, w, h).unwrap()
}

fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
}

#[test]
fn smooth_normals_at_the_hits_are_close_to_the_analytic_ones_and_closer_than_the_facets() {
    let field = sampled(64, 80, geometry(), sine);
    let bounds = field.world_bounds(Surface::Triangles);
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    let camera = camera(&field, 96, 64);
    let (g, _) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
    let smooth = ShadingNormals::smooth(field.clone());
    let (mut hits, mut smooth_sum, mut facet_sum, mut smooth_max) = (0, 0.0, 0.0, 0.0f64);
    // Every third pixel: a spread of hits over the whole terrain.
    for k in (0..g.len()).step_by(3) {
        let distance = g.distance[k] as f64;
        let geometric = DVec3::from(g.normal[k].map(f64::from));
        if !distance.is_finite() || geometric.z <= 0.0 {
            continue;
        }
        let (i, j) = ((k % g.width) as u32, (k / g.width) as u32);
        let p = camera.ray(i, j).at(distance);
        // Away from the grid's edges, where one-sided differences are first-order only.
        let (u, v) = ((p.x - bounds.min.x) / 12.0, (p.y - bounds.min.y) / 9.0);
        if u < 1.0 || v < 1.0 || u > 62.0 || v > 78.0 {
            continue;
        }
        let want = sine_normal(p.x, p.y);
        let s = angle_deg(smooth.at(p, geometric, distance), want);
        smooth_sum += s;
        facet_sum += angle_deg(geometric, want);
        smooth_max = smooth_max.max(s);
        hits += 1;
    }
    assert!(hits > 500, "{hits} hits");
    let (smooth_mean, facet_mean) = (smooth_sum / hits as f64, facet_sum / hits as f64);
    println!("mean angle to the analytic normal: smooth {smooth_mean:.3}°, faceted {facet_mean:.3}°, smooth max {smooth_max:.3}°");
    assert!(smooth_mean < 0.5 * facet_mean, "smooth {smooth_mean}° vs faceted {facet_mean}°");
    assert!(smooth_max < 2.0, "smooth normals within 2° of the analytic ones: {smooth_max}°");
}

#[test]
fn on_a_plane_the_smooth_normal_is_the_facets() {
    for (a, b) in [(0.0, 0.0), (0.8, -0.3), (-2.5, 1.7)] {
        let field = sampled(20, 17, geometry(), |x, y| a * x + b * y + 1000.0);
        let bounds = field.world_bounds(Surface::Triangles);
        let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Naive);
        let camera = camera(&field, 48, 32);
        let (g, _) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
        let smooth = ShadingNormals::smooth(field.clone());
        let mut tops = 0;
        for k in 0..g.len() {
            let distance = g.distance[k] as f64;
            let geometric = DVec3::from(g.normal[k].map(f64::from));
            if !distance.is_finite() || geometric.z <= 0.0 {
                continue;
            }
            let (i, j) = ((k % g.width) as u32, (k / g.width) as u32);
            let n = smooth.at(camera.ray(i, j).at(distance), geometric, distance);
            // Equal but for the rounding of the f32 samples and the G-buffer's f32 normal.
            assert!((n - geometric).length() < 1e-5, "slope {a},{b}: {n} vs {geometric}");
            tops += 1;
        }
        assert!(tops > 100, "slope {a},{b}: {tops} hits on the top");
        // And the pictures agree within one 8-bit step (the G-buffer's normal is f32).
        let faceted = picture(&*tracer, &field, &camera, ShadingNormals::Faceted, true);
        let smooth = picture(&*tracer, &field, &camera, smooth, true);
        assert!(max_step(&faceted.rgb, &smooth.rgb) <= 1, "slope {a},{b}");
    }
}

/// The strip render of `field` seen by `camera`, lit by `normals`, in `f64` when `precise`,
/// keeping depth and normals.
fn picture(
    tracer: &dyn Tracer,
    field: &HeightField,
    camera: &Camera,
    normals: ShadingNormals,
    precise: bool,
) -> StripRender {
    let bounds = field.world_bounds(Surface::Triangles);
    let mut params = ShadingParams::for_terrain(&field.world_bounds(Surface::Boxes)).unwrap();
    params.sun = Sun { azimuth_deg: 315.0, elevation_deg: 25.0, ..params.sun };
    params.normals = normals;
    params.precise = precise;
    let keep = KeptHits { depth: true, normals: true };
    render_to_srgb8(tracer, tracer, camera, &bounds, &params, keep, &|_| {}).unwrap()
}

fn max_step(a: &[[u8; 3]], b: &[[u8; 3]]) -> u8 {
    a.iter().flatten().zip(b.iter().flatten()).map(|(x, y)| x.abs_diff(*y)).max().unwrap()
}

fn bits<const N: usize>(v: &[[f32; N]]) -> Vec<u32> {
    v.iter().flatten().map(|x| x.to_bits()).collect()
}

#[test]
fn smooth_normals_change_the_picture_but_not_the_depth_or_the_normals_kept() {
    let field = sampled(64, 80, geometry(), sine);
    let camera = camera(&field, 120, 80);
    for kind in [TracerKind::Mipmap, TracerKind::Naive] {
        let tracer = build_tracer(field.clone(), Surface::Triangles, kind);
        let faceted = picture(&*tracer, &field, &camera, ShadingNormals::Faceted, false);
        let smooth =
            picture(&*tracer, &field, &camera, ShadingNormals::smooth(field.clone()), false);
        let depth_bits = |r: &StripRender| {
            r.depth.as_ref().unwrap().iter().map(|d| d.to_bits()).collect::<Vec<_>>()
        };
        assert_eq!(depth_bits(&faceted), depth_bits(&smooth), "{kind:?}: depth");
        assert_eq!(
            bits(faceted.normals.as_ref().unwrap()),
            bits(smooth.normals.as_ref().unwrap()),
            "{kind:?}: the normals kept are the exact ones"
        );
        assert_eq!(faceted.stats.shadow, smooth.stats.shadow, "{kind:?}: the same shadow rays");
        let changed = faceted.rgb.iter().zip(&smooth.rgb).filter(|(a, b)| a != b).count();
        assert!(changed > faceted.rgb.len() / 4, "{kind:?}: {changed} pixels changed");
    }
}

#[test]
fn the_f32_lanes_stay_within_one_step_of_the_f64_pass_with_smooth_normals() {
    let field = sampled(64, 80, geometry(), sine);
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    for (w, h) in [(120, 80), (67, 41)] {
        let camera = camera(&field, w, h);
        let smooth = || ShadingNormals::smooth(field.clone());
        let fast = picture(&*tracer, &field, &camera, smooth(), false);
        let slow = picture(&*tracer, &field, &camera, smooth(), true);
        assert!(max_step(&fast.rgb, &slow.rgb) <= 1, "{w}x{h}");
        assert_eq!(fast.stats.shadow, slow.stats.shadow);
    }
}

#[test]
fn smooth_pictures_are_the_same_on_one_and_two_threads() {
    let field = sampled(64, 80, geometry(), sine);
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    let camera = camera(&field, 90, 70);
    let run = |threads: usize, precise: bool| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let normals = ShadingNormals::smooth(field.clone());
        pool.install(|| picture(&*tracer, &field, &camera, normals, precise).rgb)
    };
    for precise in [false, true] {
        assert!(run(1, precise) == run(2, precise), "precise {precise}");
    }
}
