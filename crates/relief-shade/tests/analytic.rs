//! Analytic scenes: closed-form depths and radiance, and shadows behind a spike.

use std::f64::consts::PI;
use std::sync::Arc;

use relief_core::{Camera, DVec3, GridGeometry, HeightField, Surface};
use relief_shade::{
    direct_lighting, light_visibility, render_gbuffer, shade, sun_direction, Albedo,
    ShadingNormals, ShadingParams, Sky, Sun, TraceStats,
};
use relief_trace::{build_tracer, Tracer, TracerKind};

const EYE_HEIGHT: f64 = 6.0;
const PLANE_HEIGHT: f64 = 2.0;
const FOV_DEG: f64 = 20.0;
// Several tiles, the last ones partial, so that the scatter of tiles is checked too.
const WIDTH: u32 = 37;
const HEIGHT: u32 = 21;
const PIXELS: u64 = WIDTH as u64 * HEIGHT as u64;

/// The 4 x 4 field of height 2 from the brief and a camera straight above its centre whose
/// every pixel sees the plane, for both surfaces.
fn flat_scene(surface: Surface, kind: TracerKind) -> (Box<dyn Tracer>, Camera, relief_core::Aabb) {
    let field =
        HeightField::new(4, 4, vec![PLANE_HEIGHT as f32; 16], GridGeometry::unit()).unwrap();
    let field = Arc::new(field);
    let bounds = field.world_bounds(surface);
    let tracer = build_tracer(field, surface, kind);
    let camera = Camera::look_at(
        DVec3::new(2.0, 2.0, EYE_HEIGHT),
        DVec3::new(2.0, 2.0, 0.0),
        DVec3::Y,
        FOV_DEG,
        WIDTH,
        HEIGHT,
    )
    .unwrap();
    (tracer, camera, bounds)
}

/// Lighting without ambient light, fog or specular: only ρ E cosθ / π remains.
fn lambert_only(rho: [f32; 3], sun: Sun) -> ShadingParams {
    ShadingParams {
        sun,
        sky: Sky { ambient: [0.0; 3], ..Sky::default() },
        albedo: Albedo::Uniform(rho),
        shadows: true,
        specular: None,
        fog_density: 0.0,
        exposure: 1.0,
        precise: false,
        normals: ShadingNormals::Faceted,
    }
}

#[test]
fn flat_field_from_above_has_closed_form_depths() {
    let t = (FOV_DEG.to_radians() / 2.0).tan();
    for surface in Surface::ALL {
        for kind in [TracerKind::Naive, TracerKind::Mipmap] {
            let (tracer, camera, bounds) = flat_scene(surface, kind);
            let (g, stats) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
            assert_eq!((g.width, g.height), (WIDTH as usize, HEIGHT as usize));
            assert_eq!((stats.rays, stats.hits), (PIXELS, PIXELS), "{surface} {kind}");
            let (w, h) = (WIDTH as f64, HEIGHT as f64);
            for j in 0..HEIGHT as usize {
                for i in 0..WIDTH as usize {
                    // Looking down (forward = -z) with up = +y: right = forward x up = +x.
                    let sx = (2.0 * (i as f64 + 0.5) / w - 1.0) * t * w / h;
                    let sy = (1.0 - 2.0 * (j as f64 + 0.5) / h) * t;
                    let want = (EYE_HEIGHT - PLANE_HEIGHT) * (1.0 + sx * sx + sy * sy).sqrt();
                    let k = i + j * WIDTH as usize;
                    let got = g.distance[k] as f64;
                    assert!(
                        (got - want).abs() <= 1e-6 * want,
                        "{surface} {kind} ({i},{j}): {got} vs {want}"
                    );
                    let (x, y) = (
                        2.0 + (EYE_HEIGHT - PLANE_HEIGHT) * sx,
                        2.0 + (EYE_HEIGHT - PLANE_HEIGHT) * sy,
                    );
                    let p = g.position[k];
                    assert!((p[0] as f64 - x).abs() < 1e-5 && (p[1] as f64 - y).abs() < 1e-5);
                    assert_eq!(p[2], PLANE_HEIGHT as f32);
                    assert_eq!(g.normal[k], [0.0, 0.0, 1.0]);
                    assert_eq!(g.material[k], [1.0, 0.0, 0.0, 0.0]);
                    let (b0, b1) = (bounds.min, bounds.max);
                    let uv = [(x - b0.x) / (b1.x - b0.x), (y - b0.y) / (b1.y - b0.y)];
                    assert!(
                        (g.uv[k][0] as f64 - uv[0]).abs() < 1e-6
                            && (g.uv[k][1] as f64 - uv[1]).abs() < 1e-6
                    );
                    let footprint = want * 2.0 * t / h;
                    assert!((g.footprint[k] as f64 - footprint).abs() <= 1e-6 * footprint);
                }
            }
            assert_eq!(g.depth_hw(), g.distance);
            assert_eq!(g.normals_hw3().len(), 3 * PIXELS as usize);
        }
    }
}

