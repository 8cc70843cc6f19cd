//! relief's native `.mlhm` files: bit-exact round trips in f32 and f16 (hand-made, random and
//! the real reference scene), archives built by hand as NumPy would build them, and refusal,
//! by cause and without panic, of every broken file.
//! In a bare clone (no ../shared) a test that reads the shared data is reported ignored.

mod common;

use common::{clients, shared_data, TestDir};
use proptest::prelude::*;
use relief_core::{Mlhm, MlhmColumn, Precision};
use relief_io::mlhm::{
    read_mlhm_native, read_mlhm_native_from_bytes, read_mlhm_scene, write_mlhm_native,
};
use relief_io::{IoError, ReadOptions};
use std::io::{Read, Write};
use std::path::Path;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipArchive, ZipWriter};

fn main() {
    clients::run(vec![
        clients::trial!(f32_maps_round_trip_bit_exactly_in_the_documented_layout),
        clients::trial!(f16_maps_round_trip_bit_exactly_as_float16),
        clients::trial_reading!(
            the_real_reference_scene_round_trips,
            "data/ngwm24-scene/scene.json"
        ),
        clients::trial!(archives_as_numpy_writes_them_are_read),
        clients::trial!(missing_arrays_wrong_types_and_shapes_are_refused_by_cause),
        clients::trial!(hostile_sizes_are_refused_before_allocating),
        clients::trial!(broken_invariants_are_refused_naming_cell_and_column),
        clients::trial!(truncated_and_foreign_files_are_refused),
        clients::trial!(writing_into_a_missing_folder_fails_and_leaves_nothing),
        clients::trial!(random_maps_round_trip_bit_exactly),
        clients::trial!(corrupted_bytes_are_refused_or_read_as_the_map_written),
    ]);
}

const INF: f32 = f32::INFINITY;

/// A 3 x 2 map of up to 3 columns: an overhang with water, a negative bedrock, a NaN-free
/// value that is no f16.
fn small_map() -> Mlhm {
    let mut map = Mlhm::new(3, 2, 3, 0.5).unwrap();
    map.set_cell(
        1,
        1,
        &[
            MlhmColumn::new(1.0, 0.5, 0.25, 2.0),
            MlhmColumn::new(3.0, 0.0, 0.0, 4.5),
            MlhmColumn::new(5.0, 0.1, 1e-7, INF),
        ],
    )
    .unwrap();
    map.set_cell(2, 0, &[MlhmColumn::new(-1.5, 0.125, 2.0, INF)]).unwrap();
    map
}

/// The bits of every value of `map`'s column slots (so that -0.0 and 0.0 differ).
fn bits(map: &Mlhm) -> Vec<u32> {
    map.raw_columns().iter().flat_map(|c| c.to_array()).map(f32::to_bits).collect()
}

/// Writes `map` and reads it back.
fn round_trip(map: &Mlhm, dir: &TestDir, name: &str) -> Mlhm {
    let path = dir.join(name);
    write_mlhm_native(&path, map).unwrap();
    read_mlhm_native(&path, &ReadOptions::default()).unwrap()
}

/// The names and `.npy` headers of the members of the archive in `bytes`.
fn members(bytes: &[u8]) -> Vec<(String, String)> {
    let mut archive = ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    (0..archive.len())
        .map(|i| {
            let mut member = archive.by_index(i).unwrap();
            let mut data = Vec::new();
            member.read_to_end(&mut data).unwrap();
            let len = u16::from_le_bytes([data[8], data[9]]) as usize;
            (member.name().to_owned(), String::from_utf8_lossy(&data[10..10 + len]).into_owned())
        })
        .collect()
}

