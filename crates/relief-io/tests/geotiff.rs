//! GeoTIFF reading and writing: a real DEM, the writer's round trip and placements of
//! projected and geographic rasters. Sample types, codecs and chunk layouts are in
//! geotiff_layouts.rs, broken and unsupported files in geotiff_broken.rs.
//! In a bare clone (no ../shared) a test that reads the shared data is reported ignored.

mod common;
#[path = "common/geotiff_cases.rs"]
mod geotiff_cases;

use common::{clients, shared_data, TestDir};
use geotiff_cases::*;

use relief_core::{DVec2, GridGeometry, HeightField};
use relief_io::geotiff::{read_geotiff, write_geotiff};
use relief_io::npy::read_npy_height_field;
use relief_io::{metres_per_degree, IoError, Raster, ReadOptions, VoidPolicy};
use tiff::encoder::colortype;
use tiff::encoder::{Compression, Predictor};
use tiff::tags::Tag;

fn main() {
    clients::run(vec![
        clients::trial!(jacksboro_dem_reads_with_its_size_type_placement_and_values),
        clients::trial_reading!(
            jacksboro_rows_run_south_to_north_like_the_numpy_copy_flipped,
            "data/jacksboro_fault_dem.npy"
        ),
        clients::trial!(written_field_reads_back_with_the_same_geometry_samples_and_holes),
        clients::trial!(z_scale_is_applied_to_written_values),
        clients::trial!(failed_writes_leave_no_file),
        clients::trial!(placements_of_projected_rasters),
        clients::trial!(geographic_pixel_is_point_raster_is_placed_in_metres),
    ]);
}

// ---------------------------------------------------------------------------------------------
// The real DEM.

fn jacksboro_dem_reads_with_its_size_type_placement_and_values() {
    let raster = read_geotiff(&fixture(), &ReadOptions::default()).unwrap();
    assert_eq!((raster.width, raster.height), (403, 344));
    assert_eq!(raster.info.sample_type, "int16");
    assert_eq!(raster.info.nodata, Some(-32768.0));
    assert!(raster.info.georeferenced);
    let degrees = raster.info.from_degrees.expect("a geographic raster");
    let arc3 = 3.0 / 3600.0;
    assert!((degrees.dlon - arc3).abs() < 1e-12 && (degrees.dlat - arc3).abs() < 1e-12);
    // Extents from shared/data/datasets.json.
    let (west, south, north) = (-84.41375, 36.44625, 36.73291666666667);
    assert!((degrees.latitude - 0.5 * (south + north)).abs() < 1e-9, "{}", degrees.latitude);
    let g = raster.geometry;
    assert!((g.dx - 74.5).abs() <= 0.3, "dx {}", g.dx);
    assert!((g.dy - 92.5).abs() <= 0.3, "dy {}", g.dy);
    assert_eq!(g.z_scale, 1.0);
    let (per_lon, per_lat) = metres_per_degree(degrees.latitude);
    assert!((g.origin.x - west * per_lon).abs() < 1e-6, "{}", g.origin);
    assert!((g.origin.y - south * per_lat).abs() < 1e-6, "{}", g.origin);
    assert!((g.dx - arc3 * per_lon).abs() < 1e-9 && (g.dy - arc3 * per_lat).abs() < 1e-9);
    assert_eq!(raster.void_count(), 0);
    assert_eq!(raster.value_range(), Some((236.0, 1076.0)));
    assert!(raster.samples.iter().all(|v| v.fract() == 0.0));
}

fn jacksboro_rows_run_south_to_north_like_the_numpy_copy_flipped() {
    let Some(npy) = shared_data("data/jacksboro_fault_dem.npy") else { return };
    let raster = read_geotiff(&fixture(), &ReadOptions::default()).unwrap();
    let grid = read_npy_height_field(&npy).unwrap();
    assert_eq!((grid.width(), grid.height()), (403, 344));
    for row_from_north in 0..344 {
        for col in 0..403 {
            assert_eq!(
                grid.sample(col, row_from_north),
                raster.samples[col + (343 - row_from_north) * 403],
                "column {col}, row {row_from_north} from the north"
            );
        }
    }
    // Not symmetric: a flip would have been caught.
    assert_ne!(grid.sample(0, 0), grid.sample(0, 343));
}

