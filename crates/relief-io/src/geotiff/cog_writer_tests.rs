//! Tests of [`CogWriter`]: its file read back by relief's reader against
//! [`write_layers_geotiff`]'s, bad input, resuming after a kill, an unfinished write.

use super::*;
use crate::test_dir::TestDir;
use crate::ReadOptions;
use crate::{read_layers_geotiff, write_layers_geotiff, GeoTiffTags, Layer, LayerRaster};

/// Two bands of a `width x height` grid (row 0 south) with voids: a patch, and scattered.
fn layers(width: usize, height: usize) -> Vec<Layer> {
    let band = |name: &str, k: f32| Layer {
        name: name.into(),
        samples: (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                let patch = (20..45).contains(&x) && (30..41).contains(&y);
                if patch || i % 97 == 5 {
                    f32::NAN
                } else {
                    (x as f32 * k).sin() * 50.0 + y as f32 * 0.25
                }
            })
            .collect(),
    };
    vec![band("shadow", 0.1), band("a&b <c>", 0.3)]
}

/// The samples of `layer` in grid columns `cols`, rows `rows`, row-major from `rows.start`.
fn cut(layer: &Layer, width: usize, cols: &Range<usize>, rows: &Range<usize>) -> Vec<f32> {
    rows.clone().flat_map(|y| layer.samples[y * width..][cols.clone()].iter().copied()).collect()
}

/// The blocks of `tile`-tile multiples (`step` tiles a side) covering a north-up grid.
fn blocks(width: usize, height: usize, side: usize) -> Vec<(Range<usize>, Range<usize>)> {
    let mut out = Vec::new();
    for top in (0..height).step_by(side) {
        for x in (0..width).step_by(side) {
            let rows = height.saturating_sub(top + side)..height - top;
            out.push((x..(x + side).min(width), rows));
        }
    }
    out
}

/// Writes `layers` block by block in `order` (indices into `blocks(.., side)`).
#[allow(clippy::too_many_arguments)]
fn write_cog(
    path: &Path,
    (width, height): (usize, usize),
    layers: &[Layer],
    georeference: Option<&Georeference>,
    nodata: Option<f64>,
    tile: usize,
    side: usize,
    order: impl Fn(usize) -> usize,
) -> CogWriter {
    let names: Vec<String> = layers.iter().map(|l| l.name.clone()).collect();
    let mut out =
        CogWriter::create(path, width, height, &names, georeference, nodata, tile, "job").unwrap();
    let all = blocks(width, height, side);
    for k in 0..all.len() {
        let (cols, rows) = &all[order(k) % all.len()];
        let bands: Vec<Vec<f32>> = layers.iter().map(|l| cut(l, width, cols, rows)).collect();
        let bands: Vec<&[f32]> = bands.iter().map(Vec::as_slice).collect();
        out.write_block(cols.clone(), rows.clone(), &bands).unwrap();
    }
    out
}

/// Whether two sample lists are the same bit for bit, any NaN equal to any NaN.
fn same(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()))
}

/// A placement whose file's first row is the southernmost.
fn south_up_georeference() -> Georeference {
    #[rustfmt::skip]
    let matrix = vec![
        30.0, 0.0, 0.0, 500_000.0,
        0.0, 20.0, 0.0, 4_100_000.0,
        0.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
    ];
    let tags = GeoTiffTags { model_transformation: Some(matrix), ..GeoTiffTags::default() };
    let georeference = Georeference::from_geotiff_tags(tags).unwrap();
    assert!(georeference.is_south_up());
    georeference
}

