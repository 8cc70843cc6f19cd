//! The files beside a raster that place it: a PNG written with its world file and `.prj`
//! read back in place, and malformed sidecars refused by cause.

mod common;

use common::TestDir;
use relief_core::{GridGeometry, HeightField};
use relief_io::{
    prj_path, read_raster, world_file_path, Georeference, IoError, LengthUnit, ReadOptions,
};

#[test]
fn a_png_is_placed_by_its_world_file_and_prj() {
    let dir = TestDir::new("sidecars");
    let png = dir.path().join("tile.png");
    let field =
        HeightField::new(3, 2, vec![1.5, 2.0, 3.0, 4.0, 5.0, 6.25], GridGeometry::unit()).unwrap();
    let tile = Georeference::srtm_tile(36, -85, 3);
    let notes =
        relief_io::write_height_field_georeferenced(&png, &field, Some(&tile), LengthUnit::Metre)
            .unwrap();
    assert!(notes.iter().any(|n| n.contains("tile.prj (EPSG:4326)")), "{notes:?}");
    let options = ReadOptions::default();
    let raster = read_raster(&png, &options).unwrap();
    let read = raster.info.georeference.as_ref().unwrap();
    assert_eq!(read.epsg(), Some(4326));
    assert_eq!(read.geotransform, tile.geotransform);
    assert!(raster.info.from_degrees.is_some() && raster.info.georeferenced);
    assert_eq!(raster.info.height_unit.reason, "the PNG's tEXt height_unit");
    // A world file of five numbers, a rotated one, a .prj that is not WKT: refused.
    let world = world_file_path(&png);
    std::fs::write(&world, "1\n0\n0\n-1\n5\n").unwrap();
    assert!(matches!(read_raster(&png, &options), Err(IoError::Format { .. })));
    std::fs::write(&world, "1\n0.5\n0\n-1\n5\n6\n").unwrap();
    assert!(matches!(read_raster(&png, &options), Err(IoError::Unsupported { .. })));
    std::fs::write(&world, "1\n0\n0\n-1\n5\n6\n").unwrap();
    std::fs::write(prj_path(&png), "+proj=longlat").unwrap();
    let err = read_raster(&png, &options).unwrap_err();
    assert!(err.to_string().contains("not ESRI WKT"), "{err}");
    // Without the .prj, the world file places the image in no CRS.
    std::fs::remove_file(prj_path(&png)).unwrap();
    let raster = read_raster(&png, &options).unwrap();
    assert_eq!(raster.geometry.origin, relief_core::DVec2::new(4.5, 4.5));
    assert!(!raster.info.georeference.unwrap().has_crs());
}
