//! `relief convert` keeps the georeference, as GDAL (through rasterio) reads it back: the CRS
//! and the transform of geographic (EPSG:4326), UTM and US-survey-feet (EPSG:2274) GeoTIFFs
//! and of an SRTM tile, in a GeoTIFF, an ESRI grid with its `.prj`, and a PNG with its world
//! file and `.prj`; the heights as stored (a PNG's within its step, in the unit its tEXt
//! names). Read back by relief and written as GeoTIFFs, those outputs are the source again.

mod common;

use common::{clients, python, relief, scratch};

fn main() {
    clients::run(vec![
        clients::trial!(convert_keeps_crs_transform_and_heights_for_gdal, Rasterio),
        clients::trial!(an_srtm_tile_converts_to_wgs84_as_gdal_places_it, Rasterio),
    ]);
}

/// The checks GDAL makes of each converted file, as a Python function `check(src, out, exact)`
/// that prints nothing and raises on a difference.
const CHECK: &str = r#"
import json, sys
import numpy as np
import rasterio
from rasterio.crs import CRS

def epsg(crs):
    return crs.to_epsg(confidence_threshold=20) if crs else None

def png_scale(path):
    from PIL import Image
    text = Image.open(path).text
    return float(text["height_scale"]), float(text["height_offset"]), text["height_unit"]

def check(src_path, out_path, png=None):
    with rasterio.open(src_path) as src, rasterio.open(out_path) as out:
        assert out.crs is not None, f"{out_path}: no CRS"
        assert epsg(out.crs) == epsg(src.crs), f"{out_path}: {out.crs} is not {src.crs}"
        if out_path.endswith(".tif"):
            assert out.crs == src.crs, f"{out_path}: {out.crs.to_wkt()} != {src.crs.to_wkt()}"
        if src.crs.is_projected:
            assert out.crs.linear_units_factor[1] == src.crs.linear_units_factor[1], out_path
        a, b = src.transform, out.transform
        assert all(abs(x - y) <= 1e-9 * max(1.0, abs(x)) for x, y in zip(a[:6], b[:6])), f"{out_path}: {b} != {a}"
        assert (out.width, out.height) == (src.width, src.height), out_path
        want = src.read(1).astype(np.float64)
        got = out.read(1).astype(np.float64)
        tolerance = 0.0
        if out_path.endswith(".png"):
            scale, offset, unit = png_scale(out_path)
            got = got * scale + offset
        if out_path.endswith(".png") or png:
            scale = png_scale(png or out_path)[0]
            tolerance = scale / 2 + 1e-6 * np.abs(want).max()
        worst = np.abs(got - want).max()
        assert worst <= tolerance, f"{out_path}: heights differ by {worst} (tolerance {tolerance})"
"#;

/// Writes the test GeoTIFFs with rasterio: EPSG:32617 (metres), EPSG:2274 (US survey feet,
/// fractional heights), EPSG:4326 (3 arc-seconds, int16 as SRTM); and an SRTM tile.
const MAKE: &str = r#"
import numpy as np
import rasterio
from rasterio.transform import from_origin
rows, cols = np.mgrid[0:40, 0:50]
heights = (900 + 40 * np.sin(cols / 7.0) * np.cos(rows / 5.0) + 1.25 * rows).astype(np.float32)
for name, crs, transform, dtype in [
    ("utm.tif", "EPSG:32617", from_origin(500000, 4000000, 30, 30), "float32"),
    ("feet.tif", "EPSG:2274", from_origin(1700010, 600000, 30, 30), "float32"),
    ("wgs84.tif", "EPSG:4326", from_origin(-84.5, 36.75, 1 / 1200, 1 / 1200), "int16"),
]:
    with rasterio.open(DIR + "/" + name, "w", driver="GTiff", width=50, height=40, count=1,
                       dtype=dtype, crs=crs, transform=transform) as d:
        d.write(heights.astype(dtype)[None])
tile = (200 + (np.mgrid[0:1201, 0:1201][1] % 97)).astype(">i2")
tile.tofile(DIR + "/N36W085.hgt")
print("made")
"#;

fn convert_keeps_crs_transform_and_heights_for_gdal() {
    let dir = scratch("georeference-clients");
    std::fs::create_dir_all(&dir).unwrap();
    let d = dir.to_str().unwrap().to_string();
    let made = python("rasterio", &format!("DIR = {d:?}\n{MAKE}")).unwrap();
    assert_eq!(made, "made");
    let fixture =
        concat!(env!("CARGO_MANIFEST_DIR"), "/../relief-io/tests/fixtures/jacksboro_fault_dem.tif");
    let mut checks = String::new();
    let sources = [
        format!("{d}/utm.tif"),
        format!("{d}/feet.tif"),
        format!("{d}/wgs84.tif"),
        format!("{d}/N36W085.hgt"),
        fixture.to_string(),
    ];
    for (i, source) in sources.iter().enumerate() {
        for ext in ["tif", "asc", "png"] {
            let out = format!("{d}/out{i}.{ext}");
            let run = relief(&["convert", source, &out]);
            let said = String::from_utf8_lossy(&run.stderr).to_string();
            assert!(run.status.success(), "{source} -> {out}: {said}");
            if ext != "tif" {
                assert!(said.contains(".prj ("), "{source} -> {out}: {said}");
            }
            checks.push_str(&format!("check({source:?}, {out:?})\n"));
            if ext != "tif" {
                // Read back by relief (the .prj, the world file, the tEXt scale) and written
                // as a GeoTIFF, it is the source again.
                let back = format!("{d}/out{i}-{ext}-back.tif");
                let run = relief(&["convert", &out, &back]);
                let said = String::from_utf8_lossy(&run.stderr).to_string();
                assert!(run.status.success(), "{out} -> {back}: {said}");
                let png = if ext == "png" { format!("{out:?}") } else { "None".into() };
                checks.push_str(&format!("check({source:?}, {back:?}, {png})\n"));
            }
        }
    }
    let script = format!("{CHECK}\n{checks}print('ok')");
    assert_eq!(python("rasterio", &script).as_deref(), Some("ok"));
}

fn an_srtm_tile_converts_to_wgs84_as_gdal_places_it() {
    let dir = scratch("georeference-hgt");
    std::fs::create_dir_all(&dir).unwrap();
    let d = dir.to_str().unwrap().to_string();
    python("rasterio", &format!("DIR = {d:?}\n{MAKE}")).unwrap();
    let out = format!("{d}/tile.tif");
    let run = relief(&["convert", &format!("{d}/N36W085.hgt"), &out]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let script = format!(
        "import rasterio\nwith rasterio.open({out:?}) as t, rasterio.open({:?}) as h:\n    \
         assert t.crs.to_epsg() == 4326, t.crs\n    \
         assert all(abs(a - b) < 1e-12 for a, b in zip(t.transform[:6], h.transform[:6])), (t.transform, h.transform)\n\
         print('ok')",
        format!("{d}/N36W085.hgt")
    );
    assert_eq!(python("rasterio", &script).as_deref(), Some("ok"));
}