#[test]
fn reads_back_as_write_layers_geotiff_writes_the_same_layers() {
    let dir = TestDir::new("cog-writer-read");
    let (width, height) = (300, 200);
    let srtm = Georeference::srtm_tile(36, -85, 1201);
    let south_up = south_up_georeference();
    for (georeference, nodata, tile, side) in [
        (Some(&srtm), Some(-9999.0), 128, 128),
        (None, None, 128, 256),
        (Some(&south_up), None, 256, 256),
    ] {
        let layers = layers(width, height);
        let path = dir.path().join("out.tif");
        // Blocks in a shuffled order.
        let out =
            write_cog(&path, (width, height), &layers, georeference, nodata, tile, side, |k| {
                k * 5 + 1
            });
        out.finish().unwrap();
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["out.tif"], "the spill and journal are removed");
        let back = read_layers_geotiff(&path, &ReadOptions::default()).unwrap();
        let reference = LayerRaster {
            width,
            height,
            layers: layers.clone(),
            georeference: georeference.cloned(),
            nodata,
        };
        let strips = dir.path().join("strips.tif");
        write_layers_geotiff(&strips, &reference).unwrap();
        let expected = read_layers_geotiff(&strips, &ReadOptions::default()).unwrap();
        std::fs::remove_file(&strips).unwrap();
        assert_eq!((back.width, back.height), (width, height));
        assert_eq!(back.georeference, expected.georeference);
        assert_eq!(back.nodata.map(f64::to_bits), expected.nodata.map(f64::to_bits));
        for (a, b) in back.layers.iter().zip(&expected.layers) {
            assert_eq!(a.name, b.name);
            assert!(same(&a.samples, &b.samples), "{georeference:?} {nodata:?}");
        }
        assert!(same(&back.layers[1].samples, &layers[1].samples));
    }
}

#[test]
fn a_big_tiff_reads_back() {
    let dir = TestDir::new("cog-writer-big");
    let path = dir.path().join("big.tif");
    let layers = layers(300, 200);
    let mut out = write_cog(&path, (300, 200), &layers, None, None, 128, 128, |k| k);
    out.force_big_tiff();
    out.finish().unwrap();
    assert_eq!(&std::fs::read(&path).unwrap()[..4], b"II+\0");
    let back = read_layers_geotiff(&path, &ReadOptions::default()).unwrap();
    assert!(same(&back.layers[0].samples, &layers[0].samples));
}

#[test]
fn bad_parameters_are_refused() {
    let dir = TestDir::new("cog-writer-parameters");
    let path = dir.path().join("out.tif");
    let names = vec!["a".to_string()];
    let create = |w, h, names: &[String], nodata, tile| {
        CogWriter::create(&path, w, h, names, None, nodata, tile, "job").map(|_| ()).unwrap_err()
    };
    for tile in [0, 64, 100, 129, 2048] {
        let err = create(300, 200, &names, None, tile);
        assert!(err.to_string().contains(&format!("tile side {tile} is not")), "{err}");
    }
    assert!(create(0, 200, &names, None, 128).to_string().contains("empty"));
    assert!(create(300, 200, &[], None, 128).to_string().contains("no bands"));
    let err = create(300, 200, &names, Some(0.1), 128);
    assert!(err.to_string().contains("not a float32 value"), "{err}");
    let err = create(1 << 33, 2, &names, None, 128);
    assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
    let err = CogWriter::create(dir.path(), 2, 2, &names, None, None, 128, "job").unwrap_err();
    assert!(err.to_string().contains("is a directory"), "{err}");
    assert!(CogWriter::create(Path::new("/"), 2, 2, &names, None, None, 128, "job").is_err());
    let missing = dir.path().join("no/such/dir/x.tif");
    let err = CogWriter::create(&missing, 2, 2, &names, None, None, 128, "job").unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err}");
}

