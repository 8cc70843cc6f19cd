//! ESRI ASCII grids (`.asc`): exact round trips, centre and corner origins, errors naming
//! their line, lying headers refused up front, truncated and changed files.

mod common;
#[path = "common/reading.rs"]
mod reading;

use common::TestDir;
use reading::{
    assert_format, check_truncations_and_flips, options, read_bytes, same_samples, Accepted,
};

use relief_core::{GridGeometry, HeightField};
use relief_io::asc::{read_asc, write_asc};
use relief_io::{Format, IoError, Raster, ReadOptions};

/// A 7 x 5 field of awkward f32 values, placed off the origin.
fn asc_field(dx: f64, dy: f64) -> HeightField {
    let specials = [0.1f32, -0.0, 1e-7, 123.456, -1e-30, 3.4e38, 16_777_217.0, -9999.5];
    let samples: Vec<f32> =
        (0..35).map(|i| specials.get(i).copied().unwrap_or((i as f32).sqrt() * -17.3)).collect();
    let geometry = GridGeometry {
        dx,
        dy,
        z_scale: 1.0,
        origin: relief_core::DVec2::new(431_000.125, -3_999_999.9),
    };
    HeightField::new(7, 5, samples, geometry).unwrap()
}

fn assert_same_samples(raster: &Raster, field: &HeightField) {
    assert_eq!((raster.width, raster.height), (field.width(), field.height()));
    for (i, (&got, &want)) in raster.samples.iter().zip(field.samples()).enumerate() {
        if field.holes().is_some_and(|h| h[i]) {
            assert!(got.is_nan(), "sample {i} should be a void, is {got}");
        } else {
            assert_eq!(got.to_bits(), want.to_bits(), "sample {i}: {got} != {want}");
        }
    }
}

#[test]
fn asc_round_trips_exactly_with_and_without_nodata() {
    let dir = TestDir::new("asc-round");
    let path = dir.join("grid.asc");
    let field = asc_field(2.5, 2.5);
    write_asc(&path, &field).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("cellsize 2.5") && !text.contains("NODATA"), "{text}");
    let raster = read_asc(&path, &options()).unwrap();
    assert_same_samples(&raster, &field);
    assert_eq!(raster.geometry, *field.geometry());
    assert_eq!(raster.info.format, Format::Asc);
    assert!(raster.info.georeferenced && raster.info.from_degrees.is_none());

    // Holes become NODATA_value -9999.
    let holes: Vec<bool> = (0..35).map(|i| i % 6 == 2).collect();
    let holed = field.clone().with_holes(holes).unwrap();
    write_asc(&path, &holed).unwrap();
    assert!(std::fs::read_to_string(&path).unwrap().contains("NODATA_value -9999\n"));
    let raster = read_asc(&path, &options()).unwrap();
    assert_same_samples(&raster, &holed);
    assert_eq!(raster.info.nodata, Some(-9999.0));

    // A valid -9999 moves the nodata value out of its way.
    let mut samples = field.samples().to_vec();
    samples[0] = -9999.0;
    let clash = HeightField::new(7, 5, samples, *field.geometry())
        .unwrap()
        .with_holes((0..35).map(|i| i == 34).collect())
        .unwrap();
    write_asc(&path, &clash).unwrap();
    let raster = read_asc(&path, &options()).unwrap();
    assert_same_samples(&raster, &clash);
    assert_eq!(raster.info.nodata, Some(-99999.0));

    // Unequal spacings are written as dx and dy.
    let field = asc_field(2.0, 3.0);
    write_asc(&path, &field).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("dx 2\ndy 3\n") && !text.contains("cellsize"), "{text}");
    let raster = read_asc(&path, &options()).unwrap();
    assert_same_samples(&raster, &field);
    assert_eq!(raster.geometry, *field.geometry());

    // z_scale applies: the file holds world heights.
    let geometry = GridGeometry { z_scale: 2.0, ..*field.geometry() };
    let scaled = HeightField::new(2, 1, vec![1.5, -4.0], geometry).unwrap();
    write_asc(&path, &scaled).unwrap();
    assert_eq!(read_asc(&path, &options()).unwrap().samples, [3.0, -8.0]);
}