fn f32_maps_round_trip_bit_exactly_in_the_documented_layout() {
    let dir = TestDir::new("mlhm-native-f32");
    let map = small_map();
    let back = round_trip(&map, &dir, "small.mlhm");
    assert_eq!(back, map);
    assert_eq!(bits(&back), bits(&map));
    assert_eq!(back.precision(), Precision::F32);
    let bytes = std::fs::read(dir.join("small.mlhm")).unwrap();
    let members = members(&bytes);
    let names: Vec<&str> = members.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["relief_mlhm_version.npy", "cell_size.npy", "layer_counts.npy", "columns.npy"]
    );
    for (header, descr, shape) in [
        (&members[0].1, "'<i4'", "(1,)"),
        (&members[1].1, "'<f8'", "()"),
        (&members[2].1, "'|u1'", "(2, 3)"),
        (&members[3].1, "'<f4'", "(3, 2, 3, 4)"),
    ] {
        assert!(header.contains(descr) && header.contains(shape), "{header}");
    }
    // The same map gives the same bytes.
    write_mlhm_native(&dir.join("again.mlhm"), &map).unwrap();
    assert_eq!(std::fs::read(dir.join("again.mlhm")).unwrap(), bytes);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2, "a temporary file is left");
}

fn f16_maps_round_trip_bit_exactly_as_float16() {
    let dir = TestDir::new("mlhm-native-f16");
    let map = small_map().to_precision(Precision::F16).unwrap();
    let back = round_trip(&map, &dir, "half.mlhm");
    assert_eq!(back.precision(), Precision::F16);
    assert_eq!(back, map);
    assert_eq!(bits(&back), bits(&map));
    let bytes = std::fs::read(dir.join("half.mlhm")).unwrap();
    let header = &members(&bytes)[3].1;
    assert!(header.contains("'<f2'") && header.contains("(3, 2, 3, 4)"), "{header}");
    let f32_size = std::fs::metadata(dir.join("half.mlhm")).unwrap().len();
    write_mlhm_native(&dir.join("full.mlhm"), &small_map()).unwrap();
    assert!(f32_size < std::fs::metadata(dir.join("full.mlhm")).unwrap().len());
}

fn the_real_reference_scene_round_trips() {
    let Some(path) = shared_data("data/ngwm24-scene/scene.json") else { return };
    let dir = TestDir::new("mlhm-native-real");
    let map = read_mlhm_scene(&path, &ReadOptions::default()).unwrap().mlhm;
    let back = round_trip(&map, &dir, "ngwm24.mlhm");
    assert_eq!(back.layer_counts(), map.layer_counts());
    // Slots above a cell's layer count are zeros in the file; every used slot is kept.
    for y in 0..map.height() {
        for x in 0..map.width() {
            let (a, b): (Vec<_>, Vec<_>) =
                (map.cell_columns(x, y).collect(), back.cell_columns(x, y).collect());
            assert_eq!(a, b);
        }
    }
}

// ---- Archives built by hand, as numpy.savez would build them.

/// A `.npy` file of version 1.0 with this header and data.
fn npy(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
    let order = if fortran { "True" } else { "False" };
    let mut dict = format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': {shape}, }}");
    while (10 + dict.len() + 1) % 64 != 0 {
        dict.push(' ');
    }
    dict.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    bytes.extend_from_slice(dict.as_bytes());
    bytes.extend_from_slice(data);
    bytes
}

/// A zip archive of `members` (name, bytes), stored or deflated.
fn archive(members: &[(String, Vec<u8>)], deflated: bool) -> Vec<u8> {
    let mut zip = ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let method = if deflated { CompressionMethod::Deflated } else { CompressionMethod::Stored };
    for (name, bytes) in members {
        zip.start_file(name.as_str(), SimpleFileOptions::default().compression_method(method))
            .unwrap();
        zip.write_all(bytes).unwrap();
    }
    zip.finish().unwrap().into_inner()
}

/// The f32 values of a little-endian float32 `.npy` file of version 1.0.
fn f32_values(npy: &[u8]) -> Vec<f32> {
    let start = 10 + usize::from(u16::from_le_bytes([npy[8], npy[9]]));
    npy[start..].chunks_exact(4).map(|b| f32::from_le_bytes(b.try_into().unwrap())).collect()
}

fn le<T: Copy, const N: usize>(values: &[T], to: fn(T) -> [u8; N]) -> Vec<u8> {
    values.iter().flat_map(|&v| to(v)).collect()
}

