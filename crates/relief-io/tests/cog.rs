//! Cloud-optimised GeoTIFFs written block by block ([`CogWriter`]): read by GDAL (through
//! rasterio) as the layer file of the same samples, with tiles and overviews; accepted by
//! rio-cogeo's validator and GDAL's layout checks, as classic TIFF and BigTIFF; resumed after
//! a kill into the same bytes; an existing file replaced only by a complete one.

mod common;

use common::{clients, python, TestDir};
use relief_io::geotiff::{read_geotiff, read_layers_geotiff, write_layers_geotiff, CogWriter};
use relief_io::{Georeference, IoError, Layer, LayerRaster, ReadOptions};
use std::ops::Range;
use std::path::Path;

fn main() {
    clients::run(vec![
        clients::trial!(gdal_reads_a_cog_as_the_layer_file_of_the_same_samples, Rasterio),
        // rio-cogeo brings rasterio with it.
        clients::trial!(rio_cogeo_and_gdals_layout_checks_accept_the_cogs, RioCogeo),
        clients::trial!(a_killed_write_resumes_into_the_file_written_at_once),
        clients::trial!(an_existing_file_is_replaced_only_by_a_complete_one),
        clients::accounting_trial(
            "rio_cogeo_and_gdals_layout_checks_accept_the_cogs",
            clients::Client::RioCogeo,
        ),
    ]);
}

/// The size of most rasters here, tile 128: 8 x 6 tiles, the last column and row cut.
const WIDTH: usize = 1000;
const HEIGHT: usize = 700;

/// Named bands of a `width x height` grid (row 0 south) with voids: a patch, a void row
/// and column, and scattered ones.
fn layers(width: usize, height: usize, names: &[&str]) -> Vec<Layer> {
    names
        .iter()
        .enumerate()
        .map(|(b, name)| Layer {
            name: name.to_string(),
            samples: (0..width * height)
                .map(|i| {
                    let (x, y) = (i % width, i / width);
                    let patch = (300..333).contains(&x) && (400..421).contains(&y);
                    if patch || x == 17 || y == height - 3 || i % 89 == 7 {
                        f32::NAN
                    } else {
                        (x as f32 * 0.05 * (b + 1) as f32).sin() * 80.0 + y as f32 * 0.5
                    }
                })
                .collect(),
        })
        .collect()
}

/// The blocks of `side`-sample squares covering a north-up `width x height` grid, from the
/// north-west corner (edge blocks cut), as (columns, rows), row 0 south.
fn blocks(width: usize, height: usize, side: usize) -> Vec<(Range<usize>, Range<usize>)> {
    let mut out = Vec::new();
    for top in (0..height).step_by(side) {
        for x in (0..width).step_by(side) {
            out.push((x..(x + side).min(width), height.saturating_sub(top + side)..height - top));
        }
    }
    out
}

/// The samples of `layer` (of a `width`-wide grid) in `cols` x `rows`, from `rows.start`.
fn cut(layer: &Layer, width: usize, cols: &Range<usize>, rows: &Range<usize>) -> Vec<f32> {
    rows.clone().flat_map(|y| layer.samples[y * width..][cols.clone()].iter().copied()).collect()
}

/// Writes `block` of `layers` to `out`.
fn write(
    out: &mut CogWriter,
    layers: &[Layer],
    width: usize,
    block: &(Range<usize>, Range<usize>),
) {
    let (cols, rows) = block;
    let bands: Vec<Vec<f32>> = layers.iter().map(|l| cut(l, width, cols, rows)).collect();
    let bands: Vec<&[f32]> = bands.iter().map(Vec::as_slice).collect();
    out.write_block(cols.clone(), rows.clone(), &bands).unwrap();
}

/// What a COG is written from.
struct Job<'a> {
    width: usize,
    height: usize,
    layers: &'a [Layer],
    georeference: Option<&'a Georeference>,
    nodata: Option<f64>,
    tile: usize,
    big: bool,
}

