//! End-to-end tests of `relief render --view ... --ortho`: the depth of an orthographic
//! camera, with every tracer the command line offers, is the distance an independent
//! brute-force tracer finds along the rays of the documented convention (origin on the plane
//! through the eye, direction forward), computed here from that convention alone; and a
//! top-down map of a known terrain has the depth and ground size worked out by hand.

mod common;

#[allow(dead_code)]
#[path = "../../relief-trace/tests/common/reference.rs"]
mod reference;

#[allow(dead_code)]
#[path = "../../relief-trace/tests/common/mlhm_reference.rs"]
mod mlhm_reference;

use common::{relief, render_depth, scratch};
use relief_core::{DVec2, DVec3, HeightField, Ray, Surface};
use relief_io::ReadOptions;
use relief_trace::MlhmMode;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The image of every render here.
const W: usize = 64;
const H: usize = 48;

/// The view: heading 30 degrees, 45 degrees up, this far from the target, with this image
/// height; the target is given, so the camera is fully known.
const AZ: f64 = 30.0;
const EL: f64 = 45.0;

/// The rays of an orthographic camera looking towards compass `az` from `el` degrees up, at
/// `distance` from `target`, with an image `height` metres high, as docs/camera.md states
/// them: eye = target + distance (-sin az cos el, -cos az cos el, sin el); forward = the unit
/// vector to the target; right = forward x z; up' = right x forward; pixel (i, j) starts at
/// eye + sx right + sy up' with sx = (2 (i + 0.5) / W - 1) (h / 2) W / H and
/// sy = (1 - 2 (j + 0.5) / H) h / 2, and looks along forward. Row-major, top row first.
fn convention_rays(az: f64, el: f64, distance: f64, target: DVec3, height: f64) -> Vec<Ray> {
    let (a, e) = (az.to_radians(), el.to_radians());
    let towards_eye = DVec3::new(-a.sin() * e.cos(), -a.cos() * e.cos(), e.sin());
    let eye = target + towards_eye * distance;
    let forward = (target - eye).normalize();
    let right = forward.cross(DVec3::Z).normalize();
    let up = right.cross(forward);
    let s = height / 2.0;
    let mut rays = Vec::with_capacity(W * H);
    for j in 0..H {
        for i in 0..W {
            let sx = (2.0 * (i as f64 + 0.5) / W as f64 - 1.0) * s * W as f64 / H as f64;
            let sy = (1.0 - 2.0 * (j as f64 + 0.5) / H as f64) * s;
            rays.push(Ray::new(eye + sx * right + sy * up, forward));
        }
    }
    rays
}

/// The options of that view.
fn view_args(distance: f64, target: DVec3, height: f64) -> Vec<String> {
    vec![
        "--view".into(),
        format!("{AZ},{EL},{distance}"),
        "--target".into(),
        format!("{},{},{}", target.x, target.y, target.z),
        "--ortho".into(),
        "--ortho-height".into(),
        height.to_string(),
        "--size".into(),
        format!("{W}x{H}"),
        "--no-shadows".into(),
    ]
}

/// Checks `depth` against `reference` (f64 distances, `None` a miss): 1e-4 relative on every
/// pixel but `ties` (exact grazing ties, silhouettes); at least `min_hits` hits.
fn assert_matches(depth: &[f32], reference: &[Option<f64>], ties: usize, what: &str) {
    assert_eq!(depth.len(), reference.len(), "{what}");
    let mut wrong = Vec::new();
    for (k, (&d, r)) in depth.iter().zip(reference).enumerate() {
        let ok = match r {
            None => d == f32::INFINITY,
            Some(r) => (d as f64 - r).abs() <= 1e-4 * r.abs().max(1.0),
        };
        if !ok {
            wrong.push((k, d, *r));
        }
    }
    assert!(
        wrong.len() <= ties,
        "{what}: {} pixels differ: {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(8)]
    );
    let hits = reference.iter().filter(|r| r.is_some()).count();
    let misses = reference.len() - hits;
    assert!(hits > reference.len() / 3 && misses > 0, "{what}: {hits} hits, {misses} misses");
}

