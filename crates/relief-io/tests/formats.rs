//! Readers and writers of SRTM `.hgt`, ESRI `.asc`, PNG heights and NumPy `.npz` files:
//! round trips, decoding of hand-made data, orientation, and refusal of broken or lying files.

mod common;

use common::TestDir;

use relief_core::{GridGeometry, HeightField};
use relief_io::asc::{read_asc, write_asc};
use relief_io::hgt::{hgt_tile_corner, read_hgt, write_hgt};
use relief_io::npy::{read_npy, read_npz, write_npy_f32};
use relief_io::png::{read_png_height, write_png16_height};
use relief_io::{metres_per_degree, Format, IoError, PngEncoding, Raster, ReadOptions, VoidPolicy};
use std::io::{Cursor, ErrorKind, Write};
use std::path::Path;
use std::time::{Duration, Instant};

type Reader = fn(&Path, &ReadOptions) -> Result<Raster, IoError>;

fn options() -> ReadOptions {
    ReadOptions::default()
}

fn png_options(png_encoding: PngEncoding) -> ReadOptions {
    ReadOptions { png_encoding, ..ReadOptions::default() }
}

/// Reads `bytes` written to `path` with `read`.
fn read_bytes(
    read: Reader,
    path: &Path,
    bytes: &[u8],
    options: &ReadOptions,
) -> Result<Raster, IoError> {
    std::fs::write(path, bytes).unwrap();
    read(path, options)
}

/// A changed copy of a file that a reader accepted.
struct Accepted {
    /// The offset of the changed byte.
    at: usize,
    /// The raster read.
    raster: Raster,
}

/// Every proper prefix of `good` (but those `valid_prefix` accepts) is refused, and no single
/// byte changed in any of five ways (5 x `good.len()` copies) makes the reader panic. Returns
/// the changed copies that were still read, and the raster of `good`, for the caller to judge
/// against what the format can detect.
fn check_truncations_and_flips(
    read: Reader,
    path: &Path,
    good: &[u8],
    options: &ReadOptions,
    valid_prefix: impl Fn(usize) -> bool,
) -> (Raster, Vec<Accepted>) {
    let intact = read_bytes(read, path, good, options).expect("the intact file reads");
    for len in 0..good.len() {
        if valid_prefix(len) {
            continue;
        }
        let result = read_bytes(read, path, &good[..len], options);
        assert!(result.is_err(), "prefix of {len} of {} bytes accepted", good.len());
    }
    let mut accepted = Vec::new();
    for at in 0..good.len() {
        let changes: [fn(u8) -> u8; 5] = [|b| b ^ 0x01, |b| b ^ 0x80, |_| 0xff, |_| 0, |_| b'9'];
        for change in changes {
            let mut bad = good.to_vec();
            bad[at] = change(bad[at]);
            if bad[at] == good[at] {
                continue;
            }
            if let Ok(raster) = read_bytes(read, path, &bad, options) {
                // Whatever reads must be a raster consistent with itself.
                assert_eq!(raster.samples.len(), raster.width * raster.height, "byte {at}");
                accepted.push(Accepted { at, raster });
            }
        }
    }
    (intact, accepted)
}

/// Fails naming the changed bytes of the copies in `accepted`, if any.
fn assert_none_read(accepted: &[Accepted]) {
    let at: Vec<usize> = accepted.iter().map(|a| a.at).collect();
    assert!(at.is_empty(), "copies with these bytes changed read: {at:?}");
}

/// Whether `a` and `b` have the same size and the same samples, bit for bit (voids too).
fn same_samples(a: &Raster, b: &Raster) -> bool {
    (a.width, a.height) == (b.width, b.height)
        && a.samples.iter().zip(&b.samples).all(|(x, y)| x.to_bits() == y.to_bits())
}

fn assert_format(result: Result<Raster, IoError>, needle: &str) {
    match result {
        Err(err @ IoError::Format { .. }) => {
            assert!(err.to_string().contains(needle), "'{err}' does not say '{needle}'")
        }
        other => panic!("expected a format error saying '{needle}', got {other:?}"),
    }
}

