//! GIS interchange checked against GDAL (through rasterio): ZSTD-compressed GeoTIFFs GDAL
//! writes read as GDAL reads them, and layer files written with an input's georeference read
//! by GDAL with that input's placement, CRS and nodata, bands named after their layers.

mod common;

use common::{clients, python, TestDir};
use relief_io::geotiff::{read_geotiff, read_layers_geotiff, write_layers_geotiff};
use relief_io::npy::{read_npy, write_npy_f32};
use relief_io::{read_raster, IoError, Layer, LayerRaster, ReadOptions};
use std::path::Path;

fn main() {
    clients::run(vec![
        clients::trial!(zstd_geotiffs_written_by_gdal_read_as_gdal_reads_them, Rasterio),
        clients::trial!(layer_files_keep_the_inputs_georeference_crs_and_nodata, Rasterio),
        clients::trial!(relief_reads_its_single_layer_file_back),
        clients::trial!(layer_rasters_that_do_not_add_up_are_refused),
        clients::trial!(corrupt_zstd_chunks_and_other_codecs_give_errors, Rasterio),
        clients::trial!(
            geotiffs_written_strip_by_strip_read_in_gdal_with_their_placement,
            Rasterio
        ),
        clients::accounting_trial(
            "zstd_geotiffs_written_by_gdal_read_as_gdal_reads_them",
            clients::Client::Rasterio,
        ),
    ]);
}

/// `samples` (row 0 south) with their rows reversed: north-up, as GDAL gives them.
fn north_up(samples: &[f32], width: usize) -> Vec<f32> {
    samples.chunks_exact(width).rev().flatten().copied().collect()
}

/// Whether two samples are the same, NaN equal to NaN.
fn same(a: f32, b: f32) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

fn zstd_geotiffs_written_by_gdal_read_as_gdal_reads_them() {
    let dir = TestDir::new("gis-zstd");
    // GDAL writes each variant and, beside it, the samples it reads back (north-up .npy) and
    // its geotransform and nodata.
    let script = format!(
        r#"
import numpy as np, rasterio, json
from rasterio.transform import from_origin
d = '{dir}'
w, h = 45, 37
rows, cols = np.mgrid[0:h, 0:w]
cases = []
for dtype in ['int16', 'float32']:
    for predictor in [1, 2, 3]:
        if predictor == 3 and dtype != 'float32':
            continue
        for tiled in [False, True]:
            name = f'{{dtype}}-p{{predictor}}-{{"tiled" if tiled else "striped"}}'
            if dtype == 'int16':
                data = (rows * 97 - cols * 13 - 1000).astype('int16')
                nodata = -32768
            else:
                data = (np.sin(rows * 0.3) * 500 + cols * 0.125 - 20.5).astype('float32')
                nodata = -9999.0
            data[3, 5] = nodata
            data[h - 1, w - 1] = nodata
            opts = dict(compress='ZSTD', predictor=predictor, zstd_level=9)
            if tiled:
                opts.update(tiled=True, blockxsize=16, blockysize=16)
            else:
                opts.update(blockysize=5)
            with rasterio.open(f'{{d}}/{{name}}.tif', 'w', driver='GTiff', width=w, height=h,
                               count=1, dtype=dtype, crs='EPSG:32633', nodata=nodata,
                               transform=from_origin(500000.0, 4200000.0, 30.0, 20.0),
                               **opts) as out:
                out.write(data, 1)
            with rasterio.open(f'{{d}}/{{name}}.tif') as src:
                assert src.compression.name == 'zstd', src.compression
                back = src.read(1).astype('float32')
                np.save(f'{{d}}/{{name}}.npy', back)
                cases.append([name, list(src.transform.to_gdal()), src.nodata])
print(json.dumps(cases))
"#,
        dir = dir.path().display()
    );
    let out = python("rasterio", &script).unwrap();
    let cases: Vec<(String, Vec<f64>, f64)> = parse_cases(&out);
    assert_eq!(cases.len(), 10, "{out}");
    let options = ReadOptions::default();
    for (name, transform, nodata) in cases {
        let raster = read_geotiff(&dir.join(&format!("{name}.tif")), &options)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let gdal = read_npy(&dir.join(&format!("{name}.npy")), &options).unwrap();
        assert_eq!((raster.width, raster.height), (45, 37), "{name}");
        let got = north_up(&raster.samples, raster.width);
        for (i, (&a, &b)) in got.iter().zip(&gdal.samples).enumerate() {
            let b = if f64::from(b) == nodata { f32::NAN } else { b };
            assert!(same(a, b), "{name}: sample {i}: relief {a}, GDAL {b}");
        }
        assert_eq!(raster.void_count(), 2, "{name}");
        assert_eq!(raster.info.nodata, Some(nodata), "{name}");
        // Geometry: the projected coordinates as GDAL places them, origin at the south-west.
        let [x0, dx, _, y0, _, ey]: [f64; 6] = transform.try_into().unwrap();
        let g = raster.geometry;
        assert_eq!((g.dx, g.dy), (dx, -ey), "{name}");
        assert_eq!((g.origin.x, g.origin.y), (x0, y0 + 37.0 * ey), "{name}");
        let georeference = raster.info.georeference.as_ref().unwrap();
        assert_eq!(georeference.geotransform, [x0, dx, 0.0, y0, 0.0, ey], "{name}");
    }
}

