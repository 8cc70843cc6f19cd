//! relief as a new user types it: every command of the README as written there, every option
//! of every `--help` driven at least once (negative numbers, every output extension,
//! conflicting outputs, options that do nothing, a top-down camera, out-of-range values), and
//! what relief writes read back by the real clients of its formats (GDAL through rasterio,
//! Pillow, NumPy). The tests that need a client (those, or Xvfb for `relief view`) are reported
//! ignored, with the reason, where it is missing (tests/common/clients.rs).

#[path = "as_typed/cases.rs"]
mod cases;
mod common;

use cases::{Expect, CASES};
use common::{clients, python, read_f32_npy, relief, scratch, shared_data, x_server};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

fn main() {
    clients::run(vec![
        clients::trial!(every_option_of_every_help_is_driven),
        clients::trial!(every_view_option_runs_on_a_virtual_x_server, Xvfb),
        clients::trial!(help_says_which_size_each_command_means),
        clients::trial!(negative_numbers_are_values_of_every_numeric_option),
        clients::trial!(a_top_down_camera_puts_north_at_the_top),
        clients::trial!(info_describes_mlhm_scenes),
        clients::trial_reading!(info_describes_the_real_mlhm_scene, "data/ngwm24-scene/scene.json"),
        clients::trial!(numbers_in_messages_are_readable),
        clients::trial!(the_bench_table_is_aligned),
        clients::trial!(outputs_are_read_back_by_relief),
        clients::trial!(outputs_are_read_back_by_gdal, Rasterio),
        clients::trial!(outputs_are_read_back_by_pillow, Pillow),
        clients::trial!(outputs_are_read_back_by_numpy, Numpy),
        clients::trial!(every_readme_command_runs_as_typed),
        clients::trial!(every_readme_view_command_runs_as_typed, Xvfb),
    ]);
}

/// The repository's root.
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Small inputs every case below may use, made once: `f.npy` (48², fBm), `f.tif`, `f.png`
/// (16-bit grey), `t.png` (an RGB picture, as a texture) and its depth `d.npy` (16x16),
/// `s.mlhm` (a carved MLHM scene), `g.stacks` (a generated stacks terrain), `st` (a tile
/// store of `f.tif`), `stt` (the same with `t.png` as its photo) and `p.json` (a camera path
/// of three keys).
fn inputs() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = scratch("inputs");
        std::fs::create_dir_all(&dir).unwrap();
        let p = |name: &str| dir.join(name).to_str().unwrap().to_string();
        for out in ["f.npy", "f.tif", "f.png"] {
            let run = relief(&["generate", "fbm", "--size", "48", "-o", &p(out)]);
            assert!(run.status.success(), "{out}: {}", stderr(&run));
        }
        let run = relief(&[
            "render",
            "--fbm-size",
            "32",
            "--size",
            "16x16",
            "-o",
            &p("t.png"),
            "--depth",
            &p("d.npy"),
        ]);
        assert!(run.status.success(), "{}", stderr(&run));
        let run =
            relief(&["generate", "mlhm", "--scene", "arches", "--size", "32", "-o", &p("s.mlhm")]);
        assert!(run.status.success(), "{}", stderr(&run));
        let stacks = ["generate", "stacks", "--width", "24", "--height", "16", "-o", &p("g.stacks")];
        let run = relief(&stacks);
        assert!(run.status.success(), "{}", stderr(&run));
        let run = relief(&["tile", &p("f.tif"), "-o", &p("st"), "--tile", "16"]);
        assert!(run.status.success(), "{}", stderr(&run));
        let textured = ["tile", &p("f.tif"), "-o", &p("stt"), "--tile", "16", "--texture", &p("t.png")];
        let run = relief(&textured);
        assert!(run.status.success(), "{}", stderr(&run));
        let key = |t: f64, x: f64| {
            format!(
                r#"{{"time_s": {t}, "eye": [{x}, -40, 80], "target": [24, 24, 0], "up": [0, 0, 1], "fov_deg": 45}}"#
            )
        };
        let keys = [key(0.0, -40.0), key(0.5, -20.0), key(1.0, 0.0)].join(", ");
        let path = format!(r#"{{"format": "relief-camera-path", "version": 1, "keys": [{keys}]}}"#);
        std::fs::write(dir.join("p.json"), path).unwrap();
        dir
    })
}

