//! The store on disk: a build that stops and is resumed gives the store an uninterrupted build
//! gives, byte for byte; an incomplete store is refused; damaged tiles are named.

use relief_core::{DVec2, GridGeometry, Surface};
use relief_io::{Format, InMemoryRows, Raster, RasterInfo};
use relief_tiles::{
    build_store, BuildOptions, Precision, SourceFile, TileError, TileId, TileStore,
};
use std::path::{Path, PathBuf};

fn raster(width: usize, height: usize) -> Raster {
    let samples = (0..width * height)
        .map(|k| {
            let (c, r) = ((k % width) as f32, (k / width) as f32);
            if (c - 20.0).abs() < 3.0 && (r - 9.0).abs() < 2.0 {
                f32::NAN
            } else {
                (c * 0.3).sin() * 10.0 + r * 0.25 + (c * r * 0.01).cos()
            }
        })
        .collect();
    Raster {
        width,
        height,
        samples,
        geometry: GridGeometry {
            dx: 30.0,
            dy: 30.0,
            z_scale: 1.0,
            origin: DVec2::new(500.0, 1000.0),
        },
        info: RasterInfo {
            format: Format::Npy,
            sample_type: "float32".into(),
            georeferenced: false,
            from_degrees: None,
            nodata: None,
            georeference: None,
            height_unit: relief_io::HeightUnit::default(),
        },
    }
}

fn temp(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("relief-tiles-store-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn sources() -> Vec<SourceFile> {
    vec![SourceFile { path: "in.npy".into(), bytes: 1234, modified_ns: 99 }]
}

fn build(
    dir: &Path,
    precision: Precision,
    fail_after: Option<u64>,
) -> Result<relief_tiles::BuildReport, TileError> {
    let mut rows = InMemoryRows::new(raster(203, 77));
    let options = BuildOptions { tile: 16, precision, fail_after, ..BuildOptions::default() };
    build_store(&mut rows, sources(), dir, &options, &|_, _| {})
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (e.file_name().to_string_lossy().into_owned(), std::fs::read(e.path()).unwrap())
        })
        .collect();
    out.sort();
    out
}

#[test]
fn a_resumed_build_equals_an_uninterrupted_one() {
    for precision in [Precision::F32, Precision::F16] {
        let whole = temp(&format!("whole-{}", relief_tiles::precision_name(precision)));
        let report = build(&whole, precision, None).unwrap();
        assert_eq!(report.built, report.tiles);
        for stop in [0, 1, 17, 50, report.tiles - 1] {
            let dir = temp(&format!("resumed-{}-{stop}", relief_tiles::precision_name(precision)));
            let error = build(&dir, precision, Some(stop)).unwrap_err();
            assert!(matches!(error, TileError::Injected(n) if n == stop), "{error}");
            // Interrupted: refused for rendering, readable for `relief info`.
            let refused = TileStore::open(&dir).unwrap_err();
            assert!(
                matches!(refused, TileError::Incomplete { done, .. } if done == stop),
                "{refused}"
            );
            assert_eq!(TileStore::open_any(&dir).unwrap().progress(), (stop, report.tiles));
            let resumed = build(&dir, precision, None).unwrap();
            assert_eq!((resumed.resumed, resumed.built), (stop, report.tiles - stop));
            assert!(files(&dir) == files(&whole), "stopped after {stop}: the stores differ");
            std::fs::remove_dir_all(&dir).unwrap();
        }
        std::fs::remove_dir_all(&whole).unwrap();
    }
}

#[test]
fn a_store_of_other_inputs_or_options_is_not_resumed() {
    let dir = temp("mismatch");
    build(&dir, Precision::F32, Some(5)).unwrap_err();
    let error = build(&dir, Precision::F16, None).unwrap_err();
    assert!(error.to_string().contains("other options"), "{error}");
    let mut rows = InMemoryRows::new(raster(203, 77));
    let other = vec![SourceFile { path: "in.npy".into(), bytes: 1235, modified_ns: 99 }];
    let options = BuildOptions { tile: 16, ..BuildOptions::default() };
    let error = build_store(&mut rows, other, &dir, &options, &|_, _| {}).unwrap_err();
    assert!(error.to_string().contains("other input files"), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
    // A folder with something else in it is not taken for a store.
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    let error = build(&dir, Precision::F32, None).unwrap_err();
    assert!(error.to_string().contains("not a tile store"), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn damaged_and_truncated_tiles_are_named() {
    let dir = temp("damaged");
    build(&dir, Precision::F32, None).unwrap();
    let store = TileStore::open(&dir).unwrap();
    let id = TileId { level: 0, col: 3, row: 1 };
    let index = store.layout().index_of(id);
    let slot = store.layout().stored_samples() as u64 * 4;
    drop(store);
    let data = dir.join("tiles.data");
    let mut bytes = std::fs::read(&data).unwrap();
    bytes[(index * slot + 100) as usize] ^= 0x40;
    std::fs::write(&data, &bytes).unwrap();
    let store = TileStore::open(&dir).unwrap();
    let error = store.load(id, Surface::Triangles).unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains("tile (level 0, column 3, row 1)") && text.contains("checksum"),
        "{text}"
    );
    // A data file cut short: the last tile's slot is gone.
    let last = store.layout().id_at(store.layout().tile_count() - 1);
    bytes.truncate(bytes.len() - 10);
    std::fs::write(&data, &bytes).unwrap();
    let error = store.load(last, Surface::Boxes).unwrap_err();
    assert!(error.to_string().contains("truncated"), "{error}");
    // A table record damaged: the store names the tile at open.
    let table = dir.join("tiles.table");
    let mut records = std::fs::read(&table).unwrap();
    records[32 * 5 + 3] ^= 1;
    std::fs::write(&table, &records).unwrap();
    let error = TileStore::open(&dir).unwrap_err();
    assert!(error.to_string().contains("tile (level 0, column 5, row 0)"), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
}
