//! Mosaics (`open_mosaic`): SRTM tiles placed by their names and GeoTIFFs by their
//! georeference equal the stitched rasters, gaps are voids, the first valid input wins where
//! they overlap, and inputs that do not fit together are refused naming the files.

mod common;
#[path = "common/tiff_files.rs"]
mod tiff_files;

use common::TestDir;
use relief_core::{DVec2, GridGeometry, HeightField};
use relief_io::{
    metres_per_degree, open_mosaic, read_raster, IoError, Raster, ReadOptions, RowSource,
};
use std::path::PathBuf;
use tiff::encoder::colortype::Gray32Float;
use tiff::encoder::Compression;
use tiff::tags::Tag;
use tiff_files::{encode_f32_tiles, encode_strips, projected, Extra, TileCodec};

fn options() -> ReadOptions {
    ReadOptions { max_memory: 1 << 30, ..ReadOptions::default() }
}

/// Every row of `source`, read in bands of `band` rows from the north down.
fn read_all(source: &mut dyn RowSource, band: usize) -> Vec<f32> {
    let (w, h) = (source.width(), source.height());
    let mut all = vec![0f32; w * h];
    let mut end = h;
    while end > 0 {
        let start = end.saturating_sub(band);
        source.read_rows(start, &mut all[start * w..end * w]).unwrap();
        end = start;
    }
    all
}

/// `inputs` (rasters with their south-west sample's place) stitched into a `w x h` grid: the
/// first valid sample wins, NaN where none is.
fn stitch(w: usize, h: usize, inputs: &[(&Raster, usize, usize)]) -> Vec<f32> {
    let mut out = vec![f32::NAN; w * h];
    for &(raster, col, row) in inputs {
        for r in 0..raster.height {
            for c in 0..raster.width {
                let o = &mut out[(row + r) * w + col + c];
                if o.is_nan() {
                    *o = raster.samples[r * raster.width + c];
                }
            }
        }
    }
    out
}

fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()))
}

/// A 1201 x 1201 tile whose heights depend on `seed`, with a few holes.
fn srtm_field(seed: usize) -> HeightField {
    let n = 1201;
    let samples = (0..n * n).map(|i| ((i * 37 + seed * 101) % 4001) as f32 - 500.0).collect();
    let holes = (0..n * n).map(|i| i % 1009 == seed).collect();
    HeightField::new(n, n, samples, GridGeometry::unit()).unwrap().with_holes(holes).unwrap()
}

#[test]
fn two_by_two_srtm_tiles_share_their_edges_and_equal_the_stitched_tiles() {
    let dir = TestDir::new("mosaic-hgt");
    let names = ["N36W085.hgt", "N36W084.hgt", "N37W085.hgt", "N37W084.hgt"];
    let paths: Vec<PathBuf> = names.iter().map(|n| dir.join(n)).collect();
    for (k, path) in paths.iter().enumerate() {
        relief_io::hgt::write_hgt(path, &srtm_field(k)).unwrap();
    }
    let rasters: Vec<Raster> = paths.iter().map(|p| read_raster(p, &options()).unwrap()).collect();
    let mut mosaic = open_mosaic(&paths, &options()).unwrap();
    // Neighbours share their edge samples: 2 x 1200 + 1 a side.
    assert_eq!((mosaic.width(), mosaic.height()), (2401, 2401));
    let places = [(0, 0), (1200, 0), (0, 1200), (1200, 1200)];
    let inputs: Vec<(&Raster, usize, usize)> =
        rasters.iter().zip(places).map(|(r, (c, w))| (r, c, w)).collect();
    let expected = stitch(2401, 2401, &inputs);
    assert!(same_bits(&read_all(mosaic.as_mut(), 500), &expected));
    // The geometry of one tile, at the mosaic's central latitude (37° N).
    let g = mosaic.geometry();
    let step = 1.0 / 1200.0;
    let (per_lon, per_lat) = metres_per_degree(37.0);
    assert_eq!((g.dx, g.dy), (step * per_lon, step * per_lat));
    assert_eq!(g.origin, DVec2::new(-85.0 * per_lon - 0.5 * g.dx, 36.0 * per_lat - 0.5 * g.dy));
    let info = mosaic.info();
    assert_eq!(info.from_degrees.unwrap().latitude, 37.0);
    let geotransform = info.georeference.as_ref().unwrap().geotransform;
    assert_eq!(geotransform, [-85.0 - 0.5 * step, step, 0.0, 38.0 + 0.5 * step, 0.0, -step]);

    // A mosaic of one tile is that tile, as read_raster reads it.
    for (path, raster) in paths.iter().zip(&rasters) {
        let mut one = open_mosaic(std::slice::from_ref(path), &options()).unwrap();
        assert_eq!(one.geometry(), raster.geometry);
        assert_eq!(one.info(), &raster.info);
        assert!(same_bits(&read_all(one.as_mut(), 777), &raster.samples));
    }

    // Three of the four: the missing tile's square is void, but for the edges its
    // neighbours share with it.
    let three = [paths[0].clone(), paths[1].clone(), paths[3].clone()];
    let mut mosaic = open_mosaic(&three, &options()).unwrap();
    assert_eq!((mosaic.width(), mosaic.height()), (2401, 2401));
    let inputs = [inputs[0], inputs[1], inputs[3]];
    let expected = stitch(2401, 2401, &inputs);
    let got = read_all(mosaic.as_mut(), 1000);
    assert!(same_bits(&got, &expected));
    assert!(got[1800 * 2401 + 600].is_nan(), "inside the missing tile");
}