/// Runs `relief` with `args` in `dir`, on the X display `display` (none: without `DISPLAY`).
fn relief_with_display(args: &[&str], display: Option<&str>, dir: &Path) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_relief"));
    command.args(args).current_dir(dir);
    match display {
        Some(display) => command.env("DISPLAY", display),
        None => command.env_remove("DISPLAY"),
    };
    command.output().unwrap()
}

/// Runs `relief` with `line` split at spaces, `{in}` replaced by the inputs' folder and
/// `{out}` by a fresh scratch folder, and checks the outcome.
fn case(line: &str, expect: Expect) -> Output {
    let out_dir = scratch(&format!("case-{:x}", fnv(line)));
    std::fs::create_dir_all(&out_dir).unwrap();
    let args: Vec<String> = line
        .split_whitespace()
        .map(|a| {
            a.replace("{in}", inputs().to_str().unwrap())
                .replace("{out}", out_dir.to_str().unwrap())
        })
        .collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    // `relief view` opens a window: on a virtual X server of its own.
    let x = (args[0] == "view").then(x_server).flatten();
    let out = match &x {
        Some(x) => relief_with_display(&args, Some(&x.display), Path::new(".")),
        None => relief(&args),
    };
    let err = stderr(&out);
    assert!(!err.contains("panicked"), "{line}: {err}");
    match expect {
        Expect::Ok => assert!(out.status.success(), "{line}: {err}"),
        Expect::Refused(text) => {
            assert_eq!(out.status.code(), Some(2), "{line} should be refused: {err}");
            let error_lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error")).collect();
            assert_eq!(error_lines.len(), 1, "{line}: one error line: {err}");
            assert!(err.contains(text), "{line}: the error should say '{text}': {err}");
            assert!(!err.contains("unexpected argument"), "{line}: {err}");
        }
    }
    out
}

/// A stable hash of a case's text, to name its scratch folder.
fn fnv(text: &str) -> u64 {
    text.bytes().fold(0xcbf29ce484222325, |h, b| (h ^ u64::from(b)).wrapping_mul(0x100000001b3))
}

/// The long options a subcommand's `--help` lists.
fn options_in_help(command: &str) -> BTreeSet<String> {
    let mut args: Vec<&str> = command.split(' ').collect();
    args.push("--help");
    let out = relief(&args);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout).into_owned();
    // An option's line starts with it: `  -o, --output <OUTPUT>` or `      --north-up`.
    help.lines()
        .filter(|l| l.trim_start().starts_with('-'))
        .filter_map(|l| l.split_whitespace().find(|w| w.starts_with("--")))
        .map(|w| w.trim_end_matches(',').to_string())
        .filter(|o| {
            o[2..].chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
        })
        .filter(|o| o != "--help" && o != "--version")
        .collect()
}

fn every_option_of_every_help_is_driven() {
    help_cases(false);
}

/// `relief view`'s cases, on a virtual X server of their own.
fn every_view_option_runs_on_a_virtual_x_server() {
    help_cases(true);
}

/// Checks that the cases drive every option of every command's `--help`, and runs the cases
/// of `relief view` (`view`) or those of every other command.
fn help_cases(view: bool) {
    for (command, cases) in CASES {
        let driven: BTreeSet<String> = cases
            .iter()
            .flat_map(|(line, _)| line.split_whitespace())
            .filter(|w| w.starts_with("--"))
            .map(|w| w.split('=').next().unwrap().to_string())
            .collect();
        let listed = options_in_help(command);
        assert!(!listed.is_empty(), "{command} --help lists no options");
        let missing: Vec<&String> = listed.difference(&driven).collect();
        assert!(missing.is_empty(), "relief {command}: no case drives {missing:?}");
        if (*command == "view") != view {
            continue;
        }
        for (line, expect) in *cases {
            case(line, *expect);
        }
    }
}