// ---------------------------------------------------------------------------------------------
// The writer.

fn written_field_reads_back_with_the_same_geometry_samples_and_holes() {
    let dir = TestDir::new("roundtrip");
    let (w, h) = (29, 17);
    let samples: Vec<f32> = (0..w * h).map(|i| ((i * 37) % 101) as f32 * 1.5 - 20.25).collect();
    let geometry =
        GridGeometry { dx: 2.5, dy: 3.0, z_scale: 1.0, origin: DVec2::new(1000.0, 2000.0) };
    let holes: Vec<bool> = (0..w * h).map(|i| [3, 40, 41, 200, w * h - 1].contains(&i)).collect();
    let field = HeightField::new(w, h, samples.clone(), geometry).unwrap();
    let field = field.with_holes(holes.clone()).unwrap();
    let path = dir.join("field.tif");
    write_geotiff(&path, &field).unwrap();
    // Nothing but the file itself is left in the directory (no temporary).
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);

    let raster = read_geotiff(&path, &options()).unwrap();
    assert_eq!((raster.width, raster.height), (w, h));
    let g = raster.geometry;
    assert!((g.dx - 2.5).abs() < 1e-9 && (g.dy - 3.0).abs() < 1e-9, "{g:?}");
    assert!((g.origin - DVec2::new(1000.0, 2000.0)).length() < 1e-9, "{g:?}");
    assert_eq!(g.z_scale, 1.0);
    assert!(raster.info.georeferenced && raster.info.from_degrees.is_none());
    assert_eq!(raster.info.sample_type, "float32");
    for (i, (&got, &hole)) in raster.samples.iter().zip(&holes).enumerate() {
        if hole {
            assert!(got.is_nan(), "sample {i} should be a void, is {got}");
        } else {
            assert_eq!(got, samples[i], "sample {i}");
        }
    }
    assert_eq!(raster.void_count(), 5);
    let back = raster.into_height_field(&path, VoidPolicy::Hole).unwrap();
    assert_eq!(back.holes(), field.holes());
    assert_eq!(back.samples(), field.samples());

    // The file is float32, Deflate with the floating-point predictor, one band, north-up.
    let mut decoder = tiff::decoder::Decoder::new(std::fs::File::open(&path).unwrap()).unwrap();
    let tags = [Tag::Compression, Tag::Predictor, Tag::SampleFormat, Tag::BitsPerSample];
    let values = tags.map(|t| decoder.get_tag_u32(t).unwrap());
    assert_eq!(values, [8, 3, 3, 32], "Deflate, floating-point predictor, float32");
    let first_row = match decoder.read_chunk(0).unwrap() {
        tiff::decoder::DecodingResult::F32(v) => v,
        other => panic!("{other:?}"),
    };
    // File row 0 is the field's northernmost row; its last sample is a hole, written as NaN.
    let north = (h - 1) * w;
    for (col, &got) in first_row[..w].iter().enumerate() {
        let want = if holes[north + col] { f32::NAN } else { samples[north + col] };
        assert!(got == want || got.is_nan() && want.is_nan(), "column {col}: {got} vs {want}");
    }
    assert!(first_row[w - 1].is_nan());
}

fn z_scale_is_applied_to_written_values() {
    let dir = TestDir::new("zscale");
    let geometry = GridGeometry { z_scale: 0.5, ..GridGeometry::unit() };
    let field = HeightField::new(3, 2, vec![2.0, 4.0, 6.0, 8.0, 10.0, -12.0], geometry).unwrap();
    let path = dir.join("z.tif");
    write_geotiff(&path, &field).unwrap();
    let raster = read_geotiff(&path, &options()).unwrap();
    assert_eq!(raster.samples, [1.0, 2.0, 3.0, 4.0, 5.0, -6.0]);
}

