//! `relief render --tracer hybrid` end to end: with the exact far field its depth equals the
//! mipmap tracer's on every pixel (judged by `relief compare`); with levels of precision it
//! stays close; `--show-lop` colours the picture by what drew each pixel.

mod common;

use common::{relief, scratch, stdout_of};
use serde_json::Value;
use std::path::Path;

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Renders the default fBm terrain (96² samples) from a low view with `extra` options.
fn render(name: &str, extra: &[&str]) -> (std::path::PathBuf, std::path::PathBuf) {
    let (png, depth) = (scratch(&format!("{name}.png")), scratch(&format!("{name}.npy")));
    let mut args = vec![
        "render",
        "--fbm-size",
        "96",
        "--size",
        "120x80",
        "--eye",
        "10,10,35",
        "--target",
        "80,70,10",
        "-o",
        p(&png),
        "--depth",
        p(&depth),
    ];
    args.extend(extra);
    stdout_of(&relief(&args));
    (png, depth)
}

fn compare(reference: &Path, test: &Path) -> Value {
    let out = relief(&["compare", p(reference), p(test), "--json"]);
    serde_json::from_str(stdout_of(&out).trim()).unwrap()
}

#[test]
fn the_exact_far_field_draws_the_exact_tracers_depth() {
    let (_, exact) = render("hy-mipmap", &[]);
    let hybrid = ["--tracer", "hybrid", "--far", "exact", "--cell", "9", "--threshold", "2"];
    let (_, depth) = render("hy-exact", &hybrid);
    let m = compare(&exact, &depth);
    assert_eq!(m["wrong"], 0, "{m}");
    assert!(m["max_rel_error"].as_f64().unwrap() <= 1e-4, "{m}");

    let (_, lop) = render(
        "hy-lop",
        &["--tracer", "hybrid", "--far", "lop", "--cell", "9", "--threshold", "2"],
    );
    let m = compare(&exact, &lop);
    assert!(m["wrong_pixel_fraction"].as_f64().unwrap() < 0.02, "{m}");
}

#[test]
fn show_lop_colours_the_picture_and_stats_count_the_cells() {
    let stats = scratch("hy-stats.json");
    let options = ["--tracer", "hybrid", "--cell", "9", "--threshold", "2"];
    let (plain, _) = render("hy-plain", &options);
    let mut shown = options.to_vec();
    shown.extend(["--show-lop", "--stats", p(&stats)]);
    let (coloured, _) = render("hy-shown", &shown);
    assert_ne!(std::fs::read(plain).unwrap(), std::fs::read(coloured).unwrap());
    let s: Value = serde_json::from_str(&std::fs::read_to_string(stats).unwrap()).unwrap();
    assert_eq!(s["tracer"], "hybrid");
    assert!(s["mesh_cells"].as_u64().unwrap() > 0, "{s}");
    let ray_cast: u64 =
        s["ray_cast_cells"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).sum();
    assert!(ray_cast > 0, "{s}");
    for key in ["load_ms", "build_ms", "trace_ms", "shade_ms", "total_ms"] {
        assert!(s[key].as_f64().unwrap() >= 0.0, "{key}: {s}");
    }
}