fn help_says_which_size_each_command_means() {
    let help = |command: &str| {
        let mut args: Vec<&str> = command.split(' ').collect();
        args.push("--help");
        String::from_utf8_lossy(&relief(&args).stdout).into_owned()
    };
    assert!(help("render").contains("Image size WxH in pixels (not terrain samples"));
    assert!(help("bench").contains("Terrain samples per side of the fBm terrain"));
    assert!(help("bench").contains("not image pixels"));
    assert!(help("generate fbm").contains("Terrain samples per side"));
    assert!(help("generate mlhm").contains("Cells per side"));
}

fn negative_numbers_are_values_of_every_numeric_option() {
    // Each numeric option given a negative value: clap must take it as the value (whatever
    // the option then makes of it), never as an unknown flag.
    let numeric = [
        "render --eye -1,-2,-3 --target -4,-5,-6",
        "render --target -1,0,0 --eye 1,1,1",
        "render --eye 1,1,1 --target 0,0,0 --up -1,0,0",
        "render --spacing -5",
        "render --z-scale -1",
        "render --fov -1",
        "render --view -45,-30",
        "render --ortho --ortho-height -1",
        "render --exposure -1",
        "render --sun -1,-1",
        "render --sigma -1",
        "render --phi-max -1",
        "render --safety-reach -1",
        "render --fbm-size -1",
        "render --seed -1",
        "render --max-memory -1",
        "generate fbm --size -1",
        "generate fbm --seed -1",
        "generate mlhm --scene cave --size -1",
        "generate mlhm --scene cave --max-layers -1",
        "bench --size -1",
        "bench --seed -1",
        "bench --repeat -1",
        "view --frames -1",
        "view --frame-budget -1",
        "simulate in.mlhm --steps 1 --render-every -1",
        "simulate in.mlhm --steps 1 --view -45,-30",
        "shade no.tif --sun -45,-30",
        "shade no.tif --sun-radius -1",
        "shade no.tif --sun-rays -1",
        "shade no.tif --azimuths -1",
        "shade no.tif --observer-height -1",
        "shade no.tif --radius -1",
        "compare a.npy b.npy --diagonal -1",
        "compare a.npy b.npy --cell -1",
        "compare a.npy b.npy --terrain t.tif --spacing -1",
        "compare a.npy b.npy --terrain t.tif --z-scale -1",
    ];
    for line in numeric {
        let out_dir = scratch("negative");
        std::fs::create_dir_all(&out_dir).unwrap();
        let mut args: Vec<String> = line.split(' ').map(String::from).collect();
        args.extend(
            ["--size".into(), "8x8".into()].into_iter().filter(|_| line.starts_with("render")),
        );
        args.extend(
            ["-o".into(), out_dir.join("x.png").to_str().unwrap().into()]
                .into_iter()
                .filter(|_| !["bench", "view", "compare"].iter().any(|c| line.starts_with(c))),
        );
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = relief(&args);
        let err = stderr(&out);
        assert!(!err.contains("unexpected argument"), "{line}: {err}");
        assert!(!err.contains("panicked"), "{line}: {err}");
    }
}

