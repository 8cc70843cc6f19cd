//! `relief viewshed` end to end: its output lies on the DEM's grid with the DEM's
//! georeference, CRS and nodata as GDAL (through rasterio) reads it back, observers are placed
//! in the DEM's own coordinates, counts of several observers add up, and bad input is refused
//! with one line and exit code 2. The tests that read GeoTIFFs back need rasterio: where it is
//! missing they are reported ignored (tests/common/clients.rs).

mod common;

use common::{assert_refused, clients, python, relief, scratch};
use std::path::Path;

fn main() {
    clients::run(vec![
        clients::trial!(a_viewshed_lies_on_the_grid_of_a_projected_dem_with_voids, Rasterio),
        clients::trial!(counts_of_several_observers_are_sums_of_single_viewsheds, Rasterio),
        clients::trial!(bad_input_is_refused_with_one_line),
    ]);
}

/// Runs relief and fails with its error output unless it succeeded.
fn ok(args: &[&str]) {
    let out = relief(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

/// Writes a 40 x 48 int16 UTM DEM (30 m cells, north-west corner at 500000, 4100000) with
/// voids and a ridge along column 20 to `path`.
fn write_projected_dem(path: &Path) {
    let made = python(
        "rasterio",
        &format!(
            r#"import numpy as np, rasterio
from rasterio.transform import from_origin
y, x = np.mgrid[0:48, 0:40]
z = (300 + 20 * np.sin(x / 5.0) * np.cos(y / 7.0) + y).astype('int16')
z[:, 20] = 600
z[10:13, 30:34] = -32768
z[0, 0] = -32768
with rasterio.open(r'{}', 'w', driver='GTiff', width=40, height=48, count=1,
        dtype='int16', crs='EPSG:32633', nodata=-32768, compress='zstd', tiled=True,
        blockxsize=16, blockysize=16,
        transform=from_origin(500000, 4100000, 30, 30)) as f:
    f.write(z, 1)
print('made')"#,
            path.display()
        ),
    );
    assert_eq!(made.as_deref(), Some("made"));
}

fn a_viewshed_lies_on_the_grid_of_a_projected_dem_with_voids() {
    let dir = scratch("viewshed projected");
    std::fs::create_dir_all(&dir).unwrap();
    let (dem, vis) = (dir.join("dem.tif"), dir.join("vis.tif"));
    write_projected_dem(&dem);
    // The observer at the centre of the file's column 5, row 24 (x = 500000 + 5.5 * 30,
    // y = 4100000 - 24.5 * 30), west of the ridge.
    ok(&[
        "viewshed",
        dem.to_str().unwrap(),
        "-o",
        vis.to_str().unwrap(),
        "--observer",
        "500165,4099265,2",
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
assert s.count == 1 and s.dtypes[0] == 'float32', (s.count, s.dtypes)
assert s.descriptions == ('visible',), s.descriptions
void = d.read(1) == -32768
v = s.read(1)
assert ((v == -32768) == void).all()
assert set(np.unique(v[~void])) <= {{0.0, 1.0}}, np.unique(v)
assert v[24, 5] == 1 and v[24, 20] == 1, 'the observer sees its own sample and the ridge'
assert (v[:, 21:23] == 0).all(), 'the foot of the ridge behind it is hidden'
print('aligned')"#,
            dem.display(),
            vis.display()
        ),
    );
    assert_eq!(report.as_deref(), Some("aligned"));
}

fn counts_of_several_observers_are_sums_of_single_viewsheds() {
    let dir = scratch("viewshed cumulative");
    std::fs::create_dir_all(&dir).unwrap();
    let dem = dir.join("dem.tif");
    write_projected_dem(&dem);
    let observers = ["500165,4099265", "500900,4098800,10", "500615,4100000,0"];
    let mut singles = Vec::new();
    for (k, observer) in observers.iter().enumerate() {
        let out = dir.join(format!("one{k}.tif"));
        ok(&[
            "viewshed",
            dem.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--observer",
            observer,
            "--target-height",
            "1.5",
        ]);
        singles.push(format!("r'{}'", out.display()));
    }
    let all = dir.join("all.tif");
    let dem_arg = dem.to_str().unwrap();
    let all_arg = all.to_str().unwrap();
    let mut args = vec!["viewshed", dem_arg, "-o", all_arg, "--target-height", "1.5"];
    for observer in &observers {
        args.extend(["--observer", observer]);
    }
    ok(&args);
    let report = python(
        "rasterio",
        &format!(
            r#"import numpy as np, rasterio
s = rasterio.open(r'{}')
assert s.descriptions == ('observers',), s.descriptions
total = s.read(1)
void = total == -32768
parts = [rasterio.open(p).read(1) for p in [{}]]
assert np.array_equal(sum(p[~void] for p in parts), total[~void])
assert set(np.unique(total[~void])) >= {{0.0, 1.0, 3.0}}, np.unique(total)
print('sums')"#,
            all.display(),
            singles.join(", ")
        ),
    );
    assert_eq!(report.as_deref(), Some("sums"));
}

fn bad_input_is_refused_with_one_line() {
    let dir = scratch("viewshed refused");
    std::fs::create_dir_all(&dir).unwrap();
    let (dem, vis) = (dir.join("dem.npy"), dir.join("vis.tif"));
    ok(&["generate", "fbm", "--size", "32", "-o", dem.to_str().unwrap()]);
    let (d, o) = (dem.to_str().unwrap(), vis.to_str().unwrap());
    let refused = |extra: &[&str], mentions: &str| {
        let mut args = vec!["viewshed", d, "-o", o];
        args.extend(extra);
        let out = relief(&args);
        assert_refused(&out, mentions);
        assert_eq!(String::from_utf8_lossy(&out.stderr).trim().lines().count(), 1, "{extra:?}");
    };
    refused(&[], "no observer");
    // A .npy has no georeference: grid units, the footprint 0..32 on both axes.
    refused(&["--observer", "40,5"], "outside the DEM");
    refused(&["--observer", "5,-0.5"], "outside the DEM");
    refused(&["--observer", "5,5,-1"], "observer height");
    refused(&["--observer", "5,5,nan"], "observer height");
    refused(&["--observer", "5"], "X,Y");
    refused(&["--observer", "5,5", "--target-height", "-2"], "target-height");
    refused(&["--observer", "5,5", "--radius", "0"], "radius");
    let png = dir.join("vis.png");
    let out = relief(&["viewshed", d, "-o", png.to_str().unwrap(), "--observer", "5,5"]);
    assert_refused(&out, ".tif");
    ok(&["viewshed", d, "-o", o, "--observer", "32,0,0"]);
}