/// The members of a valid 2 x 1 map of 2 layers: cell (0, 0) one column, cell (1, 0) two.
fn valid_members() -> Vec<(String, Vec<u8>)> {
    let columns: [f32; 16] = [
        0.0, 1.0, 0.5, INF, /* (1,0,0) */ 2.0, 0.0, 0.0, 3.0, //
        0.0, 0.0, 0.0, 0.0, /* (1,0,1) */ 4.0, 0.25, 0.0, INF,
    ];
    vec![
        ("relief_mlhm_version.npy".into(), npy("<i4", false, "(1,)", &1i32.to_le_bytes())),
        ("cell_size.npy".into(), npy("<f8", false, "()", &2.5f64.to_le_bytes())),
        ("layer_counts.npy".into(), npy("|u1", false, "(1, 2)", &[1, 2])),
        ("columns.npy".into(), npy("<f4", false, "(2, 1, 2, 4)", &le(&columns, f32::to_le_bytes))),
    ]
}

/// The map of [`valid_members`].
fn valid_map() -> Mlhm {
    let mut map = Mlhm::new(2, 1, 2, 2.5).unwrap();
    map.set_cell(0, 0, &[MlhmColumn::new(0.0, 1.0, 0.5, INF)]).unwrap();
    map.set_cell(
        1,
        0,
        &[MlhmColumn::new(2.0, 0.0, 0.0, 3.0), MlhmColumn::new(4.0, 0.25, 0.0, INF)],
    )
    .unwrap();
    map
}

/// Reads the archive of `members` (stored), within `options`.
fn read_members(members: &[(String, Vec<u8>)], options: &ReadOptions) -> Result<Mlhm, IoError> {
    read_mlhm_native_from_bytes(&archive(members, false), Path::new("t.mlhm"), options)
}

/// [`valid_members`] with member `name` replaced by `bytes` (removed for `None`).
fn with(name: &str, bytes: Option<Vec<u8>>) -> Vec<(String, Vec<u8>)> {
    let mut members = valid_members();
    let at = members.iter().position(|(n, _)| n == name).unwrap();
    match bytes {
        Some(bytes) => members[at].1 = bytes,
        None => {
            members.remove(at);
        }
    }
    members
}

fn archives_as_numpy_writes_them_are_read() {
    let options = ReadOptions::default();
    assert_eq!(read_members(&valid_members(), &options).unwrap(), valid_map());
    let bytes = archive(&valid_members(), true);
    assert_eq!(
        read_mlhm_native_from_bytes(&bytes, Path::new("d.mlhm"), &options).unwrap(),
        valid_map()
    );
    // Member names without .npy, other arrays beside, scalars as (1,) or (), int64 version,
    // float32 cell size, big-endian and Fortran-ordered arrays.
    let mut members = valid_members();
    for (name, _) in &mut members {
        *name = name.trim_end_matches(".npy").to_owned();
    }
    members.push(("notes.npy".into(), npy("<f4", false, "(2,)", &[0; 8])));
    assert_eq!(read_members(&members, &options).unwrap(), valid_map());
    let version = npy(">i8", false, "()", &1i64.to_be_bytes());
    let cell_size = npy("<f4", false, "(1,)", &2.5f32.to_le_bytes());
    let mut members = with("relief_mlhm_version.npy", Some(version));
    members[1].1 = cell_size;
    assert_eq!(read_members(&members, &options).unwrap(), valid_map());
    // Fortran order: shape (2, 1, 2, 4), element (k, y, x, v) at k + 2 (y + 1 (x + 2 v)).
    let c_order = f32_values(&valid_members()[3].1);
    let mut fortran = vec![0f32; 16];
    for (i, &v) in c_order.iter().enumerate() {
        let (k, x, value) = (i / 8, (i / 4) % 2, i % 4);
        fortran[k + 2 * (x + 2 * value)] = v;
    }
    let columns = npy(">f4", true, "(2, 1, 2, 4)", &le(&fortran, f32::to_be_bytes));
    let counts = npy("|u1", true, "(1, 2)", &[1, 2]);
    let mut members = with("columns.npy", Some(columns));
    members[2].1 = counts;
    assert_eq!(read_members(&members, &options).unwrap(), valid_map());
    // float16 columns, written by hand.
    let c_half: Vec<u16> = c_order.iter().map(|&v| half::f16::from_f32(v).to_bits()).collect();
    let columns = npy("<f2", false, "(2, 1, 2, 4)", &le(&c_half, u16::to_le_bytes));
    let map = read_members(&with("columns.npy", Some(columns)), &options).unwrap();
    assert_eq!((map.precision(), map.raw_columns()), (Precision::F16, valid_map().raw_columns()));
    // Slots above a cell's layer count are ignored.
    let mut garbage = c_order.clone();
    garbage[8..12].copy_from_slice(&[f32::NAN, -1.0, 7.0, 0.0]);
    let columns = npy("<f4", false, "(2, 1, 2, 4)", &le(&garbage, f32::to_le_bytes));
    assert_eq!(read_members(&with("columns.npy", Some(columns)), &options).unwrap(), valid_map());
}

