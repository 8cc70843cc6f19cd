//! End-to-end tests of the `relief` binary: outputs, exactness of the depth file, bad input.

mod common;

use common::{assert_refused, depth_straight_down, read_f32_npy, relief, scratch};
use relief_core::{DVec2, GridGeometry, HeightField};
use std::path::Path;
use std::process::Command;

fn png_size(path: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let info = decoder.read_info().unwrap();
    (info.info().width, info.info().height)
}

fn read_npy(path: &Path) -> HeightField {
    relief_io::read_npy_height_field(path).unwrap()
}

#[test]
fn default_render_writes_png_depth_and_normals() {
    let (png, depth, normals) =
        (scratch("default.png"), scratch("default-depth.npy"), scratch("default-n.npy"));
    let out = relief(&[
        "render",
        "--fbm-size",
        "128",
        "--size",
        "64x40",
        "-o",
        png.to_str().unwrap(),
        "--depth",
        depth.to_str().unwrap(),
        "--normals",
        normals.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(png_size(&png), (64, 40));
    let (shape, d) = read_f32_npy(&depth);
    assert_eq!(shape, [40, 64]);
    assert!(d.iter().any(|v| v.is_finite()) && d.contains(&f32::INFINITY));
    let (shape, n) = read_f32_npy(&normals);
    assert_eq!(shape, [40, 64, 3]);
    for (k, normal) in n.chunks_exact(3).enumerate() {
        let length = normal.iter().map(|c| c * c).sum::<f32>().sqrt();
        let expected = if d[k].is_finite() { 1.0 } else { 0.0 };
        assert!((length - expected).abs() < 1e-5, "pixel {k}: normal {normal:?}, depth {}", d[k]);
    }
}

#[test]
fn depth_file_matches_the_closed_form_on_a_flat_terrain() {
    // A 50 x 40 grid at height 7 (z scale 2 => 14), spacing 3 x 2, seen straight from above.
    let input = scratch("flat.npy");
    let field = HeightField::new(50, 40, vec![7.0; 2000], GridGeometry::unit()).unwrap();
    relief_io::write_height_field_npy(&input, &field).unwrap();
    let depth = scratch("flat-depth.npy");
    let out = relief(&[
        "render",
        input.to_str().unwrap(),
        "--spacing",
        "3,2",
        "--z-scale",
        "2",
        "--surface",
        "boxes",
        "--eye",
        "75,40,114",
        "--target",
        "75,40,0",
        "--up",
        "0,1,0",
        "--fov",
        "30",
        "--size",
        "32x24",
        "-o",
        scratch("flat.png").to_str().unwrap(),
        "--depth",
        depth.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let d = read_npy(&depth);
    let t = (15f64.to_radians()).tan();
    for j in 0..24 {
        for i in 0..32 {
            // DESIGN.md's camera: the ray's cosine to the view axis gives the distance to z = 14.
            let sx = (2.0 * (i as f64 + 0.5) / 32.0 - 1.0) * t * 32.0 / 24.0;
            let sy = (1.0 - 2.0 * (j as f64 + 0.5) / 24.0) * t;
            let want = 100.0 * (1.0 + sx * sx + sy * sy).sqrt();
            let got = d.sample(i, j) as f64;
            assert!((got - want).abs() <= 1e-5 * want, "pixel ({i},{j}): {got} vs {want}");
        }
    }
}

#[test]
fn renders_are_identical_whatever_the_thread_count() {
    let render = |threads: &str, name: &str| {
        let png = scratch(name);
        let out = Command::new(env!("CARGO_BIN_EXE_relief"))
            .env("RAYON_NUM_THREADS", threads)
            .args(["render", "--fbm-size", "96", "--size", "48x32", "-o", png.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(out.status.success());
        std::fs::read(png).unwrap()
    };
    assert_eq!(render("1", "one.png"), render("2", "two.png"));
}

#[test]
fn generate_is_deterministic_and_readable() {
    let (a, b) = (scratch("a.npy"), scratch("b.npy"));
    for p in [&a, &b] {
        let out =
            relief(&["generate", "fbm", "--size", "33", "--seed", "5", "-o", p.to_str().unwrap()]);
        assert!(out.status.success());
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let f = read_npy(&a);
    assert_eq!((f.width(), f.height()), (33, 33));
    assert!(f.max_sample() > f.min_sample());
}

#[test]
fn bad_input_is_refused_with_exit_code_2_and_no_output() {
    let png = scratch("never.png");
    let missing = relief(&["render", "/nonexistent/relief.npy", "-o", png.to_str().unwrap()]);
    assert_refused(&missing, "/nonexistent/relief.npy");
    let truncated = scratch("truncated.npy");
    std::fs::write(&truncated, b"\x93NUMPY\x01\x00\x10\x00{'descr'").unwrap();
    assert_refused(
        &relief(&["render", truncated.to_str().unwrap(), "-o", png.to_str().unwrap()]),
        "truncated.npy",
    );
    assert!(!png.exists(), "a refused render must not leave an output");

    assert_refused(&relief(&["render", "--size", "0x10"]), "--size");
    assert_refused(&relief(&["render", "--eye", "1,2,3", "--target", "1,2,3"]), "camera");
    assert_refused(&relief(&["render", "--fov", "190", "--fbm-size", "16"]), "field of view");
    assert_refused(&relief(&["render", "--spacing", "0"]), "spacing");
    assert_refused(
        &relief(&["render", "--fbm-size", "16", "--size", "4000x3000", "--max-memory", "20M"]),
        "memory limit",
    );
    assert_refused(&relief(&["render", "--surface", "spheres"]), "spheres");
    assert_refused(
        &relief(&["render", "--fbm-size", "16", "-o", "/nonexistent-dir/x.png"]),
        "does not exist",
    );
    assert_refused(
        &relief(&["render", "--fbm-size", "16", "-o", std::env::temp_dir().to_str().unwrap()]),
        "directory",
    );
    assert_refused(&relief(&["info", std::env::temp_dir().to_str().unwrap()]), "");
}

#[test]
fn georeferenced_origin_is_kept_in_world_space() {
    // The npy reader has no georeference; spacing still applies: a 10 x 10 ramp spaced 5 m.
    let input = scratch("ramp.npy");
    let samples = (0..100).map(|k| (k % 10) as f32).collect();
    let field = HeightField::new(
        10,
        10,
        samples,
        GridGeometry { origin: DVec2::ZERO, ..GridGeometry::unit() },
    )
    .unwrap();
    relief_io::write_height_field_npy(&input, &field).unwrap();
    // Straight down over texel (6, 3): world centre (32.5, 17.5); boxes top at 6.
    assert_eq!(depth_straight_down(&input, 32.5, 17.5, 50.0, &["--spacing", "5"]), 44.0);
}
