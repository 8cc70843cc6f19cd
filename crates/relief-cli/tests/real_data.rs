//! End-to-end tests on real elevation data and every format: info, render, convert, limits.

mod common;

use common::{depth_straight_down, relief, scratch, stdout_of};
use std::path::{Path, PathBuf};

const JACKSBORO: &str = "../relief-io/tests/fixtures/jacksboro_fault_dem.tif";

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(JACKSBORO)
}

/// The number after `key` on its line of `relief info`'s output.
fn numbers_on(text: &str, key: &str) -> Vec<f64> {
    let line =
        text.lines().find(|l| l.starts_with(key)).unwrap_or_else(|| panic!("no {key} in {text}"));
    line[key.len()..]
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .filter_map(|s| s.parse().ok())
        .collect()
}

#[test]
fn info_reports_the_jacksboro_dem() {
    let text = stdout_of(&relief(&["info", fixture().to_str().unwrap()]));
    assert!(text.contains("GeoTIFF"), "{text}");
    assert!(text.contains("int16"), "{text}");
    assert_eq!(numbers_on(&text, "size:")[..2], [403.0, 344.0]);
    let spacing = numbers_on(&text, "spacing:");
    assert!((spacing[0] - 74.5).abs() < 0.3 && (spacing[1] - 92.5).abs() < 0.3, "{text}");
    assert!(text.contains("from 3.000\" x 3.000\""), "{text}");
    assert_eq!(numbers_on(&text, "values:"), [236.0, 1076.0]);
}