#[test]
fn pixels_that_miss_the_terrain_are_misses() {
    let (tracer, _, bounds) = flat_scene(Surface::Boxes, TracerKind::Mipmap);
    // Looking at the horizon: the top half of the image sees only sky.
    let camera = Camera::look_at(
        DVec3::new(2.0, -1.0, 3.0),
        DVec3::new(2.0, 2.0, 3.0),
        DVec3::Z,
        60.0,
        6,
        6,
    )
    .unwrap();
    let (g, stats) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
    assert!(stats.hits > 0 && stats.hits < stats.rays);
    for k in 0..g.len() {
        let p = g.pixel(k).unwrap();
        if !p.is_hit() {
            assert_eq!(p.distance, f32::INFINITY);
            assert_eq!((p.normal, p.material, p.footprint), ([0.0; 3], [0.0; 4], 0.0));
        }
    }
    assert!((0..6).all(|k| !g.pixel(k).unwrap().is_hit()), "top row is sky");
}

#[test]
fn lambertian_plane_lit_at_theta_shades_to_rho_e_cos_over_pi() {
    let rho = [0.25f32, 0.5, 0.75];
    let e = 3.0;
    for theta_deg in [0.0, 20.0, 45.0, 60.0, 75.0] {
        let theta = f64::to_radians(theta_deg);
        for surface in Surface::ALL {
            let (tracer, camera, bounds) = flat_scene(surface, TracerKind::Mipmap);
            let (g, _) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
            let sun = Sun { azimuth_deg: 200.0, elevation_deg: 90.0 - theta_deg, irradiance: e };
            let (radiance, shadow) = shade(&g, &*tracer, &camera, &lambert_only(rho, sun)).unwrap();
            assert_eq!(shadow.rays, PIXELS, "every pixel casts a shadow ray");
            assert_eq!(shadow.hits, 0, "a flat plane does not shadow itself");
            for px in &radiance {
                for c in 0..3 {
                    let want = rho[c] as f64 * e * theta.cos() / PI;
                    let got = px[c] as f64;
                    assert!(
                        (got - want).abs() <= 1e-6 * want,
                        "θ={theta_deg} {surface}: {got} vs {want}"
                    );
                }
            }
        }
        // The pure function on a tilted plane agrees.
        let n = DVec3::new(0.2, 0.6, 1.0).normalize();
        let l = n * theta.cos() + n.any_orthonormal_vector() * theta.sin();
        let got = direct_lighting(DVec3::splat(0.4), n, DVec3::Z, l, e, 1.0, None);
        let want = 0.4 * e * theta.cos() / PI;
        assert!(((got - DVec3::splat(want)) / want).abs().max_element() <= 1e-12);
    }
}