#[test]
fn bad_blocks_are_refused_and_the_writer_goes_on() {
    let dir = TestDir::new("cog-writer-blocks");
    let path = dir.path().join("out.tif");
    let (width, height) = (300, 200);
    let layers = layers(width, height);
    let names: Vec<String> = layers.iter().map(|l| l.name.clone()).collect();
    let mut out = CogWriter::create(&path, width, height, &names, None, None, 128, "job").unwrap();
    assert_eq!((out.tile(), out.resumed(), out.done_blocks().len()), (128, false, 0));
    // Samples of the block, zeros for one past the raster.
    let block = |cols: Range<usize>, rows: Range<usize>| -> Vec<Vec<f32>> {
        if cols.end > width || rows.end > height {
            return vec![vec![0.0; cols.len() * rows.len()]; 2];
        }
        layers.iter().map(|l| cut(l, width, &cols, &rows)).collect()
    };
    let write = |out: &mut CogWriter, cols: Range<usize>, rows: Range<usize>| {
        let bands = block(cols.clone(), rows.clone());
        let bands: Vec<&[f32]> = bands.iter().map(Vec::as_slice).collect();
        out.write_block(cols, rows, &bands)
    };
    // The northern row of tiles is grid rows 72..200.
    for (cols, rows, why) in [
        (0..128, 0..128, "file rows 72..200"),
        (10..138, 72..200, "columns 10..138"),
        (0..100, 72..200, "columns 0..100"),
        (0..128, 72..201, "not within"),
        (128..128, 72..200, "empty"),
    ] {
        let err = write(&mut out, cols, rows).unwrap_err();
        assert!(
            matches!(err, IoError::InvalidData { .. }) && err.to_string().contains(why),
            "{err}"
        );
    }
    write(&mut out, 0..256, 72..200).unwrap();
    let err = write(&mut out, 128..300, 72..200).unwrap_err();
    assert!(
        err.to_string().contains("overlaps a block already written (the block of columns 0..256"),
        "{err}"
    );
    let one = block(256..300, 72..200);
    let err = out.write_block(256..300, 72..200, &[&one[0]]).unwrap_err();
    assert!(err.to_string().contains("1 bands given; the file has 2"), "{err}");
    let err = out.write_block(256..300, 72..200, &[&one[0], &one[1][1..]]).unwrap_err();
    assert!(err.to_string().contains("band \"a&b <c>\" holds 5631 samples"), "{err}");
    write(&mut out, 256..300, 72..200).unwrap();
    write(&mut out, 0..300, 0..72).unwrap();
    assert_eq!(out.done_blocks(), [(0..256, 72..200), (256..300, 72..200), (0..300, 0..72)]);
    out.finish().unwrap();
    let back = read_layers_geotiff(&path, &ReadOptions::default()).unwrap();
    assert!(same(&back.layers[0].samples, &layers[0].samples));
}