/// Checks that reading `members` fails with an error `kind` accepts whose message holds
/// every one of `mentions`.
fn refused(members: &[(String, Vec<u8>)], kind: fn(&IoError) -> bool, mentions: &[&str]) {
    let options = ReadOptions { max_memory: 1 << 20, ..ReadOptions::default() };
    let err = read_members(members, &options).unwrap_err();
    let text = err.to_string();
    assert!(kind(&err), "wrong kind: {text}");
    for m in mentions.iter().chain(&["t.mlhm"]) {
        assert!(text.contains(m), "'{m}' missing from: {text}");
    }
}

fn format(e: &IoError) -> bool {
    matches!(e, IoError::Format { .. })
}
fn unsupported(e: &IoError) -> bool {
    matches!(e, IoError::Unsupported { .. })
}
fn invalid(e: &IoError) -> bool {
    matches!(e, IoError::InvalidData { .. })
}
fn limits(e: &IoError) -> bool {
    matches!(e, IoError::Limits { .. })
}

fn missing_arrays_wrong_types_and_shapes_are_refused_by_cause() {
    refused(&with("relief_mlhm_version.npy", None), format, &["not a relief .mlhm"]);
    refused(&with("columns.npy", None), format, &["no array 'columns'"]);
    refused(&with("cell_size.npy", None), format, &["no array 'cell_size'"]);
    refused(&with("layer_counts.npy", None), format, &["layer_counts"]);
    let version = |v: i32| npy("<i4", false, "(1,)", &v.to_le_bytes());
    refused(&with("relief_mlhm_version.npy", Some(version(2))), unsupported, &["version 2"]);
    refused(&with("relief_mlhm_version.npy", Some(version(0))), unsupported, &["version 0"]);
    let float_version = npy("<f4", false, "(1,)", &1f32.to_le_bytes());
    refused(&with("relief_mlhm_version.npy", Some(float_version)), unsupported, &["float32"]);
    let cell = |descr: &str, shape: &str, v: f64| npy(descr, false, shape, &v.to_le_bytes());
    refused(
        &with("cell_size.npy", Some(cell("<i8", "()", 0.0))),
        unsupported,
        &["int64", "cell_size"],
    );
    refused(&with("cell_size.npy", Some(cell("<f8", "(2,)", 1.0))), format, &["shape [2]"]);
    refused(&with("cell_size.npy", Some(cell("<f8", "(1, 1)", 1.0))), format, &["shape [1, 1]"]);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        refused(&with("cell_size.npy", Some(cell("<f8", "()", bad))), invalid, &["cell_size is"]);
    }
    let counts = |descr: &str, shape: &str, data: &[u8]| npy(descr, false, shape, data);
    refused(
        &with("layer_counts.npy", Some(counts("<u2", "(1, 2)", &[1, 0, 2, 0]))),
        unsupported,
        &["uint16", "uint8"],
    );
    refused(
        &with("layer_counts.npy", Some(counts("|u1", "(2,)", &[1, 2]))),
        format,
        &["2 dimensions"],
    );
    refused(
        &with("layer_counts.npy", Some(counts("|u1", "(2, 1)", &[1, 2]))),
        format,
        &["(L, 2, 1, 4)"],
    );
    refused(
        &with("layer_counts.npy", Some(counts("|u1", "(0, 2)", &[]))),
        format,
        &["dimension of 0"],
    );
    refused(
        &with("layer_counts.npy", Some(counts("|u1", "(1, 2)", &[1]))),
        format,
        &["needs 2 data bytes"],
    );
    let columns = |descr: &str, shape: &str, n: usize| npy(descr, false, shape, &vec![0; n]);
    refused(
        &with("columns.npy", Some(columns("<f8", "(2, 1, 2, 4)", 128))),
        unsupported,
        &["float64", "float32 or float16"],
    );
    refused(
        &with("columns.npy", Some(columns("<f4", "(2, 1, 2, 3)", 48))),
        format,
        &["(L, H, W, 4)"],
    );
    refused(&with("columns.npy", Some(columns("<f4", "(2, 2, 4)", 64))), format, &["4 dimensions"]);
    refused(
        &with("columns.npy", Some(columns("<f4", "(300, 1, 2, 4)", 9600))),
        unsupported,
        &["300 layers"],
    );
    refused(
        &with("columns.npy", Some(columns("<f4", "(2, 1, 2, 4)", 60))),
        format,
        &["needs 64 data bytes"],
    );
    refused(&with("columns.npy", Some(columns("<c8", "(2, 1, 2, 4)", 128))), unsupported, &["c8"]);
}