#[test]
fn sun_angles_point_where_the_compass_says() {
    assert!((sun_direction(90.0, 0.0) - DVec3::X).length() < 1e-12);
    assert!((sun_direction(0.0, 90.0) - DVec3::Z).length() < 1e-12);
}

/// A 9 x 9 flat field at 0 with one spike of height 5 at (4, 4), whose texel spans
/// x, y in [4, 5].
fn spike(surface: Surface) -> (Box<dyn Tracer>, relief_core::Aabb) {
    let mut samples = vec![0.0f32; 81];
    samples[4 + 4 * 9] = 5.0;
    let field = Arc::new(HeightField::new(9, 9, samples, GridGeometry::unit()).unwrap());
    let bounds = field.world_bounds(surface);
    (build_tracer(field, surface, TracerKind::Mipmap), bounds)
}

#[test]
fn points_behind_a_spike_are_in_its_shadow() {
    // Sun in the east, 30 degrees up: the spike's shadow falls to the west.
    let to_sun = sun_direction(90.0, 30.0);
    for surface in Surface::ALL {
        let (tracer, _) = spike(surface);
        let mut stats = TraceStats::default();
        let mut vis = |x: f64, y: f64| {
            light_visibility(&*tracer, DVec3::new(x, y, 0.0), DVec3::Z, 10.0, to_sun, &mut stats)
        };
        assert_eq!(vis(3.5, 4.5), 0.0, "{surface}: west of the spike is in shadow");
        assert_eq!(vis(2.6, 4.5), 0.0, "{surface}: farther west too");
        assert_eq!(vis(6.5, 4.5), 1.0, "{surface}: east of the spike is lit");
        assert_eq!(vis(4.5, 7.5), 1.0, "{surface}: north of the spike is lit");
        assert_eq!(vis(3.5, 1.5), 1.0, "{surface}: south-west, beside the shadow, is lit");
        assert_eq!((stats.rays, stats.hits), (5, 2));
    }
}

#[test]
fn shading_pass_darkens_the_spikes_shadow() {
    let (tracer, bounds) = spike(Surface::Boxes);
    let camera = Camera::look_at(
        DVec3::new(4.5, 4.5, 30.0),
        DVec3::new(4.5, 4.5, 0.0),
        DVec3::Y,
        30.0,
        9,
        9,
    )
    .unwrap();
    let (g, _) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
    let sun = Sun { azimuth_deg: 90.0, elevation_deg: 30.0, irradiance: 3.0 };
    let params = lambert_only([0.5; 3], sun);
    let (radiance, shadow) = shade(&g, &*tracer, &camera, &params).unwrap();
    // The pixel looking at ground point (x, y) on this camera.
    let at = |x: f64, y: f64| {
        let k = (0..g.len())
            .min_by(|&a, &b| {
                let d = |k: usize| (g.position[k][0] as f64 - x).hypot(g.position[k][1] as f64 - y);
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        assert_eq!(g.position[k][2], 0.0, "ground pixel");
        radiance[k]
    };
    let lit = 0.5 * 3.0 * 30f64.to_radians().sin() / PI;
    assert_eq!(at(3.0, 4.5), [0.0; 3], "in the shadow: no ambient, no sun");
    assert!((at(6.5, 4.5)[0] as f64 - lit).abs() < 1e-6 * lit, "east of the spike is lit");
    assert!((at(4.5, 1.5)[0] as f64 - lit).abs() < 1e-6 * lit, "south of the spike is lit");
    assert!(shadow.hits > 0 && shadow.hits < shadow.rays);
    // Without shadows the same pixel is lit.
    let (no_shadows, none) =
        shade(&g, &*tracer, &camera, &ShadingParams { shadows: false, ..params }).unwrap();
    assert_eq!(none.rays, 0);
    assert!(
        no_shadows.iter().filter(|p| p[0] == 0.0).count()
            < radiance.iter().filter(|p| p[0] == 0.0).count()
    );
}
