//! Heights in the unit their file says: a DEM in US survey feet renders, shades and reports
//! as the same DEM in metres (or `--z-unit` says otherwise); `relief info` names the unit and
//! why; 16-bit PNG heights keep their fractions, within their documented step.

mod common;

use common::{read_f32_npy, relief, scratch, stdout_of};
use relief_core::{GridGeometry, HeightField};
use relief_io::{GeoTiffTags, Georeference, LengthUnit};
use std::path::{Path, PathBuf};

/// Columns and rows of the test DEMs.
const SIZE: (usize, usize) = (48, 40);

/// Heights in metres of the test DEM, row 0 south.
fn metres() -> Vec<f32> {
    let (w, h) = SIZE;
    (0..w * h)
        .map(|k| {
            let (c, r) = ((k % w) as f32, (k / w) as f32);
            300.0 + 40.0 * (c / 7.0).sin() * (r / 5.0).cos() + 1.5 * r
        })
        .collect()
}

/// A GeoTIFF placed by `keys` (a projected CRS), `pixel` model units a side, its north-west
/// corner at (`west`, `north`), holding `samples`.
fn geotiff(
    name: &str,
    keys: Vec<u16>,
    pixel: f64,
    (west, north): (f64, f64),
    samples: Vec<f32>,
) -> PathBuf {
    let path = scratch(name);
    let (w, h) = SIZE;
    let tags = GeoTiffTags {
        model_pixel_scale: Some(vec![pixel, pixel, 0.0]),
        model_tiepoint: Some(vec![0.0, 0.0, 0.0, west, north, 0.0]),
        geo_key_directory: Some(keys),
        ..GeoTiffTags::default()
    };
    let georeference = Georeference::from_geotiff_tags(tags).unwrap();
    let field = HeightField::new(w, h, samples, GridGeometry::unit()).unwrap();
    relief_io::write_geotiff_placed(&path, &field, Some(&georeference)).unwrap();
    path
}

/// NAD83 / Tennessee (ftUS), EPSG:2274, by its code alone (no unit key): 30 ft pixels.
fn feet_dem() -> PathBuf {
    #[rustfmt::skip]
    let keys = vec![1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 2274];
    let feet = LengthUnit::UsSurveyFoot.metres();
    let samples = metres().iter().map(|&m| (f64::from(m) / feet) as f32).collect();
    geotiff("dem-ftUS.tif", keys, 30.0, (1_700_010.0, 600_000.0), samples)
}

/// The same DEM in a CRS in metres (a user-defined projected CRS in metres), its corner and
/// pixels at the same places in metres.
fn metre_dem(name: &str, samples: Vec<f32>) -> PathBuf {
    #[rustfmt::skip]
    let keys = vec![1, 1, 0, 4, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 32767, 3076, 0, 1, 9001];
    let feet = LengthUnit::UsSurveyFoot.metres();
    geotiff(name, keys, 30.0 * feet, (1_700_010.0 * feet, 600_000.0 * feet), samples)
}

/// The depth image `relief render` draws of `dem` (automatic framing) with `extra` options.
fn depth(dem: &Path, name: &str, extra: &[&str]) -> Vec<f32> {
    let (png, npy) = (scratch(&format!("{name}.png")), scratch(&format!("{name}.npy")));
    let mut args = vec!["render", dem.to_str().unwrap(), "--size", "64x48"];
    args.extend(["-o", png.to_str().unwrap(), "--depth", npy.to_str().unwrap()]);
    args.extend(extra);
    let out = relief(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    read_f32_npy(&npy).1
}

/// Whether two depth images agree to `tolerance` relative on every pixel (misses alike).
fn same_depths(a: &[f32], b: &[f32], tolerance: f32) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            (x.is_infinite() && y.is_infinite()) || (x - y).abs() <= tolerance * x.abs().max(1.0)
        })
}

#[test]
fn a_dem_in_us_survey_feet_renders_as_the_same_dem_in_metres() {
    let (feet, metre) = (feet_dem(), metre_dem("dem-m.tif", metres()));
    let in_metres = depth(&metre, "units-m", &[]);
    assert!(in_metres.iter().any(|d| d.is_finite()));
    let in_feet = depth(&feet, "units-ft", &[]);
    assert!(same_depths(&in_feet, &in_metres, 1e-4), "the DEM in feet renders differently");
    // Told its heights are metres, the same file is 3.28 times as high: another picture.
    let misread = depth(&feet, "units-ft-as-m", &["--z-unit", "m"]);
    assert!(!same_depths(&misread, &in_metres, 1e-2));
    // A file whose heights are feet in a CRS in metres, told so.
    let feet_up = LengthUnit::UsSurveyFoot.metres();
    let heights_in_feet = metres().iter().map(|&m| (f64::from(m) / feet_up) as f32).collect();
    let told = metre_dem("dem-m-heights-ft.tif", heights_in_feet);
    let told = depth(&told, "units-told", &["--z-unit", "us-ft"]);
    assert!(same_depths(&told, &in_metres, 1e-4));
}