/// A 32 x 32 fBm terrain (spacing 1) written as .npy, and the field read back.
fn terrain() -> &'static (PathBuf, HeightField) {
    static TERRAIN: OnceLock<(PathBuf, HeightField)> = OnceLock::new();
    TERRAIN.get_or_init(|| {
        let path = scratch("ortho-fbm.npy");
        let out = relief(&["generate", "fbm", "--size", "32", "-o", path.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let field = relief_io::read_npy_height_field(&path).unwrap();
        (path, field)
    })
}

#[test]
fn every_height_field_tracer_renders_the_brute_force_depth_of_the_orthographic_rays() {
    let (path, field) = terrain();
    let bounds = field.world_bounds(Surface::Boxes);
    let centre = bounds.center();
    // Far enough that every ray starts above and outside the terrain; an image a little wider
    // than the terrain, so that the edges miss.
    let (distance, height) = (4.0 * bounds.diagonal(), 0.9 * bounds.diagonal());
    let rays = convention_rays(AZ, EL, distance, centre, height);
    let view = view_args(distance, centre, height);
    let cases: &[(Surface, &[&str])] = &[
        (Surface::Triangles, &["--tracer", "mipmap"]),
        (Surface::Boxes, &["--tracer", "mipmap"]),
        (Surface::Triangles, &["--tracer", "naive"]),
        (Surface::Boxes, &["--tracer", "naive"]),
        (Surface::Triangles, &["--tracer", "safety", "--no-cache"]),
        (Surface::Triangles, &["--tracer", "cyl_ext+cone_ext", "--no-cache"]),
    ];
    for (surface, tracer) in cases {
        let reference: Vec<Option<f64>> =
            rays.iter().map(|r| reference::first_hit(field, *surface, r)).collect();
        let name = format!("ortho-{surface}-{}", tracer[1]);
        let mut args: Vec<&str> = vec![path.to_str().unwrap(), "--surface", surface.name()];
        args.extend(view.iter().map(String::as_str));
        args.extend(*tracer);
        let (shape, depth, _) = render_depth(&name, &args);
        assert_eq!(shape, [H, W], "{name}");
        assert_matches(&depth, &reference, 4, &name);
    }
}

/// A small carved MLHM scene (the 16 x 16 arches, 16 m cells).
fn cave() -> &'static Path {
    static CAVE: OnceLock<PathBuf> = OnceLock::new();
    CAVE.get_or_init(|| {
        let path = scratch("ortho-arches.mlhm");
        let out = relief(&[
            "generate",
            "mlhm",
            "--scene",
            "arches",
            "--size",
            "16",
            "-o",
            path.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        path
    })
}

#[test]
fn mlhm_tracers_render_the_brute_force_depth_of_the_orthographic_rays() {
    let mut map = relief_io::read_mlhm_native(cave(), &ReadOptions::default()).unwrap();
    // The solid ends at the base relief renders it on (a little below the lowest terrain).
    map.set_base(relief_render::scenes::mlhm::mlhm_base(&map));
    let lowest = map.heights().bedrock_min as f64;
    let side = map.width() as f64 * map.cell_size();
    let target = DVec3::new(0.5 * side, 0.5 * side, lowest);
    let (distance, height) = (3.0 * side, 1.1 * side);
    let rays = convention_rays(AZ, EL, distance, target, height);
    // The boxes [floor, bedrock + sand + water] of every column (the lowest from the base),
    // slab by slab.
    let reference: Vec<Option<f64>> = rays
        .iter()
        .map(|r| {
            mlhm_reference::first_hit(&map, DVec2::ZERO, MlhmMode::SolidsWater, r).map(|(t, _)| t)
        })
        .collect();
    let view = view_args(distance, target, height);
    let scene = cave().to_str().unwrap();
    let mut smooth = Vec::new();
    for tracer in [&["--tracer", "naive"][..], &["--tracer", "hierarchy"], &["--backtrack", "miss"]]
    {
        let mut args: Vec<&str> = vec![scene, "--preset", "low"];
        args.extend(view.iter().map(String::as_str));
        args.extend(tracer);
        let name = format!("ortho-mlhm-{}", tracer[1]);
        let (shape, depth, _) = render_depth(&name, &args);
        assert_eq!(shape, [H, W]);
        assert_matches(&depth, &reference, 4, &name);
        // Smooth mode has no brute-force reference: the naive marching and the hierarchy's
        // must agree on the same orthographic rays.
        args.extend(["--mode", "smooth"]);
        let (_, depth, _) = render_depth(&format!("{name}-smooth"), &args);
        let hits = depth.iter().filter(|d| d.is_finite()).count();
        assert!(hits > depth.len() / 3, "{name} smooth: {hits} hits");
        smooth.push(depth);
    }
    for other in &smooth[1..] {
        let differ = smooth[0]
            .iter()
            .zip(other)
            .filter(|(a, b)| !(a == b || (*a - *b).abs() <= 1e-4 * a.abs().max(1.0)))
            .count();
        assert!(differ <= 4, "smooth: naive and hierarchy differ on {differ} pixels");
    }
}

#[test]
fn a_top_down_orthographic_view_is_a_north_up_map_of_known_depth() {
    // A ramp rising one metre a row to the north: sample (c, r) at (c + 0.5, r + 0.5, r).
    let ramp = scratch("ortho-ramp.npy");
    let heights: Vec<f32> = (0..32 * 32).map(|k| (k / 32) as f32).collect();
    relief_io::write_npy_f32(&ramp, &[32, 32], &heights).unwrap();
    // Straight down from 100 m above (16, 16, 0), a 20 m by 15 m view: pixel (i, j) sees the
    // ground point x = 16 + (i + 0.5 - W/2) 20 / W, y = 16 - (j + 0.5 - H/2) 15 / H.
    let (_, depth, _) = render_depth(
        "ortho-ramp",
        &[
            ramp.to_str().unwrap(),
            "--view",
            "0,90,100",
            "--target",
            "16,16,0",
            "--ortho",
            "--ortho-height",
            "15",
            "--size",
            &format!("{W}x{H}"),
        ],
    );
    let ground = 15.0 / H as f64;
    for j in 0..H {
        let y = 16.0 - (j as f64 + 0.5 - H as f64 / 2.0) * ground;
        // On the triangles surface the ramp is the plane z = y - 0.5.
        let want = 100.0 - (y - 0.5);
        for i in 0..W {
            let d = depth[i + j * W] as f64;
            assert!((d - want).abs() < 1e-4, "pixel ({i}, {j}): {d}, want {want}");
        }
    }
    // The default framing of the map holds the whole terrain, north up: the top row is nearer.
    let (_, depth, _) = render_depth(
        "ortho-ramp-framed",
        &[ramp.to_str().unwrap(), "--view", "0,90", "--ortho", "--size", "40x40"],
    );
    let column = |j: usize| depth[20 + j * 40];
    assert!(column(5) < column(34), "north at the top: {} vs {}", column(5), column(34));
    assert!(depth[20 * 40 + 1].is_infinite() || depth[20 * 40 + 1] > 0.0);
    let hits = depth.iter().filter(|d| d.is_finite()).count();
    assert!(hits > 40 * 40 * 3 / 4, "the terrain fills the map: {hits} hits");
}

#[test]
fn nonsense_cameras_are_refused() {
    for (args, says) in [
        (
            &["--ortho", "--fov", "30"][..],
            "--fov applies to perspective cameras only, not to --ortho",
        ),
        (&["--ortho-height", "10"], "--ortho-height applies to --ortho only"),
        (&["--ortho", "--ortho-height", "0"], "orthographic height 0"),
        (&["--ortho", "--ortho-height", "-5"], "orthographic height -5"),
        (&["--view", "30,0"], "more than 0 and at most 90"),
        (&["--view", "30,95"], "more than 0 and at most 90"),
        (&["--view", "30,45,0"], "view distance"),
        (&["--view", "30,45", "--eye", "1,2,3", "--target", "0,0,0"], "cannot be used with"),
    ] {
        let png = scratch("refused.png");
        let mut all =
            vec!["render", "--fbm-size", "16", "--size", "8x8", "-o", png.to_str().unwrap()];
        all.extend(args);
        common::assert_refused(&relief(&all), says);
    }
}
