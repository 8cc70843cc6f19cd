//! SRTM `.hgt` tiles: round trips with voids and georeference, orientation, tile names, and
//! refusal of files of the wrong length and of heights a tile cannot hold.

mod common;
#[path = "common/reading.rs"]
mod reading;

use common::TestDir;
use reading::{assert_format, options, read_bytes};

use relief_core::{GridGeometry, HeightField};
use relief_io::hgt::{hgt_tile_corner, read_hgt, write_hgt};
use relief_io::{metres_per_degree, Format, IoError, VoidPolicy};
use std::path::Path;

/// A 1201 x 1201 field of whole metres with a few holes.
fn hgt_field() -> HeightField {
    let n = 1201;
    let samples: Vec<f32> =
        (0..n * n).map(|i| ((i % n * 7 + i / n * 13) % 9000) as f32 - 500.0).collect();
    let holes: Vec<bool> =
        (0..n * n).map(|i| i % 9973 == 5 || (i / n == 600 && i % n < 40)).collect();
    HeightField::new(n, n, samples, GridGeometry::unit()).unwrap().with_holes(holes).unwrap()
}

#[test]
fn hgt_round_trips_with_voids_and_georeference() {
    let dir = TestDir::new("hgt-round");
    let path = dir.join("N36W085.hgt");
    let field = hgt_field();
    write_hgt(&path, &field).unwrap();
    assert_eq!(std::fs::metadata(&path).unwrap().len(), 2 * 1201 * 1201);
    let raster = read_hgt(&path, &options()).unwrap();
    assert_eq!((raster.width, raster.height), (1201, 1201));
    let holes = field.holes().unwrap();
    for (i, (&got, &hole)) in raster.samples.iter().zip(holes).enumerate() {
        if hole {
            assert!(got.is_nan(), "sample {i} should be a void");
        } else {
            assert_eq!(got, field.samples()[i], "sample {i}");
        }
    }
    assert_eq!(raster.void_count(), field.hole_count());
    assert_eq!(raster.info.format, Format::Hgt);
    assert_eq!(raster.info.nodata, Some(-32768.0));
    assert!(raster.info.georeferenced);
    let degrees = raster.info.from_degrees.unwrap();
    assert_eq!((degrees.dlon, degrees.dlat, degrees.latitude), (1.0 / 1200.0, 1.0 / 1200.0, 36.5));

    // The south-west sample sits exactly on 36° N, 85° W; texels extend half a pixel around it.
    let (per_lon, per_lat) = metres_per_degree(36.5);
    let g = raster.geometry;
    assert!((g.dx - per_lon / 1200.0).abs() < 1e-9 && (g.dy - per_lat / 1200.0).abs() < 1e-9);
    assert!((g.dx - 74.4).abs() < 0.3 && (g.dy - 92.5).abs() < 0.3, "{g:?}");
    assert!((g.origin.x + 0.5 * g.dx - (-85.0 * per_lon)).abs() < 1e-6, "{g:?}");
    assert!((g.origin.y + 0.5 * g.dy - 36.0 * per_lat).abs() < 1e-6, "{g:?}");
    // The north-east sample on 37° N, 84° W.
    assert!((g.origin.x + 1200.5 * g.dx - (-84.0 * per_lon)).abs() < 1e-6);
    assert!((g.origin.y + 1200.5 * g.dy - 37.0 * per_lat).abs() < 1e-6);

    // Kept as holes, the voids are the field's holes again.
    let back = raster.into_height_field(&path, VoidPolicy::Hole).unwrap();
    assert_eq!(back.holes(), field.holes());
}

#[test]
fn hgt_north_row_becomes_the_last_row() {
    let dir = TestDir::new("hgt-north");
    let n = 1201;
    let mut bytes = vec![0u8; 2 * n * n];
    // The file's first row (north) is 7 m, the first sample of its last row (south-west) 3 m.
    for b in bytes[..2 * n].chunks_exact_mut(2) {
        b.copy_from_slice(&7i16.to_be_bytes());
    }
    bytes[2 * n * (n - 1)..2 * n * (n - 1) + 2].copy_from_slice(&3i16.to_be_bytes());
    bytes[2 * n + 2..2 * n + 4].copy_from_slice(&(-32768i16).to_be_bytes());
    let raster = read_bytes(read_hgt, &dir.join("S12E045.hgt"), &bytes, &options()).unwrap();
    let row = |r: usize| &raster.samples[r * n..(r + 1) * n];
    assert!(row(n - 1).iter().all(|&v| v == 7.0));
    assert_eq!(row(0)[0], 3.0);
    assert!(row(0)[1..].iter().all(|&v| v == 0.0));
    assert!(row(n - 2)[1].is_nan(), "the void in the file's second row");
    assert_eq!(raster.void_count(), 1);
    // 12° S: the corner sample is on latitude -12.
    let (_, per_lat) = metres_per_degree(-11.5);
    assert!((raster.geometry.origin.y + 0.5 * raster.geometry.dy - (-12.0 * per_lat)).abs() < 1e-6);
}