impl Job<'_> {
    fn names(&self) -> Vec<String> {
        self.layers.iter().map(|l| l.name.clone()).collect()
    }

    fn create(&self, path: &Path, fingerprint: &str) -> Result<CogWriter, IoError> {
        let names = self.names();
        let (w, h, g, n, t) = (self.width, self.height, self.georeference, self.nodata, self.tile);
        let mut out = CogWriter::create(path, w, h, &names, g, n, t, fingerprint)?;
        if self.big {
            out.force_big_tiff();
        }
        Ok(out)
    }

    /// Writes the whole COG in blocks of 2 x 2 tiles, in a shuffled order.
    fn write(&self, path: &Path) {
        let mut out = self.create(path, "job").unwrap();
        let all = blocks(self.width, self.height, 2 * self.tile);
        // 7 is prime to the block counts used here: a permutation.
        for k in 0..all.len() {
            write(&mut out, self.layers, self.width, &all[k * 7 % all.len()]);
        }
        assert_eq!(out.done_blocks().len(), all.len());
        out.finish().unwrap();
    }

    /// The same samples as a layer file.
    fn layer_raster(&self) -> LayerRaster {
        LayerRaster {
            width: self.width,
            height: self.height,
            layers: self.layers.to_vec(),
            georeference: self.georeference.cloned(),
            nodata: self.nodata,
        }
    }
}

/// Whether two sample lists are the same bit for bit, NaN equal to NaN.
fn same(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()))
}

/// The georeference of the DEM fixture (geographic, PixelIsArea, nodata -32768).
fn fixture_georeference() -> Georeference {
    let fixture =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/jacksboro_fault_dem.tif");
    let raster = read_geotiff(&fixture, &ReadOptions::default()).unwrap();
    raster.info.georeference.unwrap()
}