fn a_top_down_camera_puts_north_at_the_top() {
    // A ramp rising to the north, seen from straight above: the top rows (north) are nearer.
    let ramp = scratch("ramp.npy");
    let heights: Vec<f32> = (0..32 * 32).map(|k| (k / 32) as f32).collect();
    relief_io::write_npy_f32(&ramp, &[32, 32], &heights).unwrap();
    let depth = scratch("ramp-depth.npy");
    let out = relief(&[
        "render",
        ramp.to_str().unwrap(),
        "--eye",
        "16,16,100",
        "--target",
        "16,16,0",
        "--size",
        "9x9",
        "--fov",
        "20",
        "-o",
        scratch("ramp.png").to_str().unwrap(),
        "--depth",
        depth.to_str().unwrap(),
    ]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("parallel to the view") && err.contains("north"), "{err}");
    let (shape, d) = read_f32_npy(&depth);
    assert_eq!(shape, [9, 9]);
    let (top, bottom) = (d[4], d[8 * 9 + 4]);
    assert!(top < bottom, "the north (top) row is nearer: {top} vs {bottom}");
    let (left, right) = (d[4 * 9], d[4 * 9 + 8]);
    assert!((left - right).abs() < 1e-3, "east-west is level: {left} vs {right}");
}

fn info_describes_mlhm_scenes() {
    let out = case("info {in}/s.mlhm", Expect::Ok);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    for key in ["32 x 32 cells of 8 m", "cells by columns", "bedrock tops", "water:", "to render:"]
    {
        assert!(text.contains(key), "missing '{key}':\n{text}");
    }
}

fn info_describes_the_real_mlhm_scene() {
    let scene = shared_data("data/ngwm24-scene/scene.json").unwrap();
    let out = relief(&["info", scene.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(text.contains("256 x 256 cells") && text.contains("with simulation state"), "{text}");
}

fn numbers_in_messages_are_readable() {
    for (line, range) in [
        ("render {in}/f.npy --spacing 1e300 -o {out}/a.png", "1e-6..10000000"),
        ("render --eye 1e300,0,0 --target 0,0,0 -o {out}/a.png", "farther than 1e9 m"),
        ("render {in}/s.mlhm --mode smooth --sigma 1e-300 -o {out}/a.png", "0.125..64 m"),
    ] {
        let out = case(line, Expect::Refused(range));
        assert!(stderr(&out).len() < 300, "{line}: {}", stderr(&out));
    }
}

fn the_bench_table_is_aligned() {
    let out =
        relief(&["bench", "--size", "24", "--res", "16x9", "--repeat", "1", "--views", "flight"]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{}", stderr(&out));
    let lines: Vec<&str> = text.lines().skip(1).collect();
    let header = lines[0];
    assert!(lines.len() == 5, "{text}");
    for row in &lines[1..] {
        assert_eq!(row.len(), header.len(), "row and header differ in width:\n{header}\n{row}");
        for column in ["surface", "tracer"] {
            let at = header.find(column).unwrap();
            assert!(
                row.as_bytes()[at - 1] == b' ' && row.as_bytes()[at] != b' ',
                "{column}:\n{header}\n{row}"
            );
        }
    }
}

/// The outputs the clients read back, written once: `f.tif`, `f.png`, `f.asc`, `f.npy` and
/// `N36W085.hgt` by `relief generate`, `a.jpg`, `a.jpeg` and the depth `d.npy` by `relief
/// render`.
fn outputs() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = scratch("clients");
        std::fs::create_dir_all(&dir).unwrap();
        let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
        for ext in ["tif", "png", "asc", "npy"] {
            case(&format!("generate fbm --size 40 -o {}", path(&format!("f.{ext}"))), Expect::Ok);
        }
        case(&format!("generate fbm --size 1201 -o {}", path("N36W085.hgt")), Expect::Ok);
        case(
            &format!(
                "render --fbm-size 24 --size 20x10 -o {} --depth {}",
                path("a.jpg"),
                path("d.npy")
            ),
            Expect::Ok,
        );
        case(&format!("render --fbm-size 24 --size 20x10 -o {}", path("a.jpeg")), Expect::Ok);
        dir
    })
}

fn outputs_are_read_back_by_relief() {
    let dir = outputs();
    // relief reads each back as the format its name says.
    for (name, format) in [
        ("f.tif", "GeoTIFF"),
        ("f.png", "PNG"),
        ("f.asc", "ESRI"),
        ("f.npy", "NumPy"),
        ("N36W085.hgt", "SRTM"),
    ] {
        let out = relief(&["info", dir.join(name).to_str().unwrap()]);
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(out.status.success() && text.contains(format), "{name}: {text}{}", stderr(&out));
    }
    let bytes = std::fs::read(dir.join("a.jpg")).unwrap();
    assert_eq!(&bytes[..3], &[0xFF, 0xD8, 0xFF], "a JPEG starts with SOI");
}

