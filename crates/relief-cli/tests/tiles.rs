//! `relief tile`, `relief info STORE` and `relief render STORE` end to end: a store rendered
//! at an error of 0 gives the untiled raster's picture and depth byte for byte; an interrupted
//! build is reported, refused for rendering and resumed into the same store; damaged tiles and
//! options that do not apply are refused in one line, exit 2.

mod common;

use common::{assert_refused, relief, scratch, stdout_of};
use std::path::{Path, PathBuf};

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// A 200 x 200 fBm GeoTIFF and its store in tiles of 32 (paths with spaces).
fn raster_and_store(name: &str) -> (PathBuf, PathBuf) {
    let tif = scratch(&format!("{name} dem.tif"));
    stdout_of(&relief(&["generate", "fbm", "--size", "200", "-o", p(&tif)]));
    let store = scratch(&format!("{name} store"));
    let _ = std::fs::remove_dir_all(&store);
    stdout_of(&relief(&["tile", p(&tif), "-o", p(&store), "--tile", "32"]));
    (tif, store)
}

fn render(input: &Path, name: &str, extra: &[&str]) -> (Vec<u8>, Vec<u8>) {
    let (png, depth) = (scratch(&format!("{name}.png")), scratch(&format!("{name}.npy")));
    let mut args =
        vec!["render", p(input), "-o", p(&png), "--depth", p(&depth), "--size", "160x100"];
    args.extend(["--eye", "-100,-150,420", "--target", "100,100,0"]);
    args.extend(extra);
    stdout_of(&relief(&args));
    (std::fs::read(png).unwrap(), std::fs::read(depth).unwrap())
}

#[test]
fn a_store_at_error_0_renders_the_raster_byte_for_byte() {
    let (tif, store) = raster_and_store("exact");
    // Faceted normals: each tile's smooth normals come from its own samples, one-sided at
    // its edges, so beside a seam they differ from the whole raster's (relief-tiles'
    // exactness test bounds that); the facets' are the same everywhere.
    let faceted = ["--shading-normals", "faceted"];
    let whole = render(&tif, "exact-whole", &["--voids", "hole", faceted[0], faceted[1]]);
    let tiled = render(&store, "exact-tiled", &["--max-error-px", "0", faceted[0], faceted[1]]);
    assert!(whole.0 == tiled.0, "pictures differ");
    assert!(whole.1 == tiled.1, "depths differ");
    // Smooth (the default), the depth is still the same byte for byte.
    let smooth_whole = render(&tif, "exact-whole-smooth", &["--voids", "hole"]);
    let smooth_tiled = render(&store, "exact-tiled-smooth", &["--max-error-px", "0"]);
    assert!(smooth_whole.1 == tiled.1 && smooth_tiled.1 == tiled.1, "smooth depths differ");
    assert!(smooth_tiled.0 != tiled.0, "smooth normals light the store");
    let whole = render(
        &tif,
        "exact-whole-boxes",
        &["--voids", "hole", "--surface", "boxes", "--no-shadows"],
    );
    let tiled = render(
        &store,
        "exact-tiled-boxes",
        &["--max-error-px", "0", "--surface", "boxes", "--no-shadows"],
    );
    assert!(whole.0 == tiled.0 && whole.1 == tiled.1, "boxes differ");
    // The default error bound draws coarser tiles far away, and says how many tiles it drew.
    let stats = scratch("exact-stats.json");
    let png = scratch("exact-default.png");
    let out =
        relief(&["render", p(&store), "-o", p(&png), "--stats", p(&stats), "--size", "160x100"]);
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && text.contains("tile store"), "{text}");
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(stats).unwrap()).unwrap();
    assert_eq!(stats["tracer"], "tiles");
    assert!(stats["tiles_drawn"].as_u64().unwrap() > 0, "{stats}");
    for key in ["load_ms", "build_ms", "trace_ms", "shade_ms", "total_ms", "io_wait_ms"] {
        assert!(stats[key].as_f64().is_some(), "{key} in {stats}");
    }
}

#[test]
fn an_interrupted_build_is_reported_refused_and_resumed() {
    let (tif, store) = raster_and_store("resume");
    let complete: Vec<(String, Vec<u8>)> = files(&store);
    // What a build killed part way leaves: the index not complete, the last records unwritten.
    let index = store.join("index.json");
    let text = std::fs::read_to_string(&index)
        .unwrap()
        .replace("\"complete\": true", "\"complete\": false");
    std::fs::write(&index, text).unwrap();
    let table = store.join("tiles.table");
    let mut records = std::fs::read(&table).unwrap();
    let n = records.len();
    records[n - 32 * 5..].fill(0);
    std::fs::write(&table, &records).unwrap();
    let info = stdout_of(&relief(&["info", p(&store)]));
    assert!(info.contains("INCOMPLETE") && info.contains("65 of 70 tiles"), "{info}");
    let png = scratch("resume.png");
    assert_refused(&relief(&["render", p(&store), "-o", p(&png)]), "incomplete");
    assert!(!png.exists(), "no picture from an incomplete store");
    let out = relief(&["tile", p(&tif), "-o", p(&store), "--tile", "32"]);
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && text.contains("65 kept"), "{text}");
    assert!(files(&store) == complete, "the resumed store differs");
    // Other options than the interrupted build's are refused, the store left alone.
    assert_refused(&relief(&["tile", p(&tif), "-o", p(&store), "--tile", "64"]), "other options");
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (e.file_name().to_string_lossy().into_owned(), std::fs::read(e.path()).unwrap())
        })
        .collect();
    out.sort();
    out
}

#[test]
fn damaged_stores_and_misplaced_options_are_refused() {
    let (tif, store) = raster_and_store("damaged");
    let data = store.join("tiles.data");
    let mut bytes = std::fs::read(&data).unwrap();
    bytes[40] ^= 0x10; // the first tile of level 0
    std::fs::write(&data, &bytes).unwrap();
    let png = scratch("damaged.png");
    let out = relief(&["render", p(&store), "-o", p(&png), "--max-error-px", "0"]);
    assert_refused(&out, "tile (level 0, column 0, row 0)");
    assert!(!png.exists());
    bytes.truncate(1000);
    std::fs::write(&data, &bytes).unwrap();
    assert_refused(&relief(&["render", p(&store), "-o", p(&png)]), "truncated");

    assert_refused(&relief(&["render", p(&tif), "--max-error-px", "1"]), "--max-error-px");
    assert_refused(&relief(&["render", p(&store), "--tracer", "naive"]), "--tracer");
    assert_refused(&relief(&["render", p(&store), "--cache-mb", "-5"]), "--cache-mb");
    assert_refused(&relief(&["tile", p(&tif), "-o", p(&tif)]), "folder");
    assert_refused(&relief(&["tile", p(&tif), "-o", p(&scratch("x")), "--tile", "3"]), "--tile");
    let not_a_store = scratch("not a store");
    std::fs::create_dir_all(&not_a_store).unwrap();
    std::fs::write(not_a_store.join("mine.txt"), "x").unwrap();
    assert_refused(&relief(&["info", p(&not_a_store)]), "not a tile store");
    assert_refused(&relief(&["tile", p(&tif), "-o", p(&not_a_store)]), "not a tile store");
}