fn failed_writes_leave_no_file() {
    let dir = TestDir::new("write-fail");
    let field = HeightField::new(2, 2, vec![0.0; 4], GridGeometry::unit()).unwrap();
    let missing_dir = dir.join("absent").join("x.tif");
    assert!(matches!(write_geotiff(&missing_dir, &field), Err(IoError::Io { .. })));
    assert!(!missing_dir.exists());
    assert!(matches!(write_geotiff(dir.path(), &field), Err(IoError::Io { .. })));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

// ---------------------------------------------------------------------------------------------
// Placement.

/// A 3 x 2 uint8 raster with `extras`, values 0..6 in file order.
fn placed(dir: &TestDir, extras: &[Extra]) -> Result<Raster, IoError> {
    let bytes = encode_strips::<colortype::Gray8>(
        &[0, 1, 2, 3, 4, 5],
        (3, 2),
        Compression::Uncompressed,
        Predictor::None,
        None,
        extras,
    );
    read_geotiff(&dir.file("placed.tif", &bytes), &options())
}

fn close(a: DVec2, b: DVec2) -> bool {
    (a - b).length() < 1e-9
}

fn placements_of_projected_rasters() {
    let dir = TestDir::new("placement");
    let keys = |raster_type: u16| {
        Extra::Shorts(
            Tag::GeoKeyDirectoryTag,
            vec![1, 1, 0, 2, 1024, 0, 1, 1, 1025, 0, 1, raster_type],
        )
    };
    let scale = |sy: f64| Extra::Doubles(Tag::ModelPixelScaleTag, vec![10.0, sy, 0.0]);
    let tie = |i: f64, j: f64| {
        Extra::Doubles(Tag::ModelTiepointTag, vec![i, j, 0.0, 1000.0, 5000.0, 0.0])
    };

    // PixelIsArea, north-up: north-west corner (1000, 5000), two rows of 20 m.
    let r = placed(&dir, &[scale(20.0), tie(0.0, 0.0), keys(1)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(1000.0, 4960.0)), "{:?}", r.geometry);
    assert_eq!(r.samples, [3.0, 4.0, 5.0, 0.0, 1.0, 2.0], "flipped");
    // A tie point at raster (1, 1) instead of (0, 0).
    let r = placed(&dir, &[scale(20.0), tie(1.0, 1.0), keys(1)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(990.0, 4980.0)), "{:?}", r.geometry);
    // PixelIsPoint: (1000, 5000) is the first sample's centre, so the corner is half a pixel
    // further west and north.
    let r = placed(&dir, &[scale(20.0), tie(0.0, 0.0), keys(2)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(995.0, 4970.0)), "{:?}", r.geometry);
    // South-up (negative y scale): file row 0 is the south row, not flipped.
    let r = placed(&dir, &[scale(-20.0), tie(0.0, 0.0), keys(1)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(1000.0, 5000.0)), "{:?}", r.geometry);
    assert_eq!(r.geometry.dy, 20.0);
    assert_eq!(r.samples, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0], "not flipped");
    // A ModelTransformation without rotation, north-up and south-up.
    let transform = |dy: f64| {
        let t = vec![
            10.0, 0.0, 0.0, 1000.0, 0.0, dy, 0.0, 5000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ];
        Extra::Doubles(Tag::ModelTransformationTag, t)
    };
    let r = placed(&dir, &[transform(-20.0), keys(1)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(1000.0, 4960.0)), "{:?}", r.geometry);
    assert_eq!(r.samples, [3.0, 4.0, 5.0, 0.0, 1.0, 2.0]);
    let r = placed(&dir, &[transform(20.0), keys(2)]).unwrap();
    assert!(close(r.geometry.origin, DVec2::new(995.0, 4990.0)), "{:?}", r.geometry);
    assert_eq!(r.samples, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    // Rotation or shear is refused.
    let mut rotated = vec![10.0, 1.0, 0.0, 1000.0, 1.0, -20.0, 0.0, 5000.0];
    rotated.extend([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    let err = placed(&dir, &[Extra::Doubles(Tag::ModelTransformationTag, rotated)]).unwrap_err();
    assert!(
        matches!(err, IoError::Unsupported { .. }) && err.to_string().contains("rotated"),
        "{err}"
    );
    // Projected in US survey feet: converted to metres.
    let feet =
        Extra::Shorts(Tag::GeoKeyDirectoryTag, vec![1, 1, 0, 2, 1024, 0, 1, 1, 3076, 0, 1, 9003]);
    let r = placed(&dir, &[scale(20.0), tie(0.0, 0.0), feet]).unwrap();
    assert!((r.geometry.dx - 10.0 * 1200.0 / 3937.0).abs() < 1e-12, "{:?}", r.geometry);
    // No georeference at all: unit spacing at the origin, still flipped (a TIFF's first row
    // is its top).
    let r = placed(&dir, &[]).unwrap();
    assert!(!r.info.georeferenced);
    assert_eq!(r.geometry, GridGeometry::unit());
    assert_eq!(r.samples, [3.0, 4.0, 5.0, 0.0, 1.0, 2.0]);
    // Half a georeference is refused.
    assert!(matches!(placed(&dir, &[scale(20.0)]), Err(IoError::Unsupported { .. })));
    let zero = placed(
        &dir,
        &[Extra::Doubles(Tag::ModelPixelScaleTag, vec![0.0, 1.0, 0.0]), tie(0.0, 0.0)],
    );
    assert!(matches!(zero, Err(IoError::Format { .. })));
}

fn geographic_pixel_is_point_raster_is_placed_in_metres() {
    let dir = TestDir::new("geographic");
    // An SRTM-like layout: 1 arc-second samples, the first sample's centre at (-84 E, 37 N).
    let arc1 = 1.0 / 3600.0;
    let extras = [
        Extra::Doubles(Tag::ModelPixelScaleTag, vec![arc1, arc1, 0.0]),
        Extra::Doubles(Tag::ModelTiepointTag, vec![0.0, 0.0, 0.0, -84.0, 37.0, 0.0]),
        Extra::Shorts(
            Tag::GeoKeyDirectoryTag,
            vec![1, 1, 0, 3, 1024, 0, 1, 2, 1025, 0, 1, 2, 2048, 0, 1, 4326],
        ),
    ];
    let r = placed(&dir, &extras).unwrap();
    let degrees = r.info.from_degrees.unwrap();
    let (west, north) = (-84.0 - arc1 / 2.0, 37.0 + arc1 / 2.0);
    let south = north - 2.0 * arc1;
    assert!((degrees.latitude - (37.0 - arc1 / 2.0)).abs() < 1e-12, "{degrees:?}");
    let (per_lon, per_lat) = metres_per_degree(degrees.latitude);
    let g = r.geometry;
    assert!((g.dx - arc1 * per_lon).abs() < 1e-9 && (g.dy - arc1 * per_lat).abs() < 1e-9);
    assert!(close(g.origin, DVec2::new(west * per_lon, south * per_lat)), "{g:?}");
    // Latitudes past the poles are refused.
    let extras = [
        Extra::Doubles(Tag::ModelPixelScaleTag, vec![1.0, 60.0, 0.0]),
        Extra::Doubles(Tag::ModelTiepointTag, vec![0.0, 0.0, 0.0, 0.0, 95.0, 0.0]),
        Extra::Shorts(Tag::GeoKeyDirectoryTag, vec![1, 1, 0, 1, 1024, 0, 1, 2]),
    ];
    assert!(matches!(placed(&dir, &extras), Err(IoError::Format { .. })));
}