/// A projected float32 GeoTIFF of `w x h` samples `base + i` (file order), pixels of 10 x 20,
/// north-west corner at (`west`, `north`), nodata -1 (every 7th sample).
fn tile(
    dir: &TestDir,
    name: &str,
    (w, h): (usize, usize),
    (west, north): (f64, f64),
    base: f32,
) -> PathBuf {
    let values: Vec<f32> =
        (0..w * h).map(|i| if i % 7 == 3 { -1.0 } else { base + i as f32 }).collect();
    let mut extras = projected(10.0, 20.0, west, north);
    extras.push(Extra::Ascii(Tag::GdalNodata, "-1"));
    let bytes = encode_f32_tiles(&values, (w, h), 16, TileCodec::Deflate, &[], &extras);
    dir.file(name, &bytes)
}

#[test]
fn geotiffs_are_placed_by_their_georeference_with_gaps_as_voids() {
    let dir = TestDir::new("mosaic-tif");
    // a: 20 x 10 at (1000, 5000); b: 15 x 12, east of a with a gap of 5 columns and 3 rows
    // lower; c: 8 x 6, overlapping a's south-east corner (a wins where it is valid).
    let a = tile(&dir, "a.tif", (20, 10), (1000.0, 5000.0), 0.0);
    let b = tile(&dir, "b.tif", (15, 12), (1250.0, 4940.0), 1000.0);
    let c = tile(&dir, "c.tif", (8, 6), (1150.0, 4860.0), 2000.0);
    let paths = vec![a, b, c];
    let rasters: Vec<Raster> = paths.iter().map(|p| read_raster(p, &options()).unwrap()).collect();
    let mut mosaic = open_mosaic(&paths, &options()).unwrap();
    // West 1000, east 1400: 40 columns. North 5000, south min(4800, 4700, 4740) = 4700: 15 rows.
    assert_eq!((mosaic.width(), mosaic.height()), (40, 15));
    let g = mosaic.geometry();
    assert_eq!((g.dx, g.dy, g.origin), (10.0, 20.0, DVec2::new(1000.0, 4700.0)));
    // South-west samples, in grid rows from the south: a at row 5, b at row 0, c at row 2.
    let inputs = [(&rasters[0], 0, 5), (&rasters[1], 25, 0), (&rasters[2], 15, 2)];
    let expected = stitch(40, 15, &inputs);
    for band in [1, 4, 15] {
        assert!(same_bits(&read_all(mosaic.as_mut(), band), &expected), "bands of {band}");
    }
    assert!(expected[0].is_nan() && expected[14 * 40 + 22].is_nan(), "the gaps are voids");
    let geotransform = mosaic.info().georeference.as_ref().unwrap().geotransform;
    assert_eq!(geotransform, [1000.0, 10.0, 0.0, 5000.0, 0.0, -20.0]);

    // One file is itself.
    let mut one = open_mosaic(&paths[1..2], &options()).unwrap();
    assert_eq!(one.geometry(), rasters[1].geometry);
    assert_eq!(one.info(), &rasters[1].info);
    assert!(same_bits(&read_all(one.as_mut(), 5), &rasters[1].samples));
}