#[test]
fn renders_the_jacksboro_dem_with_its_own_georeference() {
    let (png, depth) = (scratch("jacksboro.png"), scratch("jacksboro-depth.npy"));
    let out = relief(&[
        "render",
        fixture().to_str().unwrap(),
        "--size",
        "80x45",
        "-o",
        png.to_str().unwrap(),
        "--depth",
        depth.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
}

#[test]
fn converts_between_every_format_and_back() {
    let source = fixture();
    let tif = scratch("back.tif");
    for ext in ["asc", "npy", "tif"] {
        let out_path = scratch(&format!("jacksboro.{ext}"));
        let out = relief(&["convert", source.to_str().unwrap(), out_path.to_str().unwrap()]);
        assert!(out.status.success(), "{ext}: {}", String::from_utf8_lossy(&out.stderr));
        let back = relief(&["convert", out_path.to_str().unwrap(), tif.to_str().unwrap()]);
        assert!(back.status.success(), "{ext}: {}", String::from_utf8_lossy(&back.stderr));
        let text = stdout_of(&relief(&["info", tif.to_str().unwrap()]));
        assert_eq!(numbers_on(&text, "size:")[..2], [403.0, 344.0], "{ext}: {text}");
        assert_eq!(numbers_on(&text, "values:"), [236.0, 1076.0], "{ext}: {text}");
    }
    // PNG (16-bit grey) keeps the integer heights; .hgt needs a 1201 or 3601 square tile.
    let png = scratch("jacksboro16.png");
    assert!(relief(&["convert", source.to_str().unwrap(), png.to_str().unwrap()]).status.success());
    let text = stdout_of(&relief(&["info", png.to_str().unwrap()]));
    assert_eq!(numbers_on(&text, "values:"), [236.0, 1076.0]);
    let hgt = relief(&["convert", source.to_str().unwrap(), scratch("x.hgt").to_str().unwrap()]);
    assert_eq!(hgt.status.code(), Some(2));
}

#[test]
fn hgt_tiles_round_trip_through_the_cli() {
    // A 1201 x 1201 tile with a void, written as .asc by hand, converted to .hgt and back.
    let asc = scratch("tile.asc");
    let mut text = String::from(
        "ncols 1201\nnrows 1201\nxllcorner 0\nyllcorner 0\ncellsize 90\nNODATA_value -32768\n",
    );
    for r in 0..1201 {
        let row: Vec<String> =
            (0..1201)
                .map(|c| {
                    if (r, c) == (600, 600) {
                        "-32768".into()
                    } else {
                        ((r + c) % 700).to_string()
                    }
                })
                .collect();
        text.push_str(&row.join(" "));
        text.push('\n');
    }
    std::fs::write(&asc, text).unwrap();
    let hgt = scratch("N36W085.hgt");
    let out = relief(&["convert", asc.to_str().unwrap(), hgt.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let info = stdout_of(&relief(&["info", hgt.to_str().unwrap()]));
    assert!(info.contains("SRTM"), "{info}");
    assert_eq!(numbers_on(&info, "nodata:")[0], 1.0, "{info}");
    assert!(info.contains("latitude 36.5"), "{info}");
}

#[test]
fn voids_become_holes_or_are_filled() {
    let asc = scratch("voids.asc");
    let mut text = String::from(
        "ncols 20\nnrows 10\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n",
    );
    for r in 0..10 {
        let row: Vec<&str> =
            (0..20).map(|c| if (3..8).contains(&c) && r > 2 { "-9999" } else { "5" }).collect();
        text.push_str(&row.join(" "));
        text.push('\n');
    }
    std::fs::write(&asc, text).unwrap();
    for voids in ["fill", "hole"] {
        let d = depth_straight_down(&asc, 5.5, 5.0, 30.0, &["--voids", voids]);
        match voids {
            "fill" => assert_eq!(d, 25.0, "filled voids take the surrounding height"),
            _ => assert_eq!(d, f32::INFINITY, "a hole lets the ray through"),
        }
    }
}

#[test]
fn a_raster_over_the_memory_limit_is_refused_before_reading() {
    let out = relief(&["info", fixture().to_str().unwrap(), "--max-memory", "100K"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("memory limit") && stderr.contains("--max-memory"), "{stderr}");
}

#[test]
fn unknown_and_broken_files_are_refused() {
    let odd = scratch("terrain.xyz");
    std::fs::write(&odd, "1 2 3").unwrap();
    let out = relief(&["info", odd.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("file type"));
    let bytes = std::fs::read(fixture()).unwrap();
    let cut = scratch("cut.tif");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let png = scratch("cut.png");
    let out = relief(&["render", cut.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!png.exists());
}

/// The same ramp written in every format relief reads, each rendered from the command line.
#[test]
fn every_format_renders_from_the_cli() {
    use relief_core::{GridGeometry, HeightField};
    let ramp = |w: usize, h: usize| {
        let samples = (0..w * h).map(|k| 100.0 + (k % w) as f32 + 2.0 * (k / w) as f32).collect();
        HeightField::new(w, h, samples, GridGeometry::unit()).unwrap()
    };
    let field = ramp(32, 24);
    let mut files: Vec<(PathBuf, Vec<&str>)> = Vec::new();
    for ext in ["tif", "asc", "npy", "png"] {
        let path = scratch(&format!("ramp.{ext}"));
        relief_io::write_height_field(&path, &field).unwrap();
        files.push((path, vec![]));
    }
    let tile = scratch("N10E020.hgt");
    relief_io::write_height_field(&tile, &ramp(1201, 1201)).unwrap();
    files.push((tile, vec![]));
    // Web-map tiles: terrain-RGB and Terrarium encodings of the same heights, north row first.
    let north_first: Vec<f32> = (0..24)
        .rev()
        .flat_map(|r| (0..32).map(move |c| (c, r)))
        .map(|(c, r)| field.sample(c, r))
        .collect();
    let rows_north_first = || north_first.iter().copied();
    let terrain_rgb: Vec<u8> = rows_north_first()
        .flat_map(|h| {
            let v = ((h as f64 + 10000.0) * 10.0).round() as u32;
            [(v >> 16) as u8, (v >> 8) as u8, v as u8]
        })
        .collect();
    let terrarium: Vec<u8> = rows_north_first()
        .flat_map(|h| {
            let v = h as f64 + 32768.0;
            [(v / 256.0) as u8, (v % 256.0) as u8, ((v.fract()) * 256.0) as u8]
        })
        .collect();
    for (name, rgb, encoding) in
        [("rgb.png", terrain_rgb, "terrain-rgb"), ("terrarium.png", terrarium, "terrarium")]
    {
        let path = scratch(name);
        relief_io::write_png_rgb8(&path, 32, 24, &rgb).unwrap();
        files.push((path, vec!["--png-encoding", encoding]));
    }
    // An .npz archive holding the .npy as its second member, picked by name.
    let npz = scratch("ramp.npz");
    {
        let mut zip = zip::ZipWriter::new(std::fs::File::create(&npz).unwrap());
        let options = zip::write::SimpleFileOptions::default();
        zip.start_file("other.npy", options).unwrap();
        std::io::Write::write_all(&mut zip, &std::fs::read(scratch("ramp.npy")).unwrap()).unwrap();
        zip.start_file("heights.npy", options).unwrap();
        std::io::Write::write_all(&mut zip, &std::fs::read(scratch("ramp.npy")).unwrap()).unwrap();
        zip.finish().unwrap();
    }
    files.push((npz, vec!["--array", "heights"]));

    for (path, extra) in &files {
        let depth = scratch("format-depth.npy");
        let mut args = vec!["render", path.to_str().unwrap(), "--size", "24x16", "-o"];
        let png = scratch("format.png");
        args.extend([png.to_str().unwrap(), "--depth", depth.to_str().unwrap()]);
        args.extend(extra.iter().copied());
        let out = relief(&args);
        assert!(
            out.status.success(),
            "{}: {}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        let bytes = std::fs::read(&depth).unwrap();
        let hits = bytes[128..]
            .chunks_exact(4)
            .filter(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]).is_finite())
            .count();
        assert!(hits > 24 * 16 / 10, "{}: only {hits} pixels see the terrain", path.display());
        let info = stdout_of(&relief(&[&["info", path.to_str().unwrap()][..], extra].concat()));
        let expected_max = if path.extension().unwrap() == "hgt" { 3700.0 } else { 177.0 };
        assert_eq!(
            numbers_on(&info, "values:"),
            [100.0, expected_max],
            "{}: {info}",
            path.display()
        );
    }
}