#[test]
fn a_tile_store_of_a_dem_in_feet_renders_as_the_same_dem_in_metres() {
    let in_metres = depth(&metre_dem("tiled-m.tif", metres()), "tiled-m", &[]);
    let store = |dem: &Path, name: &str, extra: &[&str]| {
        let store = scratch(name);
        let _ = std::fs::remove_dir_all(&store);
        let mut args = vec!["tile", dem.to_str().unwrap(), "-o", store.to_str().unwrap()];
        args.extend(["--tile", "16"]);
        args.extend(extra);
        let out = relief(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        store
    };
    // The unit follows the CRS (streamed GeoTIFF rows), or --z-unit.
    let feet = store(&feet_dem(), "tiled-ft.store", &[]);
    let tiled = depth(&feet, "tiled-ft", &["--max-error-px", "0"]);
    assert!(same_depths(&tiled, &in_metres, 1e-4), "the tiled DEM in feet renders differently");
    let misread = store(&feet_dem(), "tiled-ft-as-m.store", &["--z-unit", "m"]);
    let misread = depth(&misread, "tiled-ft-as-m", &["--max-error-px", "0"]);
    assert!(!same_depths(&misread, &in_metres, 1e-2));
    let feet_up = LengthUnit::UsSurveyFoot.metres();
    let heights_in_feet = metres().iter().map(|&m| (f64::from(m) / feet_up) as f32).collect();
    let told = metre_dem("tiled-m-heights-ft.tif", heights_in_feet);
    let told = store(&told, "tiled-told.store", &["--z-unit", "us-ft"]);
    let told = depth(&told, "tiled-told", &["--max-error-px", "0"]);
    assert!(same_depths(&told, &in_metres, 1e-4));
}

#[test]
fn a_dem_in_feet_shades_as_the_same_dem_in_metres() {
    let (feet, metre) = (feet_dem(), metre_dem("dem-shade-m.tif", metres()));
    let layers = |dem: &Path, name: &str| {
        let out = scratch(name);
        let args = ["shade", dem.to_str().unwrap(), "-o", out.to_str().unwrap()];
        let run = relief(&[&args[..], &["--layers", "hillshade,shadow"]].concat());
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        relief_io::read_layers_geotiff(&out, &relief_io::ReadOptions::default()).unwrap()
    };
    let (a, b) = (layers(&feet, "shade-ft.tif"), layers(&metre, "shade-m.tif"));
    for (x, y) in a.layers.iter().zip(&b.layers) {
        let worst =
            x.samples.iter().zip(&y.samples).map(|(p, q)| (p - q).abs()).fold(0.0, f32::max);
        assert!(worst < 1e-3, "layer {} differs by {worst}", x.name);
    }
}

#[test]
fn info_names_the_height_unit_and_why() {
    let text = stdout_of(&relief(&["info", feet_dem().to_str().unwrap()]));
    assert!(
        text.contains("heights:     in US survey foot (the unit of the projected CRS EPSG:2274"),
        "{text}"
    );
    assert!(text.contains("crs:         EPSG:2274"), "{text}");
    // The metres the heights amount to.
    assert!(text.contains(" m)"), "{text}");
    let told = relief(&["info", feet_dem().to_str().unwrap(), "--z-unit", "ft"]);
    let told = stdout_of(&told);
    assert!(told.contains("heights:     in foot (given by the caller (--z-unit)"), "{told}");
    // A file without a unit: metres, assumed, and said so.
    let npy = scratch("unitless.npy");
    let field = HeightField::new(2, 2, vec![1.0, 2.0, 3.0, 4.0], GridGeometry::unit()).unwrap();
    relief_io::write_height_field_npy(&npy, &field).unwrap();
    let text = stdout_of(&relief(&["info", npy.to_str().unwrap()]));
    assert!(text.contains("heights:     in metre (assumed"), "{text}");
    // --z-unit is refused where there are no heights in a file.
    let out = relief(&["render", "--z-unit", "ft", "-o", scratch("nothing.png").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    let out = relief(&["info", npy.to_str().unwrap(), "--z-unit", "yards"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn generated_png_heights_round_trip_within_their_step() {
    let (png, npy, back) = (scratch("gen.png"), scratch("gen.npy"), scratch("gen-back.npy"));
    for out in [&png, &npy] {
        let args = ["generate", "fbm", "--size", "129", "-o", out.to_str().unwrap()];
        let run = relief(&args);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        if out == &png {
            let said = String::from_utf8_lossy(&run.stderr).to_string();
            assert!(said.contains("heights stored in steps of"), "{said}");
        }
    }
    let run = relief(&["convert", png.to_str().unwrap(), back.to_str().unwrap()]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let (_, exact) = read_f32_npy(&npy);
    let (_, read) = read_f32_npy(&back);
    let (low, high) = exact.iter().fold((f32::MAX, f32::MIN), |(l, h), &v| (l.min(v), h.max(v)));
    let step = (f64::from(high) - f64::from(low)) / 65535.0;
    assert!(step < 0.01, "{low}..{high}");
    for (a, b) in exact.iter().zip(&read) {
        let error = (f64::from(*a) - f64::from(*b)).abs();
        assert!(error <= 0.5 * step + 1e-5, "{a} read back as {b} (step {step})");
    }
}

#[test]
fn an_hgt_output_names_the_rounding_to_whole_metres() {
    let (hgt, again) = (scratch("gen.hgt"), scratch("gen-again.hgt"));
    let run = relief(&["generate", "fbm", "--size", "1201", "-o", hgt.to_str().unwrap()]);
    let said = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(run.status.success(), "{said}");
    assert!(said.contains("a .hgt stores whole metres: heights rounded, by up to"), "{said}");
    // Whole metres already: nothing is rounded, nothing said.
    let run = relief(&["convert", hgt.to_str().unwrap(), again.to_str().unwrap()]);
    let said = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(run.status.success(), "{said}");
    assert!(!said.contains("rounded"), "{said}");
}

#[test]
fn an_output_without_a_georeference_leaves_no_sidecar_of_an_earlier_file() {
    let jacksboro = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../relief-io/tests/fixtures/jacksboro_fault_dem.tif");
    let npy = scratch("plain.npy");
    relief_io::write_npy_f32(&npy, &[SIZE.1, SIZE.0], &metres()).unwrap();
    for extension in ["png", "asc"] {
        let out = scratch(&format!("replaced.{extension}"));
        let run = relief(&["convert", jacksboro.to_str().unwrap(), out.to_str().unwrap()]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        assert!(out.with_extension("prj").is_file());
        // The same name again, from a DEM with no georeference: nothing may place it as the
        // earlier file was placed.
        let run = relief(&["convert", npy.to_str().unwrap(), out.to_str().unwrap()]);
        let said = String::from_utf8_lossy(&run.stderr).to_string();
        assert!(run.status.success(), "{said}");
        assert!(said.contains("left by an earlier file"), "{said}");
        for sidecar in ["prj", "pgw", "png.aux.xml"] {
            assert!(!out.with_extension(sidecar).exists(), "{extension}: {sidecar} stayed");
        }
        let info = stdout_of(&relief(&["info", out.to_str().unwrap()]));
        assert!(!info.contains("EPSG") && !info.contains("WGS"), "{info}");
        // Written once more: nothing stale is left, nothing is said.
        let run = relief(&["convert", npy.to_str().unwrap(), out.to_str().unwrap()]);
        assert!(!String::from_utf8_lossy(&run.stderr).contains("earlier file"));
    }
}

#[test]
fn convert_keeps_a_feet_dem_in_feet_and_says_so() {
    let (tif, asc, npy) = (scratch("conv-ft.tif"), scratch("conv-ft.asc"), scratch("conv-ft.npy"));
    let dem = feet_dem();
    for out in [&tif, &asc, &npy] {
        let run = relief(&["convert", dem.to_str().unwrap(), out.to_str().unwrap()]);
        let said = String::from_utf8_lossy(&run.stderr).to_string();
        assert!(run.status.success(), "{said}");
        assert!(said.contains("heights in US survey foot"), "{said}");
        if out == &npy {
            assert!(said.contains("heights converted from US survey foot to metre"), "{said}");
            assert!(said.contains("a .npy holds no georeference"), "{said}");
        }
    }
    // Read back by relief, every output gives the same heights in metres.
    let original = relief_io::read_raster(&dem, &Default::default()).unwrap();
    for out in [&tif, &asc, &npy] {
        let back = relief_io::read_raster(out, &Default::default()).unwrap();
        for (a, b) in original.samples.iter().zip(&back.samples) {
            let (a, b) =
                (f64::from(*a) * original.geometry.z_scale, f64::from(*b) * back.geometry.z_scale);
            assert!((a - b).abs() < 1e-3, "{}: {a} m read back as {b} m", out.display());
        }
        if out != &npy {
            let (g, h) = (original.geometry, back.geometry);
            assert!(
                (g.dx - h.dx).abs() < 1e-9 && (g.origin - h.origin).length() < 1e-6,
                "{}",
                out.display()
            );
        }
    }
}

#[test]
fn convert_records_the_unit_z_unit_gives() {
    let (dem, out) = (feet_dem(), scratch("conv-told-m.tif"));
    let run = relief(&["convert", dem.to_str().unwrap(), out.to_str().unwrap(), "--z-unit", "m"]);
    let said = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(run.status.success(), "{said}");
    assert!(said.contains("VerticalUnitsGeoKey says the heights are in metre"), "{said}");
    let back = relief_io::read_raster(&out, &Default::default()).unwrap();
    assert_eq!(back.info.height_unit.unit, LengthUnit::Metre);
    assert_eq!(back.info.height_unit.reason, "VerticalUnitsGeoKey");
    assert_eq!(back.geometry.z_scale, 1.0);
    // The CRS and its feet stay: only the heights' unit is declared.
    let georeference = back.info.georeference.unwrap();
    assert_eq!(georeference.epsg(), Some(2274));
    assert_eq!(georeference.linear_unit().unwrap().0, LengthUnit::UsSurveyFoot);
}