/// Every reader refuses an empty file with a format error and a directory with an I/O error.
#[test]
fn empty_files_and_directories_are_refused_by_every_reader() {
    let dir = TestDir::new("empty");
    let readers: [(&str, Reader, ReadOptions); 7] = [
        ("N36W085.hgt", read_hgt, options()),
        ("grid.asc", read_asc, options()),
        ("grey.png", read_png_height, options()),
        ("rgb.png", read_png_height, png_options(PngEncoding::TerrainRgb)),
        ("rgb.png", read_png_height, png_options(PngEncoding::Terrarium)),
        ("arrays.npz", read_npz, options()),
        ("grid.npy", read_npy, options()),
    ];
    for (name, read, options) in readers {
        let path = dir.join(name);
        let err = read_bytes(read, &path, b"", &options).unwrap_err();
        assert!(matches!(err, IoError::Format { .. }), "{name}: {err}");
        assert!(err.to_string().contains(name), "{err}");
        let sub = dir.join(&format!("{name}.d"));
        std::fs::create_dir_all(&sub).unwrap();
        let err = read(&sub, &options).unwrap_err();
        assert!(
            matches!(&err, IoError::Io { source, .. } if source.kind() == ErrorKind::IsADirectory),
            "{name}: {err}"
        );
        let err = read(&dir.join("absent"), &options).unwrap_err();
        assert!(
            matches!(&err, IoError::Io { source, .. } if source.kind() == ErrorKind::NotFound),
            "{name}: {err}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// SRTM .hgt

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

// ---------------------------------------------------------------------------------------
// ESRI ASCII grid

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
fn asc_header_that_lies_about_its_size_is_refused_quickly() {
    let dir = TestDir::new("asc-lie");
    let path = dir.join("grid.asc");
    let start = Instant::now();
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
    assert!(start.elapsed() < Duration::from_secs(30), "lying headers must be refused up front");
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

// ---------------------------------------------------------------------------------------
// PNG heights

/// Encodes a PNG of `color`/`depth` with `data` rows from the top.
fn encode_png(
    (width, height): (u32, u32),
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
) -> Vec<u8> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(color);
    encoder.set_depth(depth);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(data).unwrap();
    writer.finish().unwrap();
    out
}

#[test]
fn png16_round_trips_with_the_top_row_north() {
    let dir = TestDir::new("png16-round");
    let path = dir.join("heights.png");
    let (w, h) = (5, 4);
    let samples: Vec<f32> = (0..w * h).map(|i| (i * 3449 % 65536) as f32).collect();
    let holes: Vec<bool> = (0..w * h).map(|i| i == 7).collect();
    let field = HeightField::new(w, h, samples.clone(), GridGeometry::unit())
        .unwrap()
        .with_holes(holes)
        .unwrap();
    write_png16_height(&path, &field).unwrap();
    let raster = read_png_height(&path, &options()).unwrap();
    // Whole heights in 0..=65535 are stored as they are; the hole is transparent, a void.
    let mut expected = samples;
    expected[7] = f32::NAN;
    assert!(same_samples(&raster, &Raster { samples: expected.clone(), ..raster.clone() }));
    assert_eq!(raster.info.format, Format::Png16);
    assert_eq!(raster.info.sample_type, "uint16");
    assert!(!raster.info.georeferenced);
    // The image's top row is the field's last (north) row.
    let image = relief_io::png::read_png_rgb(&path).unwrap();
    let top_left = (expected[(h - 1) * w] as u32 >> 8) as u8;
    assert_eq!(image.pixels[0], [top_left; 3]);
}

#[test]
fn png16_heights_use_their_16_bits_and_round_trip_within_their_step() {
    let dir = TestDir::new("png16-step");
    let path = dir.join("heights.png");
    // Fractional heights, negative ones, past 65535: each read back within half a step.
    for (low, high) in [(0.0f32, 188.7), (-12.25, 3.5), (-400.0, 90_000.0), (1.4, 65534.6)] {
        let (w, h) = (7, 5);
        let samples: Vec<f32> =
            (0..w * h).map(|i| low + (high - low) * ((i * 17 % 35) as f32 / 34.0)).collect();
        let field = HeightField::new(w, h, samples.clone(), GridGeometry::unit()).unwrap();
        let scale = relief_io::png::PngHeightScale::of(&field);
        write_png16_height(&path, &field).unwrap();
        let raster = read_png_height(&path, &options()).unwrap();
        let step = (f64::from(high) - f64::from(low)) / 65535.0;
        assert!((scale.scale - step).abs() < 1e-9 * step.max(1.0), "{scale:?}");
        for (got, want) in raster.samples.iter().zip(&samples) {
            let error = (f64::from(*got) - f64::from(*want)).abs();
            let rounding = f64::from(want.abs()) * 1e-7;
            assert!(error <= 0.5 * step + rounding, "{got} vs {want}, step {step}");
        }
        assert_eq!(raster.info.height_unit.unit, relief_io::LengthUnit::Metre);
        assert!(!raster.info.height_unit.is_assumed());
    }
    // The unit written is the unit read: heights in feet come back with a z scale to metres.
    let field = HeightField::new(2, 1, vec![10.5, 20.25], GridGeometry::unit()).unwrap();
    relief_io::png::write_png16_height_in(&path, &field, relief_io::LengthUnit::Foot).unwrap();
    let raster = read_png_height(&path, &options()).unwrap();
    assert_eq!(raster.info.height_unit.unit, relief_io::LengthUnit::Foot);
    assert_eq!(raster.geometry.z_scale, 0.3048);
}

#[test]
fn grey8_png_heights_and_orientation() {
    let dir = TestDir::new("png8");
    let path = dir.join("grey.png");
    let bytes =
        encode_png((3, 2), png::ColorType::Grayscale, png::BitDepth::Eight, &[9, 9, 9, 1, 2, 3]);
    let raster = read_bytes(read_png_height, &path, &bytes, &options()).unwrap();
    assert_eq!(raster.samples, [1.0, 2.0, 3.0, 9.0, 9.0, 9.0]);
    assert_eq!(raster.info.sample_type, "uint8");
}

#[test]
fn terrain_rgb_and_terrarium_pixels_decode_to_known_heights() {
    let dir = TestDir::new("png-rgb");
    let path = dir.join("tile.png");
    // Top row first: the second row is the raster's first.
    let terrain_rgb: [([u8; 3], f32); 4] = [
        ([1, 134, 160], 0.0), // 100000 * 0.1 - 10000
        ([0, 0, 0], -10000.0),
        ([1, 135, 5], 10.1),  // 100101 * 0.1 - 10000
        ([3, 0, 20], 9662.8), // 196628 * 0.1 - 10000
    ];
    let data: Vec<u8> = terrain_rgb.iter().flat_map(|(p, _)| *p).collect();
    let bytes = encode_png((2, 2), png::ColorType::Rgb, png::BitDepth::Eight, &data);
    let options = png_options(PngEncoding::TerrainRgb);
    let raster = read_bytes(read_png_height, &path, &bytes, &options).unwrap();
    let expected = [terrain_rgb[2].1, terrain_rgb[3].1, terrain_rgb[0].1, terrain_rgb[1].1];
    for (got, want) in raster.samples.iter().zip(expected) {
        assert!((got - want).abs() < 1e-3, "{got} != {want}");
    }
    assert_eq!(raster.info.format, Format::TerrainRgb);

    let terrarium: [([u8; 4], f32); 4] = [
        ([128, 0, 0, 255], 0.0),
        ([128, 100, 128, 255], 100.5),
        ([0, 0, 0, 255], -32768.0),
        ([121, 42, 64, 0], f32::NAN), // transparent: a void
    ];
    let data: Vec<u8> = terrarium.iter().flat_map(|(p, _)| *p).collect();
    let bytes = encode_png((4, 1), png::ColorType::Rgba, png::BitDepth::Eight, &data);
    let options = png_options(PngEncoding::Terrarium);
    let raster = read_bytes(read_png_height, &path, &bytes, &options).unwrap();
    assert_eq!(&raster.samples[..3], &[0.0, 100.5, -32768.0]);
    assert!(raster.samples[3].is_nan());
    assert_eq!((raster.info.format, raster.void_count()), (Format::Terrarium, 1));
    // 0x79 * 256 + 0x2a + 0x40 / 256 - 32768 for the same pixel made opaque.
    let data = [121, 42, 64];
    let bytes = encode_png((1, 1), png::ColorType::Rgb, png::BitDepth::Eight, &data);
    let raster = read_bytes(read_png_height, &path, &bytes, &options).unwrap();
    assert_eq!(raster.samples, [121.0 * 256.0 + 42.0 + 0.25 - 32768.0]);
}

#[test]
fn png_colour_type_that_does_not_fit_the_encoding_is_unsupported() {
    let dir = TestDir::new("png-kind");
    let path = dir.join("tile.png");
    let grey16 = encode_png((1, 1), png::ColorType::Grayscale, png::BitDepth::Sixteen, &[1, 2]);
    let rgb = encode_png((1, 1), png::ColorType::Rgb, png::BitDepth::Eight, &[1, 2, 3]);
    let rgb16 = encode_png((1, 1), png::ColorType::Rgb, png::BitDepth::Sixteen, &[0; 6]);
    let cases = [
        (&grey16, PngEncoding::TerrainRgb, "16-bit greyscale"),
        (&grey16, PngEncoding::Terrarium, "16-bit greyscale"),
        (&rgb, PngEncoding::Grey, "8-bit RGB"),
        (&rgb16, PngEncoding::TerrainRgb, "16-bit RGB"),
    ];
    for (bytes, encoding, colour) in cases {
        let err = read_bytes(read_png_height, &path, bytes, &png_options(encoding)).unwrap_err();
        assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
        let message = err.to_string();
        assert!(message.contains(colour) && message.contains("--png-encoding"), "{message}");
    }
}

#[test]
fn png_truncations_corruptions_and_lying_headers_give_errors() {
    let dir = TestDir::new("png-fuzz");
    let path = dir.join("tile.png");
    let field =
        HeightField::new(3, 2, vec![1.0, 2.0, 300.0, 4.0, 5.0, 60000.0], GridGeometry::unit())
            .unwrap();
    write_png16_height(&path, &field).unwrap();
    let good = std::fs::read(&path).unwrap();
    // Every chunk carries a CRC-32 and the image data an Adler-32: no changed byte reads.
    let (_, accepted) =
        check_truncations_and_flips(read_png_height, &path, &good, &options(), |_| false);
    assert_none_read(&accepted);
    let data = [1, 2, 3, 4, 5, 6, 7, 8];
    let rgba = encode_png((2, 1), png::ColorType::Rgba, png::BitDepth::Eight, &data);
    let options = png_options(PngEncoding::TerrainRgb);
    let (_, accepted) =
        check_truncations_and_flips(read_png_height, &path, &rgba, &options, |_| false);
    assert_none_read(&accepted);

    // IHDR claims 16384 x 16384 pixels in a file of a few dozen bytes.
    let mut bytes = good.clone();
    bytes[16..24].copy_from_slice(&[0, 0, 0x40, 0, 0, 0, 0x40, 0]);
    let crc = crc32(&bytes[12..29]);
    bytes[29..33].copy_from_slice(&crc.to_be_bytes());
    let unlimited = ReadOptions { max_memory: u64::MAX, ..ReadOptions::default() };
    assert_format(read_bytes(read_png_height, &path, &bytes, &unlimited), "cannot fit");
    let err = read_bytes(
        read_png_height,
        &path,
        &bytes,
        &ReadOptions { max_memory: 1 << 20, ..unlimited },
    )
    .unwrap_err();
    assert!(matches!(err, IoError::Limits { width: 16384, height: 16384, .. }), "{err}");
}

#[test]
fn interlaced_png_heights_are_read_with_the_top_row_north() {
    // A 3 x 2 Adam7 image, 8-bit grey: top row 10 20 30, bottom row 40 50 60. Its passes
    // hold (0,0); (2,0); (1,0); then the whole second row, each line after filter byte 0.
    let raw = [0, 10, 0, 30, 0, 20, 0, 40, 50, 60];
    let mut zlib = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    zlib.write_all(&raw).unwrap();
    let idat = zlib.finish().unwrap();
    let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
    let ihdr = [0, 0, 0, 3, 0, 0, 0, 2, 8, 0, 0, 0, 1];
    for (kind, data) in [(&b"IHDR"[..], &ihdr[..]), (b"IDAT", &idat), (b"IEND", &[])] {
        bytes.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let start = bytes.len();
        bytes.extend_from_slice(kind);
        bytes.extend_from_slice(data);
        let crc = crc32(&bytes[start..]);
        bytes.extend_from_slice(&crc.to_be_bytes());
    }
    let dir = TestDir::new("png-adam7");
    let path = dir.join("adam7.png");
    let raster = read_bytes(read_png_height, &path, &bytes, &options()).unwrap();
    assert_eq!(raster.samples, [40.0, 50.0, 60.0, 10.0, 20.0, 30.0]);
    // As every PNG: a CRC-32 per chunk, an Adler-32 over the pixels.
    let (_, accepted) =
        check_truncations_and_flips(read_png_height, &path, &bytes, &options(), |_| false);
    assert_none_read(&accepted);
}

/// The CRC-32 of PNG chunks.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

// ---------------------------------------------------------------------------------------
// NumPy .npz

/// The bytes of a little-endian f32 `.npy` file of `shape` holding `data`.
fn npy_bytes(dir: &TestDir, shape: &[usize], data: &[f32]) -> Vec<u8> {
    let path = dir.join("member.npy");
    write_npy_f32(&path, shape, data).unwrap();
    std::fs::read(&path).unwrap()
}

/// A zip archive of `(name, bytes, deflated)` members, in that order.
fn zip_archive(members: &[(&str, &[u8], bool)]) -> Vec<u8> {
    let mut writer = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for &(name, bytes, deflated) in members {
        let method = if deflated {
            zip::CompressionMethod::Deflated
        } else {
            zip::CompressionMethod::Stored
        };
        let options = zip::write::SimpleFileOptions::default().compression_method(method);
        writer.start_file(name, options).unwrap();
        writer.write_all(bytes).unwrap();
    }
    writer.finish().unwrap().into_inner()
}

#[test]
fn npz_members_stored_or_deflated_are_selected_by_name() {
    let dir = TestDir::new("npz-select");
    let path = dir.join("arrays.npz");
    let a = npy_bytes(&dir, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    let b_values: Vec<f32> = (0..40 * 30).map(|i| (i % 17) as f32 * 0.25).collect();
    let b = npy_bytes(&dir, &[40, 30], &b_values);
    for (a_deflated, b_deflated) in [(false, true), (true, false), (true, true), (false, false)] {
        let archive = zip_archive(&[("a.npy", &a, a_deflated), ("b.npy", &b, b_deflated)]);
        std::fs::write(&path, &archive).unwrap();
        // The first member by default; no flip, no georeference.
        let raster = read_npz(&path, &options()).unwrap();
        assert_eq!((raster.width, raster.height), (3, 2));
        assert_eq!(raster.samples, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(raster.info.format, Format::Npz);
        assert_eq!(raster.info.sample_type, "float32");
        assert!(!raster.info.georeferenced);
        assert_eq!(raster.geometry, GridGeometry::unit());
        for name in ["b", "b.npy"] {
            let options = ReadOptions { array: Some(name.into()), ..options() };
            let raster = read_npz(&path, &options).unwrap();
            assert_eq!((raster.width, raster.height), (30, 40));
            assert_eq!(raster.samples, b_values);
        }
        let options = ReadOptions { array: Some("c".into()), ..options() };
        assert_format(
            read_npz(&path, &options),
            "no array named 'c' in the archive; it holds a.npy, b.npy",
        );
    }
    // The memory budget applies to the member.
    let archive = zip_archive(&[("b.npy", &b, true)]);
    std::fs::write(&path, &archive).unwrap();
    let small = ReadOptions { max_memory: 1000, ..options() };
    let err = read_npz(&path, &small).unwrap_err();
    assert!(matches!(err, IoError::Limits { width: 30, height: 40, .. }), "{err}");
    // An archive of nothing.
    std::fs::write(&path, zip_archive(&[])).unwrap();
    assert_format(read_npz(&path, &options()), "no arrays");
}

#[test]
fn npz_member_claiming_a_huge_size_is_refused_before_decompressing() {
    let dir = TestDir::new("npz-bomb");
    let path = dir.join("arrays.npz");
    let a = npy_bytes(&dir, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    for deflated in [false, true] {
        let mut archive = zip_archive(&[("a.npy", &a, deflated)]);
        // Declare 4 GB uncompressed in the local and the central header.
        patch_sizes(&mut archive, 0xffff_fff0);
        let start = Instant::now();
        assert_format(read_bytes(read_npz, &path, &archive, &options()), "member 'a.npy'");
        assert!(start.elapsed() < Duration::from_secs(10));
    }
    // A member whose array header claims more than the member holds.
    let mut lying = a.clone();
    let at = lying.windows(6).position(|w| w == b"(2, 3)").unwrap();
    lying[at..at + 6].copy_from_slice(b"(9, 9)");
    let archive = zip_archive(&[("a.npy", &lying, true)]);
    assert_format(read_bytes(read_npz, &path, &archive, &options()), "needs 324 data bytes");
}

/// Sets the uncompressed size of every member, in the local and the central headers.
fn patch_sizes(archive: &mut [u8], size: u32) {
    for at in 0..archive.len().saturating_sub(4) {
        let offset = match archive[at..at + 4] {
            [0x50, 0x4b, 0x03, 0x04] => 22,
            [0x50, 0x4b, 0x01, 0x02] => 24,
            _ => continue,
        };
        archive[at + offset..at + offset + 4].copy_from_slice(&size.to_le_bytes());
    }
}

#[test]
fn npz_truncations_are_refused_and_changed_bytes_never_change_the_array() {
    let dir = TestDir::new("npz-fuzz");
    let path = dir.join("arrays.npz");
    let a = npy_bytes(&dir, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    let b = npy_bytes(&dir, &[1, 2], &[7.0, 8.0]);
    for deflated in [false, true] {
        let archive = zip_archive(&[("a.npy", &a, deflated), ("b.npy", &b, !deflated)]);
        let options = ReadOptions { array: Some("b".into()), ..options() };
        let (intact, accepted) =
            check_truncations_and_flips(read_npz, &path, &archive, &options, |_| false);
        // Many bytes go unread or unchecked (member a, local header signatures, timestamps),
        // so many changed copies read; but the CRC-32 of member b guards every byte read
        // from it, so each reads exactly as the intact archive.
        assert!(!accepted.is_empty() && accepted.len() < 5 * archive.len());
        for Accepted { at, raster } in &accepted {
            assert!(same_samples(raster, &intact), "byte {at}: {:?}", raster.samples);
        }
    }
}

#[test]
fn npy_raster_keeps_array_rows_and_refuses_non_finite_samples() {
    let dir = TestDir::new("npy-raster");
    let path = dir.join("grid.npy");
    write_npy_f32(&path, &[3, 1], &[1.0, 2.0, 3.0]).unwrap();
    assert_eq!(read_npy(&path, &options()).unwrap().samples, [1.0, 2.0, 3.0]);
    write_npy_f32(&path, &[3, 1], &[1.0, f32::NAN, 3.0]).unwrap();
    let err = read_npy(&path, &options()).unwrap_err();
    assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    let mut good = std::fs::read(&path).unwrap();
    let nan_at = good.len() - 8;
    good[nan_at..nan_at + 4].copy_from_slice(&2f32.to_le_bytes());
    let (intact, accepted) =
        check_truncations_and_flips(read_npy, &path, &good, &options(), |_| false);
    // No checksum: a changed data byte reads as another height (or is refused as NaN or
    // infinite). The header is text that must parse with a shape matching the data, so a
    // changed header byte is refused unless it does not matter (the minor version, '<' made
    // '=' on a little-endian machine): whatever reads is 1 x 3, and a header change keeps
    // the samples.
    let data_at = good.len() - 12;
    assert!(accepted.iter().filter(|a| a.at < data_at).count() <= 8, "header changes read");
    for Accepted { at, raster } in &accepted {
        assert_eq!((raster.width, raster.height), (intact.width, intact.height), "byte {at}");
        assert!(*at >= data_at || same_samples(raster, &intact), "byte {at}");
    }
}
