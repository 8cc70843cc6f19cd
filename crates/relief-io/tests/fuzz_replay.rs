//! Replays the fuzz seeds and the regression inputs of tests/fuzz_regressions (inputs that
//! once crashed a reader or aim at one of its error paths): never a panic; every regression
//! input is refused but those named `ok-*`, which read; the seeds, valid files but those named
//! `short*`, read.

use relief_io::mlhm::{read_mlhm_native_from_bytes, read_mlhm_scene_from_bytes};
use relief_io::stacks::stacks_from_bytes;
use relief_io::{read_raster_from_bytes, Format, ReadOptions, VoidPolicy};
use std::path::{Path, PathBuf};

const TARGETS: [&str; 9] =
    ["npy", "npz", "geotiff", "hgt", "asc", "png", "mlhm_scene", "mlhm_native", "stacks_native"];

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut files: Vec<PathBuf> =
        entries.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.is_file()).collect();
    files.sort();
    files
}

/// Reads `bytes` as the fuzz target `target` does.
fn read(target: &str, bytes: &[u8]) -> Result<(), relief_io::IoError> {
    let options = ReadOptions { max_memory: 64 << 20, ..ReadOptions::default() };
    if target == "mlhm_scene" {
        // Two bytes of JSON length (little-endian), the JSON, then the .dat stream.
        let Some((head, rest)) = bytes.split_first_chunk::<2>() else {
            return Err(relief_io::IoError::Format {
                path: "fuzz.json".into(),
                reason: "shorter than its length prefix".into(),
            });
        };
        let json_len = (u16::from_le_bytes(*head) as usize).min(rest.len());
        let (json, dat) = rest.split_at(json_len);
        read_mlhm_scene_from_bytes(json, dat, Path::new("fuzz.json"), &options)?;
        return Ok(());
    }
    if target == "mlhm_native" {
        read_mlhm_native_from_bytes(bytes, Path::new("fuzz.mlhm"), &options)?;
        return Ok(());
    }
    if target == "stacks_native" {
        stacks_from_bytes(bytes, Path::new("fuzz.stacks"))?;
        return Ok(());
    }
    let (format, bytes, name) = match target {
        "npy" => (Format::Npy, bytes, "fuzz.npy"),
        "npz" => (Format::Npz, bytes, "fuzz.npz"),
        "geotiff" => (Format::GeoTiff, bytes, "fuzz.tif"),
        "hgt" => (Format::Hgt, bytes, "N36W085.hgt"),
        "asc" => (Format::Asc, bytes, "fuzz.asc"),
        _ => {
            let Some((&pick, rest)) = bytes.split_first() else { return Ok(()) };
            let format = [Format::Png16, Format::TerrainRgb, Format::Terrarium][pick as usize % 3];
            (format, rest, "fuzz.png")
        }
    };
    let path = Path::new(name);
    let raster = read_raster_from_bytes(bytes, format, path, &options)?;
    raster.clone().into_height_field(path, VoidPolicy::Fill)?;
    raster.into_height_field(path, VoidPolicy::Hole)?;
    Ok(())
}

/// Whether the regression input `name` is one a reader may legitimately accept: those named
/// `ok-*` must read, every other one must be refused.
fn must_read(name: &str) -> bool {
    name.starts_with("ok-")
}

#[test]
fn crashing_inputs_now_give_errors() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let mut count = 0;
    for target in TARGETS {
        let files: Vec<PathBuf> = files_in(&root.join(target))
            .into_iter()
            .filter(|f| !f.ends_with("README.md"))
            .collect();
        assert!(!files.is_empty(), "no regression input in {}", root.join(target).display());
        for file in files {
            let bytes = std::fs::read(&file).unwrap();
            let name = file.file_name().unwrap().to_string_lossy();
            let result = read(target, &bytes);
            if must_read(&name) {
                assert!(result.is_ok(), "{target}/{name} should read: {result:?}");
            } else {
                let err = result.expect_err(&format!("{target}/{name} should be refused"));
                // Bytes in memory: the operating system has no part in the refusal.
                assert!(!matches!(err, relief_io::IoError::Io { .. }), "{target}/{name}: {err}");
                println!("{target}/{name}: {err}");
            }
            count += 1;
        }
    }
    assert!(count >= TARGETS.len(), "only {count} regression inputs found");
}

#[test]
fn only_inputs_named_ok_must_read() {
    assert!(must_read("ok-void-corner.hgt"));
    assert!(!must_read("short-ok.hgt") && !must_read("huge-shape.npy"));
}

#[test]
fn fuzz_seeds_are_valid_files() {
    // Inside the repository: never skipped.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds");
    assert!(root.is_dir(), "{} is absent", root.display());
    let mut count = 0;
    for target in TARGETS {
        for file in files_in(&root.join(target)) {
            let bytes = std::fs::read(&file).unwrap();
            let name = file.file_name().unwrap().to_string_lossy();
            let result = read(target, &bytes);
            if name.starts_with("short") {
                assert!(result.is_err(), "{target}/{name} should be refused");
            } else {
                assert!(result.is_ok(), "{target}/{name}: {result:?}");
            }
            count += 1;
        }
    }
    assert!(count >= 10, "only {count} seeds found");
}