fn hostile_sizes_are_refused_before_allocating() {
    // A header that claims far more than the member holds.
    let huge = npy("<f4", false, "(200, 100000, 100000, 4)", &[0; 64]);
    refused(&with("columns.npy", Some(huge)), format, &["the member holds 64"]);
    let counts = npy("|u1", false, "(100000, 100000)", &[1; 16]);
    refused(&with("layer_counts.npy", Some(counts)), format, &["needs 10000000000 data bytes"]);
    // Honest sizes over the memory budget (1 MiB in `refused`).
    let (w, h) = (1024usize, 64usize);
    let counts = npy("|u1", false, &format!("({h}, {w})"), &vec![1; w * h]);
    let columns = npy("<f4", false, &format!("(1, {h}, {w}, 4)"), &vec![0; w * h * 16]);
    let mut members = with("layer_counts.npy", Some(counts));
    members[3].1 = columns;
    refused(&members, limits, &["1024 x 64"]);
    // A scalar member padded out to megabytes.
    let padded = npy("<f8", false, "()", &[0; 1 << 17]);
    refused(&with("cell_size.npy", Some(padded)), format, &["cell_size"]);
}

fn broken_invariants_are_refused_naming_cell_and_column() {
    let columns = |change: &dyn Fn(&mut [f32])| {
        let mut values = f32_values(&valid_members()[3].1);
        change(&mut values);
        npy("<f4", false, "(2, 1, 2, 4)", &le(&values, f32::to_le_bytes))
    };
    let nan = columns(&|v| v[4] = f32::NAN);
    refused(&with("columns.npy", Some(nan)), invalid, &["cell (1, 0)", "column 0", "NaN"]);
    let negative_sand = columns(&|v| v[1] = -1.0);
    refused(&with("columns.npy", Some(negative_sand)), invalid, &["cell (0, 0)", "sand"]);
    let finite_top = columns(&|v| v[3] = f32::MAX);
    refused(&with("columns.npy", Some(finite_top)), invalid, &["cell (0, 0)", "not +inf"]);
    let ceiling_above_next = columns(&|v| v[7] = 4.5);
    refused(&with("columns.npy", Some(ceiling_above_next)), invalid, &["cell (1, 0)", "column 0"]);
    let water_above_ceiling = columns(&|v| v[6] = 2.0);
    refused(
        &with("columns.npy", Some(water_above_ceiling)),
        invalid,
        &["cell (1, 0)", "water top"],
    );
    for bad in [0u8, 3] {
        let counts = npy("|u1", false, "(1, 2)", &[1, bad]);
        refused(&with("layer_counts.npy", Some(counts)), invalid, &["cell (1, 0)"]);
    }
}