#[test]
fn hgt_tile_names_are_parsed() {
    let corner = |name: &str| hgt_tile_corner(Path::new(name));
    assert_eq!(corner("N36W085.hgt"), Some((36, -85)));
    assert_eq!(corner("S12E045.hgt"), Some((-12, 45)));
    assert_eq!(corner("s12e045.hgt"), Some((-12, 45)));
    assert_eq!(corner("n36w085.HGT"), Some((36, -85)));
    assert_eq!(corner("tiles/N00E000.hgt"), Some((0, 0)));
    assert_eq!(corner("N36W085.SRTMGL1.hgt"), Some((36, -85)));
    for bad in [
        "N36W85.hgt",
        "36W085.hgt",
        "N36W085x.hgt",
        "E36N085.hgt",
        "N91E000.hgt",
        "N36E180.hgt",
        "N3_W085.hgt",
        "tile.hgt",
        "",
    ] {
        assert_eq!(corner(bad), None, "{bad}");
    }
}

#[test]
fn hgt_with_an_unknown_name_is_read_in_grid_units() {
    let dir = TestDir::new("hgt-anon");
    let bytes = vec![0u8; 2 * 1201 * 1201];
    for name in ["tile.hgt", "N36W85.hgt", "X36W085.hgt"] {
        let raster = read_bytes(read_hgt, &dir.join(name), &bytes, &options()).unwrap();
        assert!(!raster.info.georeferenced && raster.info.from_degrees.is_none(), "{name}");
        assert_eq!(raster.geometry, GridGeometry::unit(), "{name}");
    }
}

#[test]
fn hgt_of_the_wrong_length_is_refused_naming_the_length() {
    let dir = TestDir::new("hgt-length");
    let path = dir.join("N36W085.hgt");
    for len in [1, 2, 1200 * 1200 * 2, 1201 * 1201 * 2 - 1, 1201 * 1201 * 2 + 2] {
        let result = read_bytes(read_hgt, &path, &vec![0u8; len], &options());
        assert_format(result, &format!("this file has {len}"));
    }
    // Truncations of a real tile, from the end down, and a few changed bytes.
    let field = hgt_field();
    write_hgt(&path, &field).unwrap();
    let full = std::fs::metadata(&path).unwrap().len();
    for len in (0..full).rev().step_by(4099) {
        std::fs::OpenOptions::new().write(true).open(&path).unwrap().set_len(len).unwrap();
        assert!(read_hgt(&path, &options()).is_err(), "prefix of {len} bytes accepted");
    }
    write_hgt(&path, &field).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    bytes[0] = 0x80;
    bytes[1] = 0x00;
    let raster = read_bytes(read_hgt, &path, &bytes, &options()).unwrap();
    assert!(raster.samples[1200 * 1201].is_nan(), "a new void at the north-west corner");
}

#[test]
fn hgt_writer_refuses_other_sizes_and_out_of_range_heights() {
    let dir = TestDir::new("hgt-write");
    let path = dir.join("N00E000.hgt");
    for (w, h) in [(100, 100), (1201, 1200), (3601, 1201)] {
        let field = HeightField::new(w, h, vec![0.0; w * h], GridGeometry::unit()).unwrap();
        let err = write_hgt(&path, &field).unwrap_err();
        assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
    }
    for bad in [40000.0, -32767.6, 1e30] {
        let mut samples = vec![0.0; 1201 * 1201];
        samples[5] = bad;
        let field = HeightField::new(1201, 1201, samples, GridGeometry::unit()).unwrap();
        let err = write_hgt(&path, &field).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        assert!(err.to_string().contains("column 5, row 0"), "{err}");
    }
    assert!(!path.exists(), "a refused write leaves no file");
    // z_scale applies: heights written are world heights.
    let samples = vec![2.0; 1201 * 1201];
    let geometry = GridGeometry { z_scale: 0.5, ..GridGeometry::unit() };
    let field = HeightField::new(1201, 1201, samples, geometry).unwrap();
    write_hgt(&path, &field).unwrap();
    assert!(read_hgt(&path, &options()).unwrap().samples.iter().all(|&v| v == 1.0));
}