/// Parses the JSON list of `[name, transform, nodata]` the script prints.
fn parse_cases(json: &str) -> Vec<(String, Vec<f64>, f64)> {
    let value: serde_json::Value = serde_json::from_str(json).unwrap();
    value
        .as_array()
        .unwrap()
        .iter()
        .map(|case| {
            let name = case[0].as_str().unwrap().to_string();
            let transform = case[1].as_array().unwrap().iter().map(|v| v.as_f64().unwrap());
            (name, transform.collect(), case[2].as_f64().unwrap())
        })
        .collect()
}

fn layer_files_keep_the_inputs_georeference_crs_and_nodata() {
    let dir = TestDir::new("gis-layers");
    // The inputs: GDAL writes a projected and a geographic GeoTIFF; the SRTM tile is raw bytes.
    let script = format!(
        r#"
import numpy as np, rasterio
from rasterio.transform import from_origin
d = '{dir}'
rows, cols = np.mgrid[0:30, 0:41]
data = (rows * 7.5 - cols * 3.25 + 100).astype('float32')
data[2, 3] = -9999
for name, crs, transform in [
        ('projected', 'EPSG:32633', from_origin(433000.5, 5300000.25, 25.0, 12.5)),
        ('geographic', 'EPSG:4326', from_origin(-85.25, 36.75, 1 / 3600, 1 / 3600))]:
    with rasterio.open(f'{{d}}/{{name}}.tif', 'w', driver='GTiff', width=41, height=30,
                       count=1, dtype='float32', crs=crs, transform=transform,
                       nodata=-9999) as out:
        out.write(data, 1)
tile = (np.arange(1201 * 1201) % 3000 - 500).astype('>i2').reshape(1201, 1201)
tile[0, 0] = -32768
tile.tofile(f'{{d}}/N36W085.hgt')
"#,
        dir = dir.path().display()
    );
    python("rasterio", &script).unwrap();
    let names = ["shadow", "sky & <sun>"];
    for input in ["projected.tif", "geographic.tif", "N36W085.hgt"] {
        let source = dir.join(input);
        let raster = read_raster(&source, &ReadOptions::default()).unwrap();
        let georeference = raster.info.georeference.clone();
        assert!(georeference.is_some(), "{input}");
        // Two layers from the samples: a scaled copy and its complement, voids kept.
        let (lo, hi) = raster.value_range().unwrap();
        let scaled: Vec<f32> = raster.samples.iter().map(|v| (v - lo) / (hi - lo)).collect();
        let complement: Vec<f32> = scaled.iter().map(|v| 1.0 - v).collect();
        let layers = LayerRaster {
            width: raster.width,
            height: raster.height,
            layers: vec![
                Layer { name: names[0].into(), samples: scaled },
                Layer { name: names[1].into(), samples: complement },
            ],
            georeference,
            nodata: raster.info.nodata,
        };
        let output = dir.join(&format!("{input}.layers.tif"));
        write_layers_geotiff(&output, &layers).unwrap();
        // What GDAL should read: the layers north-up, voids as the nodata value.
        for (i, layer) in layers.layers.iter().enumerate() {
            let nodata = raster.info.nodata.unwrap() as f32;
            let expected: Vec<f32> = north_up(&layer.samples, raster.width)
                .into_iter()
                .map(|v| if v.is_nan() { nodata } else { v })
                .collect();
            let npy = dir.join(&format!("{input}.band{}.npy", i + 1));
            write_npy_f32(&npy, &[raster.height, raster.width], &expected).unwrap();
        }
        let check = format!(
            r#"
import numpy as np, rasterio
src = rasterio.open('{source}')
out = rasterio.open('{output}')
assert (out.width, out.height) == (src.width, src.height), (out.width, out.height)
assert out.transform == src.transform, (out.transform, src.transform)
assert out.crs == src.crs, (out.crs, src.crs)
assert out.nodata == src.nodata, (out.nodata, src.nodata)
assert out.count == 2 and out.dtypes == ('float32', 'float32'), (out.count, out.dtypes)
assert out.descriptions == {names:?}, out.descriptions
for band in (1, 2):
    want = np.load('{output_base}.band%d.npy' % band)
    got = out.read(band)
    assert np.array_equal(got, want), (band, np.argwhere(got != want)[:5])
print('ok', out.tags().get('AREA_OR_POINT'), src.tags().get('AREA_OR_POINT'))
"#,
            source = source.display(),
            output = output.display(),
            output_base = dir.join(input).display(),
            names = (names[0], names[1]),
        );
        let out = python("rasterio", &check).unwrap();
        assert!(out.starts_with("ok"), "{input}: {out}");
        // AREA_OR_POINT as the input's (Point for an SRTM tile).
        let words: Vec<&str> = out.split_whitespace().collect();
        assert_eq!(words[1], words[2], "{input}: {out}");
        // relief reads its own layer file back: names, samples, georeference, nodata.
        let back = read_layers_geotiff(&output, &ReadOptions::default()).unwrap();
        assert_eq!(back.georeference, layers.georeference, "{input}");
        assert_eq!(back.nodata, layers.nodata, "{input}");
        for (a, b) in back.layers.iter().zip(&layers.layers) {
            assert_eq!(a.name, b.name, "{input}");
            assert!(a.samples.iter().zip(&b.samples).all(|(&x, &y)| same(x, y)), "{input}");
        }
    }
}