#[test]
fn asc_centre_and_corner_origins_and_case_insensitive_keys() {
    let dir = TestDir::new("asc-centre");
    let path = dir.join("grid.asc");
    let centre = "NCOLS 3\nNRows 2\nXLLCENTER 100\nyllcenter 200\nCellSize 10\nnodata_value -1\n\
                  1 2 3\n4 -1 6\n";
    let raster = read_bytes(read_asc, &path, centre.as_bytes(), &options()).unwrap();
    assert_eq!(raster.geometry.origin, relief_core::DVec2::new(95.0, 195.0));
    assert_eq!((raster.geometry.dx, raster.geometry.dy), (10.0, 10.0));
    assert_eq!(raster.info.nodata, Some(-1.0));
    // North row first in the file: the last raster row.
    assert_eq!(&raster.samples[3..], &[1.0, 2.0, 3.0]);
    assert_eq!(raster.samples[0], 4.0);
    assert!(raster.samples[1].is_nan());
    assert_eq!(raster.samples[2], 6.0);

    let corner = "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ndx 10\ndy 20\n1 2 3\n4 5 6\n";
    let raster = read_bytes(read_asc, &path, corner.as_bytes(), &options()).unwrap();
    assert_eq!(raster.geometry.origin, relief_core::DVec2::new(100.0, 200.0));
    assert_eq!((raster.geometry.dx, raster.geometry.dy), (10.0, 20.0));
    assert_eq!(raster.samples, [4.0, 5.0, 6.0, 1.0, 2.0, 3.0]);
    assert_eq!(raster.info.nodata, None);

    // A NaN sample is invalid without a nodata value to match it.
    let nan = "ncols 1\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\nnan\n";
    let err = read_bytes(read_asc, &path, nan.as_bytes(), &options()).unwrap_err();
    assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    assert!(err.to_string().contains("column 0, row 1"), "{err}");
}

#[test]
fn asc_errors_name_the_line() {
    let dir = TestDir::new("asc-lines");
    let path = dir.join("grid.asc");
    let head = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
    let cases = [
        (format!("{head}1 2 3\n4 5\n"), "line 7: row 2 has 2 samples, ncols is 3"),
        (format!("{head}1 2 3\n4 5 6 7\n"), "line 7: row 2 has more than the 3"),
        (format!("{head}1 2 3\n4 five 6\n"), "line 7: sample 'five' is not a number"),
        (format!("{head}1 2 3\n"), "after 1 of the 2 rows"),
        (format!("{head}1 2 3\n4 5 6\n\n7 8 9\n"), "line 9: more data after the 2 rows"),
        (
            format!("{}1 2 3\n4 5 6\n", head.replace("cellsize 1\n", "")),
            "line 5: the header lacks 'cellsize'",
        ),
        (format!("{}1 2 3\n4 5 6\n", head.replace("ncols 3\n", "")), "lacks 'ncols'"),
        (format!("{}1 2 3\n4 5 6\n", head.replace("nrows 2", "nrows two")), "line 2: nrows 'two'"),
        (
            format!("{}1 2 3\n4 5 6\n", head.replace("yllcorner 0", "yllcorner")),
            "line 4: header key 'yllcorner' has no value",
        ),
        (
            format!("projection utm\n{head}1 2 3\n4 5 6\n"),
            "line 1: unknown header key 'projection'",
        ),
    ];
    for (text, needle) in cases {
        assert_format(read_bytes(read_asc, &path, text.as_bytes(), &options()), needle);
    }
}

#[test]
fn asc_header_that_lies_about_its_size_is_refused() {
    let dir = TestDir::new("asc-lie");
    let path = dir.join("grid.asc");
    let huge = "ncols 100000\nnrows 100000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n";
    let err = read_bytes(read_asc, &path, huge.as_bytes(), &options()).unwrap_err();
    assert!(matches!(err, IoError::Limits { .. } | IoError::Format { .. }), "{err}");
    // Within the memory budget, the file is still far too short for the header's claim.
    let err = read_bytes(
        read_asc,
        &path,
        huge.as_bytes(),
        &ReadOptions { max_memory: u64::MAX, ..options() },
    )
    .unwrap_err();
    assert!(err.to_string().contains("more than the"), "{err}");
    let big = huge.replace("100000", "1000");
    assert_format(read_bytes(read_asc, &path, big.as_bytes(), &options()), "more than the");
    // A budget too small for the grid is a Limits error.
    let small = ReadOptions { max_memory: 10, ..options() };
    let ok = "ncols 3\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n";
    let err = read_bytes(read_asc, &path, ok.as_bytes(), &small).unwrap_err();
    assert!(matches!(err, IoError::Limits { width: 3, height: 1, .. }), "{err}");
}

#[test]
fn asc_truncations_are_refused_and_changed_bytes_read_at_the_declared_size() {
    let dir = TestDir::new("asc-fuzz");
    let path = dir.join("grid.asc");
    let good = b"ncols 3\nnrows 2\nxllcorner 0.5\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n\
                 1.5 -9999 3\n4 5 6\n";
    // Dropping only the final line end still leaves a complete grid.
    let (intact, accepted) =
        check_truncations_and_flips(read_asc, &path, good, &options(), |len| len == good.len() - 1);
    // Text without a checksum: a digit changed in a sample, the corner, the cell size or the
    // nodata value reads as another number. But ncols and nrows must match the samples, so
    // whatever reads is 3 x 2, and a change before the nodata line keeps the samples.
    let nodata_line = good.windows(6).position(|w| w == b"NODATA").unwrap();
    assert!(accepted.len() <= 40, "{} of {} changed copies read", accepted.len(), 5 * good.len());
    for Accepted { at, raster } in &accepted {
        assert_eq!((raster.width, raster.height), (3, 2), "byte {at}");
        assert!(*at >= nodata_line || same_samples(raster, &intact), "byte {at}");
    }
}