#[test]
fn an_unfinished_write_leaves_the_old_file_and_resumes() {
    let dir = TestDir::new("cog-writer-unfinished");
    let path = dir.path().join("out.tif");
    std::fs::write(&path, b"old").unwrap();
    let (width, height) = (300, 200);
    let layers = layers(width, height);
    // Three of the 6 blocks, then finished too early.
    killed_after(&path, &layers, 3, |k| k);
    let names: Vec<String> = layers.iter().map(|l| l.name.clone()).collect();
    let out = CogWriter::create(&path, width, height, &names, None, None, 128, "job").unwrap();
    let err = out.finish().unwrap_err();
    assert!(
        err.to_string().contains(
            "finished with 6 of 12 tiles not written; the first is band \
                                  \"shadow\", columns 0..128, rows 0..72"
        ),
        "{err}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    let mut listing: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    listing.sort();
    assert_eq!(listing, [".out.tif.cog-journal", ".out.tif.cog-spill", "out.tif"]);
    // The rerun resumes the three blocks.
    let out = CogWriter::create(&path, width, height, &names, None, None, 128, "job").unwrap();
    assert!(out.resumed());
    assert_eq!(out.done_blocks(), [(0..128, 72..200), (128..256, 72..200), (256..300, 72..200)]);
}

/// Writes the first `count` of the 6 blocks of a 300 x 200 grid (tile 128), then drops
/// the writer as a kill would leave it.
fn killed_after(path: &Path, layers: &[Layer], count: usize, order: fn(usize) -> usize) {
    let names: Vec<String> = layers.iter().map(|l| l.name.clone()).collect();
    let mut out = CogWriter::create(path, 300, 200, &names, None, None, 128, "job").unwrap();
    let all = blocks(300, 200, 128);
    for k in 0..count {
        let (cols, rows) = &all[order(k)];
        let bands: Vec<Vec<f32>> = layers.iter().map(|l| cut(l, 300, cols, rows)).collect();
        let bands: Vec<&[f32]> = bands.iter().map(Vec::as_slice).collect();
        out.write_block(cols.clone(), rows.clone(), &bands).unwrap();
    }
}

/// Resumes the write of `path`, writes the blocks not done and finishes; returns the
/// blocks found done.
fn resume_and_finish(path: &Path, layers: &[Layer]) -> Vec<(Range<usize>, Range<usize>)> {
    let names: Vec<String> = layers.iter().map(|l| l.name.clone()).collect();
    let mut out = CogWriter::create(path, 300, 200, &names, None, None, 128, "job").unwrap();
    assert!(out.resumed());
    let done = out.done_blocks().to_vec();
    for (cols, rows) in blocks(300, 200, 128) {
        if !done.contains(&(cols.clone(), rows.clone())) {
            let bands: Vec<Vec<f32>> = layers.iter().map(|l| cut(l, 300, &cols, &rows)).collect();
            let bands: Vec<&[f32]> = bands.iter().map(Vec::as_slice).collect();
            out.write_block(cols, rows, &bands).unwrap();
        }
    }
    out.finish().unwrap();
    done
}

#[test]
fn a_cut_journal_line_or_spill_drops_the_block_which_is_written_again() {
    let dir = TestDir::new("cog-writer-cut");
    let layers = layers(300, 200);
    let one_go = dir.path().join("one-go.tif");
    write_cog(&one_go, (300, 200), &layers, None, None, 128, 128, |k| k).finish().unwrap();
    let expected = std::fs::read(&one_go).unwrap();
    let path = dir.path().join("out.tif");
    let journal = dir.path().join(".out.tif.cog-journal");
    let spill = dir.path().join(".out.tif.cog-spill");
    let all = blocks(300, 200, 128);
    // A kill while the last journal line was written.
    killed_after(&path, &layers, 3, |k| 5 - k);
    let text = std::fs::read(&journal).unwrap();
    std::fs::write(&journal, &text[..text.len() - 7]).unwrap();
    let done = resume_and_finish(&path, &layers);
    assert_eq!(done, [all[5].clone(), all[4].clone()]);
    assert!(std::fs::read(&path).unwrap() == expected);
    // A spill cut short (its last tiles lost): the block whose tiles lay there is redone.
    killed_after(&path, &layers, 2, |k| k);
    let len = std::fs::metadata(&spill).unwrap().len();
    std::fs::OpenOptions::new().write(true).open(&spill).unwrap().set_len(len - 1).unwrap();
    let done = resume_and_finish(&path, &layers);
    assert_eq!(done, [all[0].clone()]);
    assert!(std::fs::read(&path).unwrap() == expected);
    // A stale temporary file of a killed finish is removed; another job starts over.
    killed_after(&path, &layers, 2, |k| k);
    std::fs::write(dir.path().join(".out.tif.cog-tmp"), b"partial").unwrap();
    let names: Vec<String> = layers.iter().map(|l| l.name.clone()).collect();
    let out = CogWriter::create(&path, 300, 200, &names, None, None, 128, "other job").unwrap();
    assert!(!out.resumed() && out.done_blocks().is_empty());
    assert!(!dir.path().join(".out.tif.cog-tmp").exists());
    assert_eq!(std::fs::metadata(&spill).unwrap().len(), 0);
    drop(out);
    // ... and so does the same job with another tile side.
    let out = CogWriter::create(&path, 300, 200, &names, None, None, 256, "other job").unwrap();
    assert!(!out.resumed());
}

#[test]
fn memory_is_the_tile_index_and_a_few_tiles_per_thread() {
    let threads = rayon::current_num_threads() as u64;
    let small = CogWriter::memory_bytes(1000, 700, 2, 128);
    let large = CogWriter::memory_bytes(32768, 32768, 4, 512);
    let tile = 512 * 512 * 4;
    // 4096 tiles a band at full resolution, 5461 over the levels.
    let index = 5461 * 4 * 12;
    assert!(large > index + threads * tile * 10, "{large}");
    assert!(large < index + 4096 * 400 + threads * tile * 20 + (4 << 20), "{large}");
    assert!(small < large && small > threads * 128 * 128 * 4);
    // Beyond the working set, memory grows with the raster by the index, the list of blocks
    // and a block's journal line, at worst a tile a block and the whole raster one block.
    let huge = CogWriter::memory_bytes(1 << 20, 1 << 20, 1, 512);
    let tiles = 2048 * 2048;
    assert!(huge < tiles * (16 + 32 + 128 + 22) + threads * tile * 20 + (4 << 20), "{huge}");
    // Dimensions create refuses count as the nearest it accepts, without overflow.
    assert_eq!(CogWriter::memory_bytes(1000, 700, 2, 7), small);
    assert!(CogWriter::memory_bytes(usize::MAX, usize::MAX, usize::MAX, usize::MAX) > huge);
    assert!(CogWriter::memory_bytes(0, 0, 0, 0) > 0);
}