fn relief_reads_its_single_layer_file_back() {
    let dir = TestDir::new("gis-own");
    let source = relief_io::Georeference::north_up_grid(1000.0, 2000.0, 30.0, 30.0);
    let samples = vec![0.25, f32::NAN, 0.5, 0.75, 1.0, 0.0];
    let layers = LayerRaster {
        width: 3,
        height: 2,
        layers: vec![Layer { name: "shadow".into(), samples: samples.clone() }],
        georeference: Some(source.clone()),
        nodata: Some(-1.0),
    };
    let path = dir.join("own.tif");
    write_layers_geotiff(&path, &layers).unwrap();
    let raster = read_geotiff(&path, &ReadOptions::default()).unwrap();
    assert_eq!((raster.width, raster.height), (3, 2));
    assert!(raster.samples.iter().zip(&samples).all(|(&a, &b)| same(a, b)), "{:?}", raster.samples);
    assert_eq!(raster.info.nodata, Some(-1.0));
    assert_eq!(raster.info.georeference, Some(source));
    assert_eq!(raster.geometry.origin.y, 2000.0 - 60.0);
}

fn layer_rasters_that_do_not_add_up_are_refused() {
    let dir = TestDir::new("gis-bad-layers");
    let path = dir.join("bad.tif");
    let layer = |n: usize| Layer { name: "a".into(), samples: vec![0.0; n] };
    let raster = |layers: Vec<Layer>, nodata| LayerRaster {
        width: 3,
        height: 2,
        layers,
        georeference: None,
        nodata,
    };
    for bad in [
        raster(vec![], None),
        raster(vec![layer(6), layer(5)], None),
        raster(vec![layer(6)], Some(1e300)),
    ] {
        let err = write_layers_geotiff(&path, &bad).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    }
    assert!(!Path::new(&path).exists());
}

