//! Rough edges a newcomer met (issue 35): the image memory check refuses only what will not
//! fit, sizes below a MiB read in KiB, a folder that is not a tile store and an unknown file
//! are refused naming every input, a complete tile store says so, and `render` without `-o`
//! says where it wrote.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh folder for the test `name`.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-edges-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `relief` with `args` in `dir`: its exit code and stderr. Two render threads, so that
/// the strip G-buffers' share of the image memory is the same on any machine.
fn relief(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_relief"));
    command.current_dir(dir).args(args).env("RAYON_NUM_THREADS", "2");
    let out: Output = command.output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// A small .npy DEM in `dir`.
fn dem(dir: &Path) -> &'static str {
    let values: Vec<f32> = (0..24 * 24).map(|i| (i % 24) as f32 * 0.5).collect();
    relief_io::write_npy_f32(&dir.join("dem.npy"), &[24, 24], &values).unwrap();
    "dem.npy"
}

#[test]
fn a_render_that_fits_in_memory_is_not_refused_and_one_that_does_not_is() {
    let dir = folder("memory");
    // 32768 x 32768 drawn strip by strip takes about 3.6 GiB: under 8G it passes the memory
    // check and fails on the missing input; under 3G it is refused before any reading.
    let big = ["render", "missing.npy", "--size", "32768x32768", "--aa", "off"];
    let (code, stderr) = relief(&dir, &[&big[..], &["--max-memory", "8G"][..]].concat());
    assert_eq!(code, Some(2));
    assert!(!stderr.contains("memory limit") && stderr.contains("missing.npy"), "{stderr}");
    let (code, stderr) = relief(&dir, &[&big[..], &["--max-memory", "3G"][..]].concat());
    assert_eq!(code, Some(2));
    assert!(
        stderr.contains("a 32768x32768 image needs") && stderr.contains("3072 MiB"),
        "{stderr}"
    );
    // --depth and --normals keep 16 bytes a pixel more: 20 GiB.
    let kept = ["--max-memory", "16G", "--depth", "d.npy", "--normals", "n.npy"];
    let (code, stderr) = relief(&dir, &[&big[..], &kept[..]].concat());
    assert_eq!(code, Some(2));
    assert!(stderr.contains("memory limit"), "{stderr}");
    // The adaptive anti-aliasing (the default) holds 22 bytes a pixel more: 25.6 GiB.
    let adaptive = ["render", "missing.npy", "--size", "32768x32768", "--max-memory", "8G"];
    let (code, stderr) = relief(&dir, &adaptive);
    assert_eq!(code, Some(2));
    assert!(stderr.contains("a 32768x32768 image needs 26224 MiB"), "{stderr}");
}

#[test]
fn an_mlhm_render_is_checked_for_what_it_holds() {
    // The MLHM renderer holds about 124 bytes a pixel (measured): 1000x1000 needs 122 MiB.
    let dir = folder("mlhm-memory");
    let big = ["render", "missing.mlhm", "--size", "1000x1000", "--max-memory"];
    let (code, stderr) = relief(&dir, &[&big[..], &["100M"][..]].concat());
    assert_eq!(code, Some(2));
    assert!(stderr.contains("memory limit"), "{stderr}");
    let (code, stderr) = relief(&dir, &[&big[..], &["200M"][..]].concat());
    assert_eq!(code, Some(2));
    assert!(!stderr.contains("memory limit") && stderr.contains("missing.mlhm"), "{stderr}");
}

#[test]
fn a_limit_under_a_mib_reads_in_kib() {
    let dir = folder("kib");
    let (code, stderr) = relief(&dir, &["render", "--size", "640x360", "--max-memory", "1K"]);
    assert_eq!(code, Some(2));
    assert!(stderr.contains("over the 1 KiB memory limit"), "{stderr}");
    assert!(!stderr.contains("0 MiB"), "{stderr}");
}

#[test]
fn a_folder_that_is_not_a_tile_store_or_an_unknown_file_is_refused_naming_every_input() {
    let dir = folder("inputs");
    std::fs::create_dir_all(dir.join("somedir")).unwrap();
    std::fs::write(dir.join("heights.xyz"), b"1 2 3").unwrap();
    for command in ["render", "view"] {
        for input in ["somedir", "heights.xyz"] {
            let (code, stderr) = relief(&dir, &[command, input]);
            assert_eq!(code, Some(2), "{command} {input}: {stderr}");
            for named in [".tif", ".npy", ".npz", ".json", ".mlhm", ".stacks", "tile store"] {
                assert!(stderr.contains(named), "{command} {input}: {named}: {stderr}");
            }
            assert!(stderr.contains(&format!("relief {command} takes")), "{stderr}");
        }
        let (_, stderr) = relief(&dir, &[command, "somedir"]);
        assert!(stderr.contains("not a tile store"), "{stderr}");
        let (code, stderr) = relief(&dir, &[command, "nosuch"]);
        assert_eq!(code, Some(2), "{stderr}");
        assert!(stderr.contains("nosuch: no such file or folder"), "{stderr}");
    }
}

#[test]
fn rerunning_tile_on_a_complete_store_says_there_is_nothing_to_do() {
    let dir = folder("tile");
    let dem = dem(&dir);
    let (code, stderr) = relief(&dir, &["tile", dem, "-o", "dem.store", "--tile", "16"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(!stderr.contains("complete"), "{stderr}");
    let (code, stderr) = relief(&dir, &["tile", dem, "-o", "dem.store", "--tile", "16"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stderr.contains("dem.store is complete") && stderr.contains("nothing to do"),
        "{stderr}"
    );
    assert!(!stderr.contains("MB/s") && !stderr.contains("interrupted"), "{stderr}");
}

#[test]
fn render_without_an_output_says_where_it_wrote() {
    let dir = folder("default-output");
    let dem = dem(&dir);
    let (code, stderr) = relief(&dir, &["render", dem, "--size", "32x18"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains("wrote relief.png (32x18"), "{stderr}");
    assert!(dir.join("relief.png").is_file());
}