fn outputs_are_read_back_by_gdal() {
    let shapes = python(
        "rasterio",
        &format!(
            "import rasterio\nfor n in ['f.tif', 'f.asc', 'f.png', 'N36W085.hgt']:\n    \
             r = rasterio.open('{0}/' + n)\n    print(n, r.driver, r.width, r.height, r.dtypes[0])",
            outputs().display()
        ),
    )
    .unwrap();
    for expected in [
        "f.tif GTiff 40 40 float32",
        "f.asc AAIGrid 40 40",
        "f.png PNG 40 40 uint16",
        "N36W085.hgt SRTMHGT 1201 1201 int16",
    ] {
        assert!(shapes.contains(expected), "GDAL read {shapes}, expected {expected}");
    }
}

fn outputs_are_read_back_by_pillow() {
    let read = python(
        "PIL",
        &format!("from PIL import Image\nfor n in ['a.jpg', 'a.jpeg']:\n    i = Image.open('{}/' + n)\n    print(i.format, i.size)", outputs().display()),
    );
    assert_eq!(read.unwrap(), "JPEG (20, 10)\nJPEG (20, 10)");
}

fn outputs_are_read_back_by_numpy() {
    let depth = outputs().join("d.npy");
    let shape =
        python("numpy", &format!("import numpy\nprint(numpy.load('{}').shape)", depth.display()));
    assert_eq!(shape.unwrap(), "(10, 20)");
}

fn every_readme_command_runs_as_typed() {
    readme_commands(false);
}

/// The README's `relief view` commands, on a virtual X server.
fn every_readme_view_command_runs_as_typed() {
    readme_commands(true);
}

/// Runs the README's `relief view` commands (`view`) or all its others.
fn readme_commands(view: bool) {
    // The README's `cargo run --release -- ...` lines, continuation lines joined, run in a
    // scratch folder that sees the repository's crates/ and data/ as the README's paths do.
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let mut commands = Vec::new();
    let mut pending = String::new();
    for line in readme.lines() {
        let line = line.split(" #").next().unwrap().trim();
        if pending.is_empty() && !line.starts_with("cargo run --release -- ") {
            continue;
        }
        pending.push_str(line.trim_end_matches('\\'));
        pending.push(' ');
        if !line.ends_with('\\') {
            commands.push(pending.trim_start_matches("cargo run --release -- ").trim().to_string());
            pending.clear();
        }
    }
    assert!(commands.len() >= 8, "README commands: {commands:?}");
    let dir = scratch("readme");
    std::fs::create_dir_all(&dir).unwrap();
    for link in ["crates", "data"] {
        let _ = std::fs::remove_file(dir.join(link));
        std::os::unix::fs::symlink(repo().join(link), dir.join(link)).unwrap();
    }
    for command in &commands {
        let mut args: Vec<&str> = command.split_whitespace().collect();
        if (args[0] == "view") != view {
            continue;
        }
        // The full benchmark (4096², 1920x1080, naive and mipmap) takes minutes: as typed,
        // but on a small terrain and image.
        if args == ["bench"] {
            args.extend(["--size", "128", "--res", "64x36", "--repeat", "1"]);
        }
        // The viewer runs until its window is closed: as typed, on a virtual X server, for a
        // few frames.
        let x = if args[0] == "view" {
            let x = x_server().expect("Xvfb starts");
            if !args.contains(&"--frames") {
                args.extend(["--frames", "3"]);
            }
            Some(x)
        } else {
            None
        };
        let out = relief_with_display(&args, x.as_ref().map(|x| x.display.as_str()), &dir);
        assert!(out.status.success(), "relief {command}: {}", stderr(&out));
    }
}