fn corrupt_zstd_chunks_and_other_codecs_give_errors() {
    let dir = TestDir::new("gis-zstd-corrupt");
    let script = format!(
        r#"
import numpy as np, rasterio, warnings
warnings.filterwarnings('ignore')
d = '{dir}'
data = (np.arange(40 * 24).reshape(24, 40) % 251).astype('uint8')
for name, opts in [('zstd', dict(compress='ZSTD', predictor=2, tiled=True, blockxsize=16,
                                 blockysize=16)),
                   ('lerc', dict(compress='LERC')), ('jpeg', dict(compress='JPEG'))]:
    with rasterio.open(f'{{d}}/{{name}}.tif', 'w', driver='GTiff', width=40, height=24,
                       count=1, dtype='uint8', **opts) as out:
        out.write(data, 1)
"#,
        dir = dir.path().display()
    );
    python("rasterio", &script).unwrap();
    let options = ReadOptions::default();
    let path = dir.join("zstd.tif");
    let good = std::fs::read(&path).unwrap();
    let raster = read_geotiff(&path, &options).unwrap();
    assert_eq!(raster.samples[0], (23 * 40 % 251) as f32);
    // Where tile 1's bytes lie.
    let mut decoder = tiff::decoder::Decoder::new(std::io::Cursor::new(&good)).unwrap();
    let offsets = decoder.get_tag_u64_vec(tiff::tags::Tag::TileOffsets).unwrap();
    let counts = decoder.get_tag_u64_vec(tiff::tags::Tag::TileByteCounts).unwrap();
    let (start, len) = (offsets[1] as usize, counts[1] as usize);
    // A broken frame magic: a format error naming the file and the tile.
    let mut bad = good.clone();
    bad[start] ^= 0xff;
    let bad_path = dir.file("bad.tif", &bad);
    let err = read_geotiff(&bad_path, &options).unwrap_err();
    assert!(matches!(err, IoError::Format { .. }), "{err}");
    let text = err.to_string();
    assert!(text.contains("bad.tif") && text.contains("tile 1") && text.contains("ZSTD"), "{text}");
    // Every single-byte change of the tile's data: an error or a raster, never a panic.
    for at in start..start + len {
        let mut bad = good.clone();
        bad[at] = bad[at].wrapping_add(0x41);
        let result = relief_io::read_raster_from_bytes(
            &bad,
            relief_io::Format::GeoTiff,
            Path::new("bad.tif"),
            &options,
        );
        if let Ok(raster) = result {
            assert_eq!(raster.samples.len(), 40 * 24);
        }
    }
    // LERC and JPEG are still refused, by name.
    for (name, codec) in [("lerc.tif", "LERC"), ("jpeg.tif", "JPEG")] {
        let err = read_geotiff(&dir.join(name), &options).unwrap_err();
        assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
        let text = err.to_string();
        assert!(text.to_uppercase().contains(codec) && text.contains("ZSTD"), "{text}");
    }
}

fn geotiffs_written_strip_by_strip_read_in_gdal_with_their_placement() {
    use relief_core::{DVec2, GridGeometry};
    let dir = TestDir::new("gis-strip-writer");
    let (w, h) = (301usize, 977usize);
    let geometry =
        GridGeometry { dx: 2.5, dy: 4.0, z_scale: 1.0, origin: DVec2::new(1000.0, 20.0) };
    let path = dir.join("strips.tif");
    let mut out = relief_io::geotiff::GeoTiffStripWriter::create(&path, w, h, &geometry).unwrap();
    // North first: file row r holds r * 0.5 + column, with a void.
    let rows: Vec<f32> = (0..w * h)
        .map(|i| if i == 7 { f32::NAN } else { (i / w) as f32 * 0.5 + (i % w) as f32 })
        .collect();
    for band in rows.chunks(100 * w) {
        out.write_rows(band).unwrap();
    }
    out.finish().unwrap();
    let expected = dir.join("expected.npy");
    write_npy_f32(&expected, &[h, w], &rows).unwrap();
    let check = format!(
        r#"
import numpy as np, rasterio
out = rasterio.open('{path}')
assert (out.width, out.height) == ({w}, {h}), (out.width, out.height)
assert tuple(out.transform)[:6] == (2.5, 0.0, 1000.0, 0.0, -4.0, 20.0 + {h} * 4.0), out.transform
got = out.read(1)
want = np.load('{expected}')
assert np.array_equal(got, want, equal_nan=True), np.argwhere(got != want)[:5]
assert np.isnan(out.nodata), out.nodata
print('ok')
"#,
        path = path.display(),
        expected = expected.display(),
    );
    assert_eq!(python("rasterio", &check).unwrap(), "ok");
}