#[test]
fn each_request_reads_only_the_inputs_it_overlaps() {
    let dir = TestDir::new("mosaic-streaming");
    let north = tile(&dir, "north.tif", (6, 4), (0.0, 160.0), 0.0);
    // The southern input holds a NaN that is not its nodata value: reading it fails.
    let mut values = vec![1.0f32; 24];
    values[5] = f32::NAN;
    let bytes = encode_strips::<Gray32Float>(
        &values,
        (6, 4),
        Compression::Uncompressed,
        Some(1),
        &projected(10.0, 20.0, 0.0, 80.0),
    );
    let south = dir.file("south.tif", &bytes);
    let mut mosaic = open_mosaic(&[north, south], &options()).unwrap();
    assert_eq!((mosaic.width(), mosaic.height()), (6, 8));
    let mut band = vec![0f32; 4 * 6];
    mosaic.read_rows(4, &mut band).unwrap();
    let err = mosaic.read_rows(3, &mut band[..6]).unwrap_err();
    assert!(err.to_string().contains("south.tif"), "{err}");
}

/// Refuses `paths`, and checks the message names `files` and says `why`.
fn assert_refused(paths: &[PathBuf], files: &[&str], why: &str) {
    let err = match open_mosaic(paths, &options()) {
        Ok(_) => panic!("{paths:?} accepted"),
        Err(e) => e,
    };
    let text = err.to_string();
    assert!(matches!(err, IoError::Mosaic { .. }), "{text}");
    for file in files {
        assert!(text.contains(file), "{file} not in: {text}");
    }
    assert!(text.contains(why), "'{why}' not in: {text}");
}

#[test]
fn inputs_that_do_not_fit_together_are_refused_naming_them() {
    let dir = TestDir::new("mosaic-refused");
    let a = tile(&dir, "a.tif", (5, 5), (0.0, 100.0), 0.0);
    let file = |name: &str, extras: Vec<Extra>| {
        let values = vec![1.0f32; 25];
        dir.file(name, &encode_f32_tiles(&values, (5, 5), 16, TileCodec::None, &[], &extras))
    };
    let coarse = file("coarse.tif", projected(20.0, 20.0, 50.0, 100.0));
    assert_refused(&[a.clone(), coarse], &["a.tif", "coarse.tif"], "pixel size");
    let off = file("off.tif", projected(10.0, 20.0, 55.0, 100.0));
    assert_refused(&[a.clone(), off], &["a.tif", "off.tif"], "0.500 pixels off");
    let mut degrees = projected(10.0, 20.0, 50.0, 80.0);
    degrees[2] = Extra::Shorts(Tag::GeoKeyDirectoryTag, vec![1, 1, 0, 1, 1024, 0, 1, 2]);
    let degrees = file("degrees.tif", degrees);
    assert_refused(&[a.clone(), degrees], &["a.tif", "degrees.tif"], "projection");
    let utm = |zone: u16| {
        let mut extras = projected(10.0, 20.0, 50.0, 100.0);
        extras[2] = Extra::Shorts(
            Tag::GeoKeyDirectoryTag,
            vec![1, 1, 0, 2, 1024, 0, 1, 1, 3072, 0, 1, zone],
        );
        extras
    };
    let (z33, z34) = (file("z33.tif", utm(32633)), file("z34.tif", utm(32634)));
    assert_refused(&[z33.clone(), z34], &["z33.tif", "z34.tif"], "coordinate reference systems");
    let bare = file("bare.tif", Vec::new());
    assert_refused(&[a.clone(), bare], &["bare.tif"], "no georeference");

    let hgt = dir.join("N10E010.hgt");
    relief_io::hgt::write_hgt(&hgt, &srtm_field(1)).unwrap();
    assert_refused(&[hgt.clone(), a.clone()], &["N10E010.hgt", "a.tif"], "one kind");
    let unnamed = dir.join("tile.hgt");
    relief_io::hgt::write_hgt(&unnamed, &srtm_field(2)).unwrap();
    assert_refused(&[hgt.clone(), unnamed], &["tile.hgt"], "N36W085.hgt");
    let fine = dir.join("N10E011.hgt");
    let n = 3601;
    let field = HeightField::new(n, n, vec![0.0; n * n], GridGeometry::unit()).unwrap();
    relief_io::hgt::write_hgt(&fine, &field).unwrap();
    assert_refused(&[hgt, fine], &["N10E010.hgt", "N10E011.hgt"], "one spacing");
    let asc = dir.join("grid.asc");
    relief_io::write_height_field(
        &asc,
        &HeightField::new(2, 2, vec![0.0; 4], GridGeometry::unit()).unwrap(),
    )
    .unwrap();
    assert_refused(&[asc.clone(), asc], &["grid.asc"], ".hgt tiles");
    assert_refused(&[], &[], "no input files");

    // A file's own error names it.
    let broken = dir.file("broken.tif", b"II*\0 not a tiff");
    let err = open_mosaic(&[a, broken], &options()).err().unwrap();
    assert!(err.to_string().contains("broken.tif"), "{err}");
}
