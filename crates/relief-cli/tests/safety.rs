//! End-to-end tests of `relief render --tracer safety`: every variant renders the same depth as
//! the mipmap tracer, shapes are cached and reused only for the same terrain and options, and
//! views the shapes were not built for are refused.

mod common;

use common::{assert_refused, relief, render_depth, scratch};
use std::path::Path;

/// Renders the 48 x 48 fBm terrain with the safety tracer, its shapes cached in `cache`, and
/// `extra` options; returns (depth, stderr).
fn render(name: &str, cache: &Path, extra: &[&str]) -> (Vec<f32>, String) {
    let mut args = vec!["--fbm-size", "48", "--size", "40x30", "--cache-dir"];
    args.push(cache.to_str().unwrap());
    args.extend(extra);
    let (_, depth, stderr) = render_depth(name, &args);
    (depth, stderr)
}

/// The reference: the 48 x 48 fBm terrain rendered by the mipmap tracer with `extra` options.
fn render_mipmap(name: &str, extra: &[&str]) -> Vec<f32> {
    let mut args = vec!["--fbm-size", "48", "--size", "40x30", "--tracer", "mipmap"];
    args.extend(extra);
    render_depth(name, &args).1
}

fn assert_same_depth(a: &[f32], b: &[f32], what: &str) {
    assert_eq!(a.len(), b.len());
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        let same = x == y || (x - y).abs() <= 1e-5 * x.abs().max(y.abs());
        assert!(same, "{what}: pixel {k}: {x} vs {y}");
    }
}

#[test]
fn every_variant_renders_the_exact_depth() {
    let cache = scratch("cache-variants");
    let reference = render_mipmap("mipmap", &[]);
    assert!(reference.iter().any(|d| d.is_finite()));
    let variants = [
        "cyl_all",
        "cyl_all+cone_all",
        "cyl_all+cone_exact",
        "cyl_ext",
        "cyl_ext+cone_all",
        "cyl_ext+cone_ext",
    ];
    for variant in variants {
        for extra in [&[][..], &["--isotropic"][..]] {
            let mut args = vec!["--tracer", "safety", "--safety", variant];
            args.extend(extra);
            let (depth, _) = render(variant, &cache, &args);
            assert_same_depth(&reference, &depth, &format!("{variant} {extra:?}"));
        }
        // The variant's name is a tracer name too.
        let (depth, _) = render(variant, &cache, &["--tracer", variant, "--no-shadows"]);
        assert_same_depth(&reference, &depth, variant);
    }
}

#[test]
fn phi_max_shapes_render_a_steep_view_exactly_and_refuse_a_shallow_one() {
    let cache = scratch("cache-phi");
    let view = ["--eye", "20,10,120", "--target", "24,24,0", "--fov", "30"];
    let high_sun = ["--sun", "0,60"];
    let reference = render_mipmap("phi-mipmap", &[&view[..], &high_sun].concat());
    for variant in ["cyl_all+cone_all", "cyl_ext+cone_ext"] {
        let args = [&view[..], &high_sun, &["--tracer", variant, "--phi-max", "-45"]].concat();
        let (depth, _) = render("phi", &cache, &args);
        assert_same_depth(&reference, &depth, variant);
    }
    // The default three-quarter view looks at the horizon: refused, and nothing is written.
    let png = scratch("phi-refused.png");
    let out = relief(&[
        "render",
        "--fbm-size",
        "48",
        "--size",
        "40x30",
        "--tracer",
        "safety",
        "--phi-max",
        "-45",
        "--cache-dir",
        cache.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_refused(&out, "degrees from horizontal");
    assert!(!png.exists());
    // A low sun casts shadow rays the shapes do not admit either.
    let args = [&view[..], &["--tracer", "safety", "--phi-max", "-45", "--sun", "0,20"]].concat();
    let mut full = vec!["render", "--fbm-size", "48", "--size", "40x30", "--cache-dir"];
    full.push(cache.to_str().unwrap());
    full.extend(["-o", png.to_str().unwrap()]);
    full.extend(args);
    assert_refused(&relief(&full), "raise the sun");
}

#[test]
fn shapes_are_cached_per_terrain_and_options() {
    let cache = scratch("cache-reuse");
    let _ = std::fs::remove_dir_all(&cache);
    let (first, stderr) = render("cache-a", &cache, &["--tracer", "safety"]);
    assert!(stderr.contains("cached in"), "{stderr}");
    let (second, stderr) = render("cache-b", &cache, &["--tracer", "safety"]);
    assert!(stderr.contains("shapes from"), "the second render reuses the shapes: {stderr}");
    assert_eq!(first, second);
    // Another terrain, or other options: computed afresh, never taken from the cache.
    let (_, stderr) = render("cache-c", &cache, &["--tracer", "safety", "--seed", "2"]);
    assert!(stderr.contains("cached in"), "{stderr}");
    let (_, stderr) = render("cache-d", &cache, &["--tracer", "safety", "--isotropic"]);
    assert!(stderr.contains("cached in"), "{stderr}");
    let (_, stderr) = render("cache-e", &cache, &["--tracer", "safety", "--no-cache"]);
    assert!(!stderr.contains("cached in") && !stderr.contains("shapes from"), "{stderr}");
    assert_eq!(std::fs::read_dir(&cache).unwrap().count(), 3);
}

#[test]
fn overwritten_cached_shapes_are_rebuilt_with_a_warning_and_the_same_image() {
    let cache = scratch("cache-damaged");
    let _ = std::fs::remove_dir_all(&cache);
    let (first, _) = render("damaged-a", &cache, &["--tracer", "safety"]);
    let file = std::fs::read_dir(&cache).unwrap().next().unwrap().unwrap().path();
    // Radii overwritten in the middle of the file, its length and header intact.
    let mut bytes = std::fs::read(&file).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle..middle + 64].fill(0x00);
    std::fs::write(&file, &bytes).unwrap();
    let (second, stderr) = render("damaged-b", &cache, &["--tracer", "safety"]);
    assert!(stderr.contains("warning:") && stderr.contains("checksum"), "{stderr}");
    assert_eq!(first, second, "the damaged shapes were used");
    let (_, stderr) = render("damaged-c", &cache, &["--tracer", "safety"]);
    assert!(stderr.contains("shapes from") && !stderr.contains("warning"), "{stderr}");
}

#[test]
fn views_and_surfaces_the_shapes_do_not_serve_are_refused() {
    let cache = scratch("cache-refuse");
    let png = scratch("refused.png");
    let base = ["render", "--fbm-size", "48", "--size", "40x30", "-o", png.to_str().unwrap()];
    let with = |extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend(["--cache-dir", cache.to_str().unwrap()]);
        args.extend(extra);
        relief(&args)
    };
    assert_refused(&with(&["--tracer", "safety", "--surface", "boxes"]), "triangles surface only");
    // Exterior shapes with the eye inside the terrain's bounding box.
    let inside = ["--tracer", "cyl_ext", "--eye", "24,24,0.5", "--target", "40,40,0"];
    assert_refused(&with(&inside), "inside the terrain's bounding box");
    assert_refused(&with(&["--tracer", "cyl_any"]), "unknown");
    assert_refused(&with(&["--tracer", "safety", "--safety", "cyl_all+cone_ext"]), "cyl_ext");
    assert_refused(&with(&["--tracer", "safety", "--phi-max", "95"]), "phi max");
    assert_refused(&with(&["--tracer", "safety", "--max-memory", "100K"]), "memory limit");
    assert!(!png.exists());
}