fn truncated_and_foreign_files_are_refused() {
    let dir = TestDir::new("mlhm-native-broken");
    let path = dir.join("small.mlhm");
    write_mlhm_native(&path, &small_map()).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let options = ReadOptions::default();
    for cut in [0, 4, 30, bytes.len() / 2, bytes.len() - 1] {
        let err = read_mlhm_native_from_bytes(&bytes[..cut], &path, &options).unwrap_err();
        assert!(format(&err), "{cut}: {err}");
    }
    let err = read_mlhm_native_from_bytes(b"{\"Terrain/GridSize\": [1, 1]}", &path, &options)
        .unwrap_err();
    assert!(format(&err) && err.to_string().contains("zip"), "{err}");
    let err = read_mlhm_native(&dir.join("absent.mlhm"), &options).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err}");
    let err = read_mlhm_native(dir.path(), &options).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err}");
    // A member whose data no longer matches its CRC.
    let mut flipped = archive(&valid_members(), false);
    let at = flipped.windows(4).position(|w| w == 4.0f32.to_le_bytes()).unwrap();
    flipped[at] ^= 1;
    let err = read_mlhm_native_from_bytes(&flipped, &path, &options).unwrap_err();
    assert!(format(&err) || matches!(err, IoError::Io { .. }), "{err}");
}

fn writing_into_a_missing_folder_fails_and_leaves_nothing() {
    let dir = TestDir::new("mlhm-native-missing");
    let err = write_mlhm_native(&dir.join("no/such.mlhm"), &small_map()).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

// ---- Random maps and random corruption.

/// A random valid map of up to 6 x 5 cells and 4 layers, in f32 or f16.
fn random_map() -> impl Strategy<Value = Mlhm> {
    (1usize..=6, 1usize..=5, 1usize..=4, prop::sample::select(vec![0.25, 1.0, 3.7]), any::<bool>())
        .prop_flat_map(|(w, h, layers, cell_size, half)| {
            let cell = prop::collection::vec(
                (-100f32..100.0, 0f32..3.0, prop_oneof![Just(0f32), 0f32..2.0], 0f32..5.0),
                1..=layers,
            );
            prop::collection::vec(cell, w * h).prop_map(move |cells| {
                let mut map = Mlhm::new(w, h, layers, cell_size).unwrap();
                for (i, stack) in cells.iter().enumerate() {
                    let mut columns = Vec::new();
                    let mut floor = f32::NEG_INFINITY;
                    for &(bedrock, sand, water, gap) in stack {
                        let bedrock = bedrock.max(floor);
                        let column = MlhmColumn::new(bedrock, sand, water, 0.0);
                        let top = column.water_top();
                        columns.push(MlhmColumn { ceiling: top + gap, ..column });
                        floor = top + gap;
                    }
                    columns.last_mut().unwrap().ceiling = INF;
                    map.set_cell(i % w, i / w, &columns).unwrap();
                }
                if half {
                    map.to_precision(Precision::F16).unwrap()
                } else {
                    map
                }
            })
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    fn random_maps_round_trip_bit_exactly(map in random_map()) {
        let dir = TestDir::new("mlhm-native-random");
        let back = round_trip(&map, &dir, "random.mlhm");
        prop_assert_eq!(back.precision(), map.precision());
        prop_assert_eq!(bits(&back), bits(&map));
        prop_assert_eq!(back, map);
    }

    fn corrupted_bytes_are_refused_or_read_as_the_map_written(
        map in random_map(),
        changes in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
        cut in any::<prop::sample::Index>(),
    ) {
        let dir = TestDir::new("mlhm-native-corrupt");
        let path = dir.join("c.mlhm");
        write_mlhm_native(&path, &map).unwrap();
        let mut bytes = std::fs::read(&path).unwrap();
        let options = ReadOptions { max_memory: 16 << 20, ..ReadOptions::default() };
        prop_assert!(read_mlhm_native_from_bytes(&bytes[..cut.index(bytes.len())], &path, &options).is_err());
        for (at, value) in changes {
            let at = at.index(bytes.len());
            bytes[at] = value;
        }
        // Every member's CRC-32 guards what is read from it: a copy that still reads had its
        // changes where nothing is read or checked (timestamps, unused header fields), and
        // holds the map that was written.
        if let Ok(read) = read_mlhm_native_from_bytes(&bytes, &path, &options) {
            prop_assert_eq!(read, map);
        }
    }
}
