//! `relief shade` end to end: its layers lie on the DEM's grid, sample for sample, with the
//! DEM's georeference, CRS and nodata, as GDAL (through rasterio) reads them back; a DEM in
//! degrees keeps its grid; a PNG layer is placed by its world file. Each needs rasterio: where
//! it is missing, the test is reported ignored (tests/common/clients.rs).

mod common;

use common::{clients, python, relief, scratch};

fn main() {
    clients::run(vec![
        clients::trial!(layers_lie_on_the_grid_of_a_projected_dem_with_voids, Rasterio),
        clients::trial!(a_dem_in_degrees_keeps_its_grid, Rasterio),
        clients::trial!(a_png_layer_is_placed_by_its_world_file, Rasterio),
    ]);
}

/// Runs relief and fails with its error output unless it succeeded.
fn ok(args: &[&str]) {
    let out = relief(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

fn layers_lie_on_the_grid_of_a_projected_dem_with_voids() {
    let dir = scratch("shade projected");
    std::fs::create_dir_all(&dir).unwrap();
    let (dem, shade) = (dir.join("dem.tif"), dir.join("shade.tif"));
    // An int16 UTM DEM with voids, ZSTD-compressed in tiles, as GDAL writes modern rasters.
    let made = python(
        "rasterio",
        &format!(
            r#"import numpy as np, rasterio
from rasterio.transform import from_origin
y, x = np.mgrid[0:48, 0:40]
z = (300 + 80 * np.sin(x / 5.0) * np.cos(y / 7.0) + 3 * y).astype('int16')
z[10:13, 20:24] = -32768
z[0, 0] = -32768
with rasterio.open(r'{}', 'w', driver='GTiff', width=40, height=48, count=1,
        dtype='int16', crs='EPSG:32633', nodata=-32768, compress='zstd', tiled=True,
        blockxsize=16, blockysize=16,
        transform=from_origin(500000, 4100000, 30, 30)) as f:
    f.write(z, 1)
print('made')"#,
            dem.display()
        ),
    );
    assert_eq!(made.as_deref(), Some("made"));
    ok(&[
        "shade",
        dem.to_str().unwrap(),
        "-o",
        shade.to_str().unwrap(),
        "--layers",
        "shadow,sky,hillshade,combined",
        "--sun",
        "270,20",
        "--azimuths",
        "16",
    ]);
    let report = python(
        "rasterio",
        &format!(
            r#"import numpy as np, rasterio
d = rasterio.open(r'{}'); s = rasterio.open(r'{}')
assert (s.width, s.height) == (d.width, d.height), (s.width, s.height)
assert s.transform == d.transform, (s.transform, d.transform)
assert s.crs == d.crs, (s.crs, d.crs)
assert s.nodata == d.nodata == -32768, s.nodata
assert s.count == 4 and set(s.dtypes) == {{'float32'}}, (s.count, s.dtypes)
assert s.descriptions == ('shadow', 'sky', 'hillshade', 'combined'), s.descriptions
void = d.read(1) == -32768
for band in range(1, 5):
    v = s.read(band)
    assert ((v == -32768) == void).all(), band
    assert ((v[~void] >= 0) & (v[~void] <= 1)).all(), band
shadow = s.read(1)[~void]
assert (shadow == 0).any() and (shadow == 1).any(), 'a low sun casts shadows'
print('aligned')"#,
            dem.display(),
            shade.display()
        ),
    );
    assert_eq!(report.as_deref(), Some("aligned"));
}

fn a_dem_in_degrees_keeps_its_grid() {
    let dir = scratch("shade degrees");
    std::fs::create_dir_all(&dir).unwrap();
    let (hgt, shade) = (dir.join("N36W085.hgt"), dir.join("hillshade.tif"));
    ok(&["generate", "fbm", "--size", "1201", "-o", hgt.to_str().unwrap()]);
    ok(&[
        "shade",
        hgt.to_str().unwrap(),
        "-o",
        shade.to_str().unwrap(),
        "--layers",
        "shadow,hillshade",
    ]);
    let report = python(
        "rasterio",
        &format!(
            "import rasterio\n\
             d = rasterio.open(r'{}'); s = rasterio.open(r'{}')\n\
             assert (s.width, s.height) == (1201, 1201)\n\
             assert s.transform == d.transform, (s.transform, d.transform)\n\
             assert s.crs.to_epsg() == 4326, s.crs\n\
             h = s.read(2)\n\
             assert 0.3 < h.mean() < 0.95, h.mean()\n\
             print('degrees')",
            hgt.display(),
            shade.display()
        ),
    );
    assert_eq!(report.as_deref(), Some("degrees"));
}

fn a_png_layer_is_placed_by_its_world_file() {
    let dir = scratch("shade png");
    std::fs::create_dir_all(&dir).unwrap();
    let (dem, png) = (dir.join("dem.tif"), dir.join("combined.png"));
    ok(&["generate", "fbm", "--size", "64", "-o", dem.to_str().unwrap()]);
    ok(&["shade", dem.to_str().unwrap(), "-o", png.to_str().unwrap(), "--azimuths", "8"]);
    assert!(dir.join("combined.pgw").exists(), "the world file is written beside the PNG");
    let report = python(
        "rasterio",
        &format!(
            "import rasterio\n\
             d = rasterio.open(r'{}'); s = rasterio.open(r'{}')\n\
             assert (s.width, s.height, s.dtypes[0]) == (64, 64, 'uint16')\n\
             assert s.transform.almost_equals(d.transform), (s.transform, d.transform)\n\
             print('placed')",
            dem.display(),
            png.display()
        ),
    );
    assert_eq!(report.as_deref(), Some("placed"));
}
