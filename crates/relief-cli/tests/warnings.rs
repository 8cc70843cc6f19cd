//! The warnings of scenes that render without an error but not as meant (issue 35): a camera inside
//! the terrain (a height field, an MLHM, material stacks), and a DEM read at the default spacing
//! whose heights dwarf its grid. Each is printed where it applies and nowhere else.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh folder for the test `name`.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-warnings-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `relief` with `args` in `dir`.
fn relief(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_relief")).current_dir(dir).args(args).output().unwrap()
}

/// Runs a command that must succeed; its stderr.
fn stderr_of(dir: &Path, args: &[&str]) -> String {
    let out = relief(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {stderr}");
    stderr
}

/// A `w x h` .npy DEM in `dir` whose sample (col, row) is `height(col, row)`.
fn npy(dir: &Path, name: &str, w: usize, h: usize, height: impl Fn(usize, usize) -> f32) -> String {
    let values: Vec<f32> =
        (0..h).flat_map(|r| (0..w).map(move |c| (c, r))).map(|(c, r)| height(c, r)).collect();
    relief_io::write_npy_f32(&dir.join(name), &[h, w], &values).unwrap();
    name.to_string()
}

const INSIDE: &str = "is inside the terrain";
const NEEDLE: &str = "renders as a needle";

#[test]
fn an_eye_under_the_surface_is_warned_of_with_the_height_there() {
    let dir = folder("eye");
    // A 32 x 32 plateau at height 20 (relief under the grid's width: no spacing warning).
    let dem = npy(&dir, "plateau.npy", 32, 32, |c, _| if c < 16 { 20.0 } else { 10.0 });
    let small = ["--size", "32x18", "-o", "out.png"];
    for how in [["--surface", "triangles"], ["--surface", "boxes"], ["--mode", "mesh"]] {
        let mut args = vec!["render", &dem, "--eye", "8,16,15", "--target", "30,16,5"];
        args.extend(how);
        args.extend(small);
        let stderr = stderr_of(&dir, &args);
        assert!(stderr.contains(INSIDE), "{how:?}: {stderr}");
        assert!(stderr.contains("(8, 16, 15)") && stderr.contains("height 20"), "{stderr}");
        assert!(stderr.contains("--eye"), "{stderr}");
        assert!(!stderr.contains(NEEDLE), "{stderr}");
    }
    // Above the surface, over the lower half, off the grid, the default view: no warning.
    for eye in ["8,16,25", "24,16,15", "-10,16,5"] {
        for mode in [&[][..], &["--mode", "mesh"][..]] {
            let mut args = vec!["render", &dem, "--eye", eye, "--target", "16,16,0"];
            args.extend(mode);
            args.extend(small);
            let stderr = stderr_of(&dir, &args);
            assert!(!stderr.contains(INSIDE), "{eye} {mode:?}: {stderr}");
        }
    }
    let mut args = vec!["render", &dem];
    args.extend(small);
    let stderr = stderr_of(&dir, &args);
    assert!(!stderr.contains(INSIDE) && !stderr.contains("warning"), "{stderr}");
}

#[test]
fn an_eye_inside_an_mlhm_solid_is_warned_of_and_one_in_a_cave_is_not() {
    let dir = folder("mlhm");
    stderr_of(&dir, &["generate", "mlhm", "--scene", "cave", "--size", "32", "-o", "cave.mlhm"]);
    let small = ["--size", "32x18", "-o", "out.png"];
    let inside = ["render", "cave.mlhm", "--eye", "128,128,2", "--target", "0,0,2"];
    let stderr = stderr_of(&dir, &[&inside[..], &small[..]].concat());
    assert!(stderr.contains(INSIDE), "{stderr}");
    let above = ["render", "cave.mlhm", "--eye", "128,128,200", "--target", "0,0,0"];
    let stderr = stderr_of(&dir, &[&above[..], &small[..]].concat());
    assert!(!stderr.contains(INSIDE), "{stderr}");
    let stderr = stderr_of(&dir, &[&["render", "cave.mlhm"][..], &small[..]].concat());
    assert!(!stderr.contains("warning"), "{stderr}");
}

#[test]
fn a_dem_taller_than_wide_at_the_default_spacing_names_spacing_and_z_scale() {
    let dir = folder("needle");
    // 20 x 20 samples rising 0 to 190: relief 190 over a grid 20 wide.
    let dem = npy(&dir, "needle.npy", 20, 20, |c, r| (c + r) as f32 * 5.0);
    let small = ["--size", "32x18", "-o", "out.png"];
    let stderr = stderr_of(&dir, &[&["render", &dem][..], &small[..]].concat());
    assert!(stderr.contains(NEEDLE), "{stderr}");
    assert!(stderr.contains("--spacing") && stderr.contains("--z-scale"), "{stderr}");
    assert!(stderr.contains("20 x 20") && stderr.contains("190"), "{stderr}");
    // A spacing given, heights scaled down, or the default terrain: no warning.
    for fix in [&["--spacing", "10"][..], &["--z-scale", "0.1"][..]] {
        let stderr = stderr_of(&dir, &[&["render", &dem][..], fix, &small[..]].concat());
        assert!(!stderr.contains(NEEDLE), "{fix:?}: {stderr}");
    }
    let stderr = stderr_of(&dir, &["render", "--fbm-size", "64", "--size", "32x18", "-o", "f.png"]);
    assert!(!stderr.contains("warning"), "{stderr}");
    // A gentle DEM at the default spacing: no warning.
    let gentle = npy(&dir, "gentle.npy", 20, 20, |c, _| c as f32);
    let stderr = stderr_of(&dir, &[&["render", &gentle][..], &small[..]].concat());
    assert!(!stderr.contains(NEEDLE), "{stderr}");
}