fn gdal_reads_a_cog_as_the_layer_file_of_the_same_samples() {
    let dir = TestDir::new("cog-gdal");
    let layers = layers(WIDTH, HEIGHT, &["shadow", "sky & <sun>"]);
    let (srtm, dem) = (Georeference::srtm_tile(36, -85, 1201), fixture_georeference());
    for (name, georeference, nodata) in
        [("srtm", Some(&srtm), None), ("dem", Some(&dem), Some(-9999.0)), ("none", None, None)]
    {
        let job = Job {
            width: WIDTH,
            height: HEIGHT,
            layers: &layers,
            georeference,
            nodata,
            tile: 128,
            big: false,
        };
        let cog = dir.join(&format!("{name}.cog.tif"));
        let strips = dir.join(&format!("{name}.strips.tif"));
        job.write(&cog);
        write_layers_geotiff(&strips, &job.layer_raster()).unwrap();
        // relief reads it back as written.
        let back = read_layers_geotiff(&cog, &ReadOptions::default()).unwrap();
        assert_eq!(back.georeference.as_ref(), georeference, "{name}");
        for (a, b) in back.layers.iter().zip(&layers) {
            assert_eq!(a.name, b.name);
            assert!(same(&a.samples, &b.samples), "{name}: {}", a.name);
        }
        // GDAL reads it as the layer file of the same samples, tiled, with its overviews.
        let script = format!(
            r#"
import numpy as np, rasterio, warnings
cog = rasterio.open('{cog}')
ref = rasterio.open('{strips}')
assert (cog.width, cog.height, cog.count) == ({WIDTH}, {HEIGHT}, 2), (cog.width, cog.height)
assert cog.dtypes == ('float32', 'float32'), cog.dtypes
assert cog.transform == ref.transform, (cog.transform, ref.transform)
assert cog.crs == ref.crs, (cog.crs, ref.crs)
assert cog.descriptions == ref.descriptions == ('shadow', 'sky & <sun>'), cog.descriptions
assert (cog.nodata is None and ref.nodata is None) or np.array_equal(
    np.float64(cog.nodata), np.float64(ref.nodata), equal_nan=True), (cog.nodata, ref.nodata)
assert cog.tags() == ref.tags(), (cog.tags(), ref.tags())
with warnings.catch_warnings():
    warnings.simplefilter('ignore')
    assert cog.is_tiled and not ref.is_tiled
assert cog.profile['tiled'] and cog.block_shapes == [(128, 128)] * 2, cog.block_shapes
assert cog.compression.name == 'deflate', cog.compression
assert cog.interleaving.value == 'BAND', cog.interleaving
assert cog.tags(ns='IMAGE_STRUCTURE').get('PREDICTOR') == '3', cog.tags(ns='IMAGE_STRUCTURE')
for band in (1, 2):
    assert cog.overviews(band) == [2, 4, 8], cog.overviews(band)
    got, want = cog.read(band), ref.read(band)
    assert np.array_equal(got.view('u4'), want.view('u4')), np.argwhere(got.view('u4') != want.view('u4'))[:5]
# Overview level 1 is the 2 x 2 mean of the full resolution, voids ignored.
full = cog.read().astype('float64')
if cog.nodata is not None and not np.isnan(cog.nodata):
    full[full == cog.nodata] = np.nan
void = np.float32(np.nan if cog.nodata is None else cog.nodata)
padded = np.full((2, {HEIGHT} + {HEIGHT} % 2, {WIDTH} + {WIDTH} % 2), np.nan)
padded[:, :{HEIGHT}, :{WIDTH}] = full
groups = padded.reshape(2, padded.shape[1] // 2, 2, padded.shape[2] // 2, 2)
with warnings.catch_warnings():
    warnings.simplefilter('ignore')
    mean = np.nanmean(groups, axis=(2, 4))
want = np.where(np.isnan(mean), void, mean).astype('float32')
with rasterio.open('{cog}', OVERVIEW_LEVEL=0) as level:
    assert (level.width, level.height) == ({WIDTH} // 2, {HEIGHT} // 2), (level.width, level.height)
    got = level.read()
assert np.array_equal(got, want, equal_nan=True), np.argwhere(~np.isclose(got, want, equal_nan=True))[:5]
exact = (got.view('u4') == want.view('u4')) | (np.isnan(got) & np.isnan(want))
print('ok', exact.mean())
"#,
            cog = cog.display(),
            strips = strips.display(),
        );
        let out = python("rasterio", &script).unwrap();
        assert_eq!(out, "ok 1.0", "{name}");
    }
}

fn rio_cogeo_and_gdals_layout_checks_accept_the_cogs() {
    let dir = TestDir::new("cog-validate");
    let two = layers(WIDTH, HEIGHT, &["a", "b"]);
    let wide = layers(2100, 1300, &["hillshade"]);
    let small = layers(300, 200, &["x", "y", "z"]);
    let dem = fixture_georeference();
    let job = |width, height, layers, tile, big| Job {
        width,
        height,
        layers,
        georeference: Some(&dem),
        nodata: None,
        tile,
        big,
    };
    let cases = [
        ("two-bands", job(WIDTH, HEIGHT, &two[..], 128, false)),
        ("big-tiff", job(WIDTH, HEIGHT, &two[..], 128, true)),
        ("one-band-512", job(2100, 1300, &wide[..], 512, false)),
        ("one-tile", job(300, 200, &small[..], 512, false)),
        ("one-tile-big", job(300, 200, &small[..], 256, true)),
    ];
    for (name, job) in &cases {
        let path = dir.join(&format!("{name}.tif"));
        job.write(&path);
        let magic = &std::fs::read(&path).unwrap()[..4];
        assert_eq!(magic, if job.big { b"II+\0" } else { b"II*\0" }, "{name}");
    }
    let names: Vec<&str> = cases.iter().map(|(name, _)| *name).collect();
    // rio-cogeo's cog_validate, then what GDAL's validate_cloud_optimized_geotiff.py checks
    // with --full-check=yes, through rasterio: the first directory right after the ghost area,
    // directories by decreasing size, each level's tiles row by row in increasing offsets,
    // each between its leader and trailer, the smallest overview's first, the full
    // resolution's last, after every directory.
    let script = format!(
        r#"
import rasterio, json
from rio_cogeo.cogeo import cog_validate
d = '{dir}'
report = {{}}
for name in {names:?}:
    path = f'{{d}}/{{name}}.tif'
    valid, errors, warnings = cog_validate(path, quiet=True)
    assert valid and not errors and not warnings, (name, errors, warnings)
    with open(path, 'rb') as f:
        head = f.read(16 + 43)
    start = 16 if head[2] == 0x2b else 8
    line = head[start:start + 43].decode()
    assert line.startswith('GDAL_STRUCTURAL_METADATA_SIZE=') and line.endswith(' bytes\n'), line
    size = int(line[30:36])
    expected_ifd = start + 43 + size
    expected_ifd += expected_ifd % 2
    with rasterio.open(path) as src, open(path, 'rb') as data:
        ghost = src.get_tag_item('GDAL_STRUCTURAL_METADATA', 'TIFF')
        for item in ['LAYOUT=IFDS_BEFORE_DATA', 'BLOCK_ORDER=ROW_MAJOR', 'BLOCK_LEADER=SIZE_AS_UINT4',
                     'BLOCK_TRAILER=LAST_4_BYTES_REPEATED', 'KNOWN_INCOMPATIBLE_EDITION=NO']:
            assert item in ghost, (name, ghost)
        # GDAL takes the file for a COG.
        assert src.tags(ns='IMAGE_STRUCTURE').get('LAYOUT') == 'COG', src.tags(ns='IMAGE_STRUCTURE')
        ifds = [int(src.get_tag_item('IFD_OFFSET', 'TIFF', bidx=1))]
        assert ifds[0] == expected_ifd, (name, ifds[0], expected_ifd)
        levels = src.overviews(1)
        sizes = [(src.width, src.height)]
        for i in range(len(levels)):
            ifds.append(int(src.get_tag_item('IFD_OFFSET', 'TIFF', bidx=1, ovr=i)))
            with rasterio.open(path, OVERVIEW_LEVEL=i) as level:
                sizes.append((level.width, level.height))
                assert level.block_shapes[0] == src.block_shapes[0], (name, level.block_shapes)
        assert ifds == sorted(ifds), (name, ifds)
        assert all(a[0] >= b[0] and a[1] >= b[1] for a, b in zip(sizes, sizes[1:])), sizes
        bw, bh = src.block_shapes[0][1], src.block_shapes[0][0]
        firsts = []
        for level in range(len(levels) + 1):
            w, h = sizes[level]
            ovr = {{}} if level == 0 else {{'ovr': level - 1}}
            last = 0
            for band in range(1, src.count + 1):
                for y in range((h + bh - 1) // bh):
                    for x in range((w + bw - 1) // bw):
                        offset = int(src.get_tag_item(f'BLOCK_OFFSET_{{x}}_{{y}}', 'TIFF', bidx=band, **ovr))
                        count = int(src.get_tag_item(f'BLOCK_SIZE_{{x}}_{{y}}', 'TIFF', bidx=band, **ovr))
                        assert offset > last and count > 0, (name, level, band, x, y, offset, last)
                        # The leader holds the tile's size; the trailer repeats its last 4 bytes.
                        data.seek(offset - 4)
                        chunk = data.read(count + 8)
                        assert int.from_bytes(chunk[:4], 'little') == count, (name, level, x, y)
                        assert chunk[count:count + 4] == chunk[count + 4:], (name, level, x, y)
                        if band == 1 and x == 0 and y == 0:
                            firsts.append(offset)
                        last = offset
        assert firsts[-1] > ifds[-1], (name, firsts, ifds)
        assert firsts == sorted(firsts, reverse=True), (name, firsts)
        report[name] = [len(levels), src.count, sizes[-1]]
print(json.dumps(report, sort_keys=True))
"#,
        dir = dir.path().display(),
    );
    let out = python("rio_cogeo", &script).unwrap();
    // Overview levels, bands and the smallest level's size.
    let expected = [
        r#""big-tiff": [3, 2, [125, 88]]"#,
        r#""one-band-512": [3, 1, [263, 163]]"#,
        r#""one-tile": [0, 3, [300, 200]]"#,
        r#""one-tile-big": [1, 3, [150, 100]]"#,
        r#""two-bands": [3, 2, [125, 88]]"#,
    ];
    assert_eq!(out, format!("{{{}}}", expected.join(", ")));
    // GDAL reads the BigTIFF's samples as written.
    let script = format!(
        r#"
import numpy as np, rasterio
a = rasterio.open('{dir}/big-tiff.tif').read()
b = rasterio.open('{dir}/two-bands.tif').read()
assert np.array_equal(a.view('u4'), b.view('u4'))
print(np.isnan(a).sum())
"#,
        dir = dir.path().display(),
    );
    let voids: usize = python("rio_cogeo", &script).unwrap().parse().unwrap();
    let expected: usize = two.iter().map(|l| l.samples.iter().filter(|v| v.is_nan()).count()).sum();
    assert_eq!(voids, expected);
}

fn a_killed_write_resumes_into_the_file_written_at_once() {
    let dir = TestDir::new("cog-resume");
    let layers = layers(WIDTH, HEIGHT, &["shadow", "sky"]);
    let dem = fixture_georeference();
    let job = Job {
        width: WIDTH,
        height: HEIGHT,
        layers: &layers,
        georeference: Some(&dem),
        nodata: Some(-1.0),
        tile: 128,
        big: false,
    };
    let at_once = dir.join("at-once.tif");
    job.write(&at_once);
    let expected = std::fs::read(&at_once).unwrap();
    let path = dir.join("out.tif");
    let all = blocks(WIDTH, HEIGHT, 256);
    // 5 of the 12 blocks, edge blocks among them; then the writer is dropped, as a kill
    // after write_block returned leaves it.
    let first: Vec<_> = [11, 3, 0, 7, 8].iter().map(|&k| all[k].clone()).collect();
    let mut out = job.create(&path, "input 1, options A").unwrap();
    assert!(!out.resumed());
    for block in &first {
        write(&mut out, &layers, WIDTH, block);
    }
    drop(out);
    assert!(!path.exists());
    // The same job resumes them; the rest written, the file is the one written at once.
    let mut out = job.create(&path, "input 1, options A").unwrap();
    assert!(out.resumed());
    assert_eq!(out.done_blocks(), first);
    for block in all.iter().filter(|b| !first.contains(b)) {
        write(&mut out, &layers, WIDTH, block);
    }
    out.finish().unwrap();
    assert!(std::fs::read(&path).unwrap() == expected, "resumed file differs");
    // Another job's spill is not resumed: it starts over.
    let mut out = job.create(&dir.join("again.tif"), "input 1, options A").unwrap();
    write(&mut out, &layers, WIDTH, &all[4]);
    drop(out);
    let mut out = job.create(&dir.join("again.tif"), "input 2, options A").unwrap();
    assert!(!out.resumed() && out.done_blocks().is_empty());
    for block in &all {
        write(&mut out, &layers, WIDTH, block);
    }
    out.finish().unwrap();
    assert!(std::fs::read(dir.join("again.tif")).unwrap() == expected);
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["again.tif", "at-once.tif", "out.tif"]);
}

fn an_existing_file_is_replaced_only_by_a_complete_one() {
    let dir = TestDir::new("cog-replace");
    let path = dir.join("shade.tif");
    std::fs::write(&path, b"the old shade").unwrap();
    let layers = layers(WIDTH, HEIGHT, &["shade"]);
    let job = Job {
        width: WIDTH,
        height: HEIGHT,
        layers: &layers,
        georeference: None,
        nodata: None,
        tile: 256,
        big: false,
    };
    let all = blocks(WIDTH, HEIGHT, 256);
    let mut out = job.create(&path, "job").unwrap();
    for block in &all[..all.len() - 1] {
        write(&mut out, &layers, WIDTH, block);
        assert_eq!(std::fs::read(&path).unwrap(), b"the old shade");
    }
    let err = out.finish().unwrap_err();
    assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    // The south-east block, columns 768..1000, rows 0..188 (row 0 south), is missing.
    assert!(
        err.to_string().contains(
            "finished with 1 of 12 tiles not written; the first is band \"shade\", columns \
             768..1000, rows 0..188"
        ),
        "{err}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), b"the old shade");
    // The rerun resumes, writes the last block and replaces the file.
    let mut out = job.create(&path, "job").unwrap();
    assert!(out.resumed());
    assert_eq!(out.done_blocks().len(), all.len() - 1);
    write(&mut out, &layers, WIDTH, &all[all.len() - 1]);
    out.finish().unwrap();
    let back = read_layers_geotiff(&path, &ReadOptions::default()).unwrap();
    assert!(same(&back.layers[0].samples, &layers[0].samples));
}
