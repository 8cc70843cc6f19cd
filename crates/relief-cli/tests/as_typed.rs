//! relief as a new user types it: every command of the README as written there, every option
//! of every `--help` driven at least once (negative numbers, every output extension,
//! conflicting outputs, options that do nothing, a top-down camera, out-of-range values), and
//! what relief writes read back by the real clients of its formats (GDAL through rasterio,
//! Pillow, NumPy). The tests that need a client (those, or Xvfb for `relief view`) are reported
//! ignored, with the reason, where it is missing (tests/common/clients.rs).

mod common;

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

/// What a case must do.
#[derive(Debug, Clone, Copy)]
enum Expect {
    /// Exit 0.
    Ok,
    /// Exit 2 with one line of error on stderr that holds this text.
    Refused(&'static str),
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

/// Every subcommand and the cases that drive its options. Each option its `--help` lists
/// must appear in at least one case (checked by `every_option_of_every_help_is_driven`).
const CASES: &[(&str, &[(&str, Expect)])] = &[
    (
        "render",
        &[
            ("render --fbm-size 24 --seed 3 --size 32x18 --output {out}/a.png", Expect::Ok),
            ("render --eye -100,-150,420 --target 0,0,0 --fbm-size 24 --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render --eye=-100,-150,420 --target=-5,0,0 --up 0,0,1 --fov 30 --fbm-size 24 --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render --view -45,30 --fbm-size 24 --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render --fbm-size 24 --size 16x9 -o {out}/a.png --png-compression high", Expect::Ok),
            ("render --fbm-size 24 --size 16x9 -o {out}/a.jpg --png-compression high", Expect::Refused("--png-compression: -o")),
            ("render --fbm-size 24 --size 16x9 -o {out}/a.png --png-compression=-1", Expect::Refused("unknown PNG compression '-1'")),
            ("render --view 0,90 --ortho --fbm-size 24 --size 16x9 -o {out}/a.png --depth {out}/d.npy", Expect::Ok),
            ("render {in}/s.mlhm --view 30,45,500 --target=10,10,0 --ortho --ortho-height 40 --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render --eye=-100,-150,420 --target 0,0,0 --ortho --fbm-size 24 --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render --ortho --fov 30 -o {out}/a.png", Expect::Refused("--fov applies to perspective cameras only, not to --ortho")),
            ("render --ortho-height 10 -o {out}/a.png", Expect::Refused("--ortho-height applies to --ortho only")),
            ("render --ortho --ortho-height 0 -o {out}/a.png", Expect::Refused("more than 0")),
            ("render --view 30,0 -o {out}/a.png", Expect::Refused("more than 0 and at most 90")),
            ("render --view 30,45 --eye 1,2,3 --target 0,0,0 -o {out}/a.png", Expect::Refused("cannot be used with")),
            ("render {in}/f.npy --spacing -5 -o {out}/a.png", Expect::Refused("must be positive")),
            ("render {in}/f.npy --spacing 2,3 --north-up --z-scale 3 --size 16x9 -o {out}/a.jpg", Expect::Ok),
            ("render {in}/f.npy --z-scale -3 -o {out}/a.png", Expect::Refused("outside")),
            ("render {in}/f.npy --exposure -1 -o {out}/a.png", Expect::Refused("outside 0.0001..10000")),
            ("render {in}/f.npy --exposure 2 --sun -45,-10 --no-shadows --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.npy --sun 10,95 -o {out}/a.png", Expect::Refused("-90..90")),
            ("render {in}/f.npy --fov 0 -o {out}/a.png", Expect::Refused("field of view")),
            ("render {in}/f.npy --fov 180 -o {out}/a.png", Expect::Refused("field of view")),
            ("render {in}/f.npy --surface boxes --tracer naive --size 16x9 -o {out}/a.png --depth {out}/d.npy --normals {out}/n.npy", Expect::Ok),
            ("render {in}/f.npy --tracer safety --safety cyl_ext+cone_ext --phi-max -5 --no-shadows --isotropic --positive --linear-surface --safety-reach 16 --no-cache --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.npy --tracer safety --cache-dir {out} --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.npy --tracer safety --safety-reach 5000 -o {out}/a.png", Expect::Refused("between 1 and 1024")),
            ("render {in}/f.npy --phi-max -45 -o {out}/a.png", Expect::Refused("--phi-max applies to the safety tracer only")),
            ("render {in}/f.npy --no-cache -o {out}/a.png", Expect::Refused("--no-cache applies to the safety tracer only")),
            ("render {in}/f.npy --seed 3 -o {out}/a.png", Expect::Refused("--seed applies to the default fBm terrain only")),
            ("render {in}/f.npy --fbm-size 64 -o {out}/a.png", Expect::Refused("--fbm-size applies to the default fBm terrain only")),
            ("render --voids hole -o {out}/a.png", Expect::Refused("--voids applies to input files only")),
            ("render {in}/f.tif --array heights -o {out}/a.png", Expect::Refused("--array applies to NumPy archives (.npz) only")),
            ("render {in}/f.tif --png-encoding terrain-rgb -o {out}/a.png", Expect::Refused("--png-encoding applies to PNG input (.png) only")),
            ("render {in}/f.png --png-encoding grey --voids fill --max-memory 1G --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.tif --z-unit us-ft --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.tif --z-unit yards -o {out}/a.png", Expect::Refused("unknown unit 'yards'")),
            ("render {in}/f.npy --tracer hybrid --cell 8 --threshold 2 --k 1.5 --lop 3 --far lop --show-lop --size 16x9 -o {out}/a.png --stats {out}/s.json", Expect::Ok),
            ("render {in}/f.npy --tracer hybrid --far exact --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.npy --tracer hybrid --cell 1 -o {out}/a.png", Expect::Refused("between 2 and 4096")),
            ("render {in}/f.npy --tracer hybrid --threshold -3 -o {out}/a.png", Expect::Refused("above 0")),
            ("render {in}/f.npy --tracer hybrid --k 0 -o {out}/a.png", Expect::Refused("above 0")),
            ("render {in}/f.npy --tracer hybrid --lop 0 -o {out}/a.png", Expect::Refused("between 2 and 10")),
            ("render {in}/f.npy --tracer hybrid --far fast -o {out}/a.png", Expect::Refused("expected lop or exact")),
            ("render {in}/f.npy --cell 8 -o {out}/a.png", Expect::Refused("--cell applies to --tracer hybrid only")),
            ("render {in}/s.mlhm --show-lop -o {out}/a.png", Expect::Refused("--show-lop applies to height fields (--tracer hybrid) only")),
            ("render {in}/f.tif --texture {in}/t.png --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.tif --mode smooth -o {out}/a.png", Expect::Refused("--mode applies to MLHM scenes")),
            ("render {in}/s.mlhm --texture {in}/t.png -o {out}/a.png", Expect::Refused("--texture")),
            ("render {in}/s.mlhm --mode smooth --sigma 1 --preset low --no-ao --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/s.mlhm --tracer hierarchy --backtrack miss --hierarchy-bounds f16 --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/s.mlhm --mode smooth --sigma 1e-6 -o {out}/a.png", Expect::Refused("1/64 of a cell to 8 cells")),
            ("render {in}/s.mlhm --sigma 1 -o {out}/a.png", Expect::Refused("--sigma applies to --mode smooth only")),
            ("render {in}/s.mlhm --phi-max -45 -o {out}/a.png", Expect::Refused("--phi-max applies to the safety tracer")),
            ("render {in}/f.npy -o {out}/a.bmp", Expect::Refused(".png or .jpg")),
            ("render {in}/f.npy -o {out}/y.png --depth {out}/y.png", Expect::Refused("must end in .npy")),
            ("render {in}/f.npy -o {out}/y.png --depth {out}/d.npy --normals {out}/./d.npy", Expect::Refused("--depth and --normals both write")),
            ("render {in}/f.png -o {in}/f.png", Expect::Refused("would overwrite the input")),
            ("render {in}/f.npy --size 0x10 -o {out}/a.png", Expect::Refused("between 1 and 32768")),
            ("render {in}/f.npy --size 16x9 -o {out}/a.png --stats {out}/s.json", Expect::Ok),
            ("render {in}/s.mlhm --size 16x9 -o {out}/a.png --stats {out}/s.json", Expect::Ok),
            ("render {in}/f.npy -o {out}/a.png --stats {out}/s.txt", Expect::Refused("the statistics are written as .json")),
            ("render {in}/st --max-error-px 1 --cache-mb 16 --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.tif --cache-mb 16 -o {out}/a.png", Expect::Refused("--cache-mb applies to tile stores")),
            ("render {in}/stt --texture-filter bilinear --texture-cache-mb 16 --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/st --texture-filter anisotropic -o {out}/a.png", Expect::Refused("--texture-filter applies to textured tile stores")),
            ("render {in}/f.tif --texture-cache-mb 16 -o {out}/a.png", Expect::Refused("--texture-cache-mb applies to tile stores")),
            ("render {in}/s.mlhm --mode mesh --tau 4 --sigma 8 --voxel-height 4 --size 16x9 -o {out}/a.png --depth {out}/d.npy --stats {out}/s.json", Expect::Ok),
            ("render {in}/f.npy --mode mesh --size 16x9 -o {out}/a.png", Expect::Ok),
            ("render {in}/f.npy --tau 4 -o {out}/a.png", Expect::Refused("--tau applies to --mode mesh only")),
            ("render {in}/f.npy --voxel-height 1 -o {out}/a.png", Expect::Refused("--voxel-height applies to --mode mesh only")),
            ("render {in}/f.npy --mode mesh --tau 0 -o {out}/a.png", Expect::Refused("outside 0.01..10000")),
            ("render {in}/f.npy --mode mesh --tracer naive -o {out}/a.png", Expect::Refused("--tracer applies to the ray-cast renderers only")),
        ],
    ),
    (
        "compare",
        &[
            ("compare {in}/d.npy {in}/d.npy", Expect::Ok),
            ("compare {in}/d.npy {in}/d.npy --json --diagonal 100 --cell 2 --max-memory 1G", Expect::Ok),
            ("compare {in}/d.npy {in}/d.npy --terrain {in}/f.tif --spacing 2,3 --z-scale 3", Expect::Ok),
            ("compare {in}/d.npy {in}/d.npy --terrain {in}/s.mlhm --json", Expect::Ok),
            ("compare {in}/d.npy {in}/d.npy --terrain {in}/s.mlhm --spacing 2", Expect::Refused("--spacing applies to height files only")),
            ("compare {in}/d.npy {in}/d.npy --z-scale 2", Expect::Refused("--terrain")),
            ("compare {in}/d.npy {in}/f.npy", Expect::Refused("different shapes")),
            ("compare {in}/d.npy {in}/t.png", Expect::Refused("not a .npy file")),
            ("compare {in}/d.npy {out}/missing.npy", Expect::Refused("missing.npy")),
            ("compare {in}/d.npy {in}/d.npy --diagonal 0", Expect::Refused("positive length")),
            ("compare {in}/d.npy {in}/d.npy --cell -1", Expect::Refused("positive length")),
        ],
    ),
    (
        "shade",
        &[
            ("shade {in}/f.tif -o {out}/s.tif --layers shadow,sky,hillshade,combined --sun 315,45 --sun -45,30 --sun-radius 0.5 --sun-rays 4 --sky-rays 8 --surface boxes --stats {out}/s.json", Expect::Ok),
            ("shade {in}/f.npy --spacing 2,3 --z-scale 3 --voids hole --max-memory 1G --output {out}/s.png --layers hillshade", Expect::Ok),
            ("shade {in}/f.png --png-encoding grey -o {out}/s.tif --layers sky --sky-rays 4", Expect::Ok),
            ("shade {in}/f.tif --z-unit ft -o {out}/s.tif --layers hillshade", Expect::Ok),
            ("shade {in}/f.tif --array heights -o {out}/s.tif", Expect::Refused("--array applies to NumPy archives (.npz) only")),
            ("shade {in}/f.tif -o {out}/s.tif --layers shadows", Expect::Refused("unknown layer 'shadows'")),
            ("shade {in}/f.tif -o {out}/s.png --layers shadow,sky", Expect::Refused("a PNG holds one layer")),
            ("shade {in}/f.tif -o {out}/s.jpg", Expect::Refused(".tif (GeoTIFF) or .png")),
            ("shade {in}/f.tif -o {in}/f.tif", Expect::Refused("f.tif")),
            ("shade {in}/f.tif -o {out}/s.tif --layers shadow --sky-rays 8", Expect::Refused("--sky-rays applies to the sky and combined layers only")),
            ("shade {in}/f.tif -o {out}/s.tif --sun-rays 8", Expect::Refused("--sun-rays applies to a sun with --sun-radius above 0 only")),
            ("shade {in}/f.tif -o {out}/s.tif --layers sky --sun 10,10", Expect::Refused("--sun applies to")),
            ("shade {in}/f.tif -o {out}/s.tif --layers hillshade --sun-radius 1", Expect::Refused("--sun-radius applies to")),
            ("shade {in}/f.tif -o {out}/s.tif --sun 10,0", Expect::Refused("sun elevation")),
            ("shade {in}/f.tif -o {out}/s.tif --sky-rays 0", Expect::Refused("between 1 and 4096")),
            ("shade {in}/s.mlhm -o {out}/s.tif", Expect::Refused("MLHM")),
            ("shade {in}/f.tif -o {out}/s.tif --stats {out}/s.txt", Expect::Refused("--stats")),
        ],
    ),
    (
        "view",
        &[
            ("view --fbm-size 24 --seed 3 --size 32x18 --frames 2 --screenshot {out}/a.png --stats {out}/s.json --output-dir {out} --frame-budget 20 --script 2:W+Left,1:!P", Expect::Ok),
            ("view --eye=-100,-150,420 --target=-5,0,0 --up 0,0,1 --fov 30 --fbm-size 24 --size 16x9 --frames 1 --sun -45,-10 --no-shadows --exposure 2", Expect::Ok),
            ("view {in}/f.npy --spacing 2,3 --north-up --z-scale 3 --surface boxes --tracer naive --size 16x9 --frames 1", Expect::Ok),
            ("view {in}/f.npy --tracer safety --safety cyl_ext+cone_ext --phi-max -5 --no-shadows --isotropic --positive --linear-surface --safety-reach 16 --no-cache --size 16x9 --frames 1", Expect::Ok),
            ("view {in}/f.npy --tracer safety --cache-dir {out} --size 16x9 --frames 1", Expect::Ok),
            ("view {in}/f.png --png-encoding grey --voids fill --max-memory 1G --texture {in}/t.png --size 16x9 --frames 1", Expect::Ok),
            ("view {in}/f.tif --z-unit m --size 16x9 --frames 1", Expect::Ok),
            ("view {in}/s.mlhm --mode smooth --sigma 1 --preset low --no-ao --size 16x9 --frames 1", Expect::Ok),
            ("view {in}/s.mlhm --tracer hierarchy --backtrack miss --hierarchy-bounds f16 --size 16x9 --frames 1", Expect::Ok),
            ("view --view -45,30 --fbm-size 24 --size 16x9 --frames 1", Expect::Ok),
            ("view --ortho --ortho-height 10", Expect::Refused("--ortho applies to relief render only, not to relief view")),
            ("view {in}/f.tif --array heights", Expect::Refused("--array applies to NumPy archives (.npz) only")),
            ("view {in}/s.mlhm --texture {in}/t.png", Expect::Refused("--texture")),
            ("view {in}/f.npy --phi-max -45", Expect::Refused("--phi-max applies to the safety tracer only")),
            ("view --screenshot {out}/a.png", Expect::Refused("--frames")),
            ("view --frames 2 --screenshot {out}/a.jpg", Expect::Refused("written as .png")),
            ("view --frames 2 --stats {out}/s.txt", Expect::Refused("written as .json")),
            ("view --frames 0", Expect::Refused("between 1 and 100000")),
            ("view --frames 2 --script 3:W+Nope", Expect::Refused("unknown key 'Nope'")),
            ("view --frame-budget 1", Expect::Refused("between 5 and 1000")),
            ("view --output-dir {out}/new/dir --frames 1 --size 16x9 --fbm-size 24", Expect::Ok),
            ("view --output-dir {in}/f.tif", Expect::Refused("not a folder")),
            ("view {in}/stt --max-error-px 1 --cache-mb 16 --texture-filter bilinear --texture-cache-mb 16 --size 16x9 --frames 1", Expect::Ok),
            ("view {in}/f.tif --cache-mb 16", Expect::Refused("--cache-mb applies to tile stores")),
            ("view {in}/f.png --frames 1 --screenshot {in}/f.png", Expect::Refused("would overwrite the input")),
            ("view {in}/s.mlhm --mode mesh --tau 6 --voxel-height 4 --size 16x9 --frames 1", Expect::Ok),
            ("view {in}/f.npy --tau 4", Expect::Refused("--tau applies to --mode mesh only")),
        ],
    ),
    (
        "generate fbm",
        &[
            ("generate fbm --size 32 --seed 7 --output {out}/f.npy", Expect::Ok),
            ("generate fbm --size 32 -o {out}/f.tif", Expect::Ok),
            ("generate fbm --size 32 -o {out}/f.png", Expect::Ok),
            ("generate fbm --size 32 -o {out}/f.asc", Expect::Ok),
            ("generate fbm --size 32 -o {out}/f.hgt", Expect::Refused("1201 x 1201 or 3601 x 3601")),
            ("generate fbm --size 32 -o {out}/f.jpg", Expect::Refused("a height file is written as")),
            ("generate fbm --size -32 -o {out}/f.npy", Expect::Refused("between 1 and 65536")),
            ("generate fbm --seed -1 -o {out}/f.npy", Expect::Refused("seed '-1'")),
        ],
    ),
    (
        "generate mlhm",
        &[
            ("generate mlhm --scene rivers-rain --size 16 --seed 5 --max-layers 2 --half --max-memory 1G -o {out}/s.mlhm", Expect::Ok),
            ("generate mlhm --scene cave --size 16 --output {out}/s.json", Expect::Ok),
            ("generate mlhm --scene arches --size 16 --seed 5 -o {out}/s.mlhm", Expect::Refused("--seed applies to rivers-rain only")),
            ("generate mlhm --scene arches --size 16 --max-layers 0 -o {out}/s.mlhm", Expect::Refused("between 1 and 127")),
            ("generate mlhm --scene arches --size 16 -o {out}/s.npy", Expect::Refused(".mlhm")),
        ],
    ),
    (
        "generate stacks",
        &[
            ("generate stacks --width 24 --height 16 --seed 4 --spacing 1.5 --max-height 40 --max-memory 1G -o {out}/t.stacks", Expect::Ok),
            ("generate stacks --width 24 --height 16 --output {out}/t.npy", Expect::Refused(".stacks")),
            ("generate stacks --width 0 --height 16 -o {out}/t.stacks", Expect::Refused("between 1 and 65536")),
        ],
    ),
    (
        "mesh",
        &[
            ("mesh {in}/s.mlhm --lod 0 -o {out}/m.glb --stats {out}/s.json", Expect::Ok),
            ("mesh {in}/g.stacks --lod 1 -o {out}/m.glb", Expect::Ok),
            ("mesh {in}/f.npy --spacing 2,3 --z-scale 3 --north-up --voxel-height 0.5 --sigma 2 --lod 1 --output {out}/m.obj", Expect::Ok),
            ("mesh --fbm-size 24 --seed 3 --eye=-40,-30,60 --target 12,12,0 --up 0,0,1 --fov 40 --size 64x36 --tau 4 -o {out}/m.ply", Expect::Ok),
            ("mesh {in}/s.mlhm --view 45,30 --lod auto -o {out}/m.glb", Expect::Ok),
            ("mesh {in}/s.mlhm --view 0,90 --ortho --ortho-height 100 -o {out}/m.glb", Expect::Ok),
            ("mesh {in}/f.png --png-encoding grey --voids fill --max-memory 1G -o {out}/m.glb", Expect::Ok),
            ("mesh {in}/f.tif --z-unit ft -o {out}/m.glb", Expect::Ok),
            ("mesh {in}/f.tif --array heights -o {out}/m.glb", Expect::Refused("--array applies to NumPy archives (.npz) only")),
            ("mesh {in}/s.mlhm --lod 99 -o {out}/m.glb", Expect::Refused("level of detail 99")),
            ("mesh {in}/s.mlhm -o {out}/m.stl", Expect::Refused(".glb")),
            ("mesh {in}/s.mlhm --lod 0 --tau 3 -o {out}/m.glb", Expect::Refused("--tau applies to --lod auto")),
            ("mesh {in}/s.mlhm --tracer naive -o {out}/m.glb", Expect::Refused("--tracer applies to the ray-cast renderers only, not to relief mesh")),
            ("mesh {in}/s.mlhm --mode boxes -o {out}/m.glb", Expect::Refused("--mode applies to relief render only")),
        ],
    ),
    (
        "info",
        &[
            ("info {in}/f.tif", Expect::Ok),
            ("info {in}/f.png --png-encoding terrarium --max-memory 1G", Expect::Refused("Terrarium heights need 8-bit RGB")),
            ("info {in}/f.tif --z-unit us-ft", Expect::Ok),
            ("info {in}/s.mlhm", Expect::Ok),
            ("info {in}/g.stacks", Expect::Ok),
            ("info {in}/f.tif --voids hole", Expect::Refused("--voids applies to render and convert only")),
            ("info {in}/f.tif --array a", Expect::Refused("--array applies to NumPy archives")),
        ],
    ),
    (
        "convert",
        &[
            ("convert {in}/f.tif {out}/f.asc --voids fill --max-memory 1G", Expect::Ok),
            ("convert {in}/f.png {out}/f.npy --png-encoding grey", Expect::Ok),
            ("convert {in}/f.tif {out}/f.tif --z-unit ft", Expect::Ok),
            ("convert {in}/s.mlhm {out}/s.json", Expect::Ok),
            ("convert {in}/f.tif {in}/f.tif", Expect::Refused("would overwrite the input")),
            ("convert {in}/f.tif {out}/f.jpg", Expect::Refused("a height file is written as")),
            ("convert {in}/f.tif {out}/f.npy --array a", Expect::Refused("--array applies to NumPy archives")),
            ("convert {in}/s.mlhm {out}/s.json --voids fill", Expect::Refused("--voids applies to height files only")),
        ],
    ),
    (
        "bench",
        &[
            ("bench --size 24 --res 16x9 --seed 2 --tracers mipmap --surfaces boxes --views flight --repeat 1 --simd portable --json --depth-dir {out}", Expect::Ok),
            ("bench --size 24 --res 16x9 --tracers naive,mipmap --surfaces boxes --views flight --repeat 1 --single-rays", Expect::Ok),
            ("bench --size 24 --res 16x9 --tracers mipmap --views flight --repeat 1 --shadow-sweep", Expect::Ok),
            ("bench --size 24 --simd avx2 --single-rays", Expect::Refused("--simd applies to ray packets only, not to --single-rays")),
            ("bench --size 24 --simd portable --tracers naive", Expect::Refused("--simd applies to the mipmap tracer only")),
            ("bench --input {in}/f.npy --res 16x9 --tracers cyl_all --safety cyl_all --phi-max -30 --isotropic --positive --linear-surface --safety-reach 8 --cache-dir {out} --no-cache --surfaces triangles --views cover --repeat 1", Expect::Ok),
            ("bench --input {in}/f.npy --size 64", Expect::Refused("--size applies to the generated fBm terrain only")),
            ("bench --size 24 --phi-max -30 --tracers mipmap", Expect::Refused("--phi-max applies to the safety tracers only")),
            ("bench --size 24 --repeat 0", Expect::Refused("between 1 and 1000")),
            ("bench --size 24 --res 16x9 --tracers mipmap,hybrid --cell 5 --threshold 3 --k 1.1 --lop 2 --far exact --views flight --repeat 1", Expect::Ok),
            ("bench --size 24 --res 16x9 --dynamic waves --frames 2 --surfaces boxes --views top-down", Expect::Ok),
            ("bench --size 24 --res 16x9 --dynamic stamp --frames 2 --no-shadows", Expect::Ok),
            ("bench --size 24 --no-shadows", Expect::Refused("--dynamic")),
            ("bench --size 24 --res 16x9 --dynamic erosion --frames 1", Expect::Ok),
            ("bench --size 24 --dynamic sand", Expect::Refused("invalid value 'sand'")),
            ("bench --size 24 --cell 8 --tracers mipmap", Expect::Refused("--cell applies to the hybrid renderer only")),
            ("bench --size 24 --tracers hybrid --show-lop", Expect::Refused("--show-lop applies to relief render only")),
            ("bench --size 24 --frames 3", Expect::Refused("--frames applies to --dynamic only")),
            ("bench --size 24 --res 16x9 --tracers mipmap --surfaces triangles --views flight --repeat 1 --no-shadow-sweep", Expect::Ok),
            ("bench --size 24 --res 16x9 --tracers mipmap --surfaces triangles --views top-down --repeat 1 --shadow-sweep --json", Expect::Ok),
            ("bench --size 24 --dynamic waves --no-shadow-sweep", Expect::Refused("--no-shadow-sweep applies to the tracers' shadow rays only")),
            ("bench --size 24 --dynamic waves --frames 0", Expect::Refused("between 1 and 100000")),
        ],
    ),
    (
        "simulate",
        &[
            ("simulate {in}/s.mlhm --steps 3 --seed 4 --rain 0.1 --evaporation 0.02 --dt 0.1 --stats {out}/s.json --max-memory 1G -o {out}/a.json", Expect::Ok),
            ("simulate {in}/s.mlhm --steps 2 --output {out}/a.mlhm", Expect::Ok),
            ("simulate {in}/s.mlhm --steps 0 -o {out}/a.mlhm", Expect::Refused("between 1 and 10000000")),
            ("simulate {in}/s.mlhm --steps 1 --dt -1 -o {out}/a.mlhm", Expect::Refused("time step -1 is outside 0.001..10")),
            ("simulate {in}/s.mlhm --steps 1 --rain -0.5 -o {out}/a.mlhm", Expect::Refused("water rate -0.5 is outside 0..100")),
            ("simulate {in}/f.npy --steps 1 -o {out}/a.mlhm", Expect::Refused("takes an MLHM scene")),
            ("simulate {in}/s.mlhm --steps 1 -o {out}/a.png", Expect::Refused("the result is written as .json")),
            ("simulate {in}/s.mlhm --steps 1 -o {out}/a.mlhm --stats {out}/s.txt", Expect::Refused("the statistics are written as .json")),
            ("simulate {in}/s.mlhm --steps 1 -o {in}/s.mlhm", Expect::Refused("would overwrite the input")),
            ("simulate {in}/s.mlhm --steps 4 --render-every 2 --frames {out}/frames --preset high --size 32x18 --view 30,40 --stats {out}/s.json -o {out}/a.mlhm", Expect::Ok),
            ("simulate {in}/s.mlhm --steps 2 --render-every 1 --frames {out}/frames -o {out}/a.mlhm --size 16x16", Expect::Ok),
            ("simulate {in}/s.mlhm --steps 2 --frames {out}/frames -o {out}/a.mlhm", Expect::Refused("--frames needs --render-every")),
            ("simulate {in}/s.mlhm --steps 2 --render-every 1 -o {out}/a.mlhm", Expect::Refused("--render-every needs --frames")),
            ("simulate {in}/s.mlhm --steps 2 --render-every 0 --frames {out}/frames -o {out}/a.mlhm", Expect::Refused("between 1 and 10000000")),
            ("simulate {in}/s.mlhm --steps 2 --render-every 1 --frames {in}/s.mlhm/frames -o {out}/a.mlhm", Expect::Refused("cannot create the folder")),
            ("simulate {in}/s.mlhm --steps 2 --preset low -o {out}/a.mlhm", Expect::Refused("--preset applies to --frames only")),
            ("simulate {in}/s.mlhm --steps 2 --view 45,30 -o {out}/a.mlhm", Expect::Refused("--view applies to --frames only")),
            ("simulate {in}/s.mlhm --steps 3 --checkpoint 2 --check-stages -o {out}/a.mlhm", Expect::Ok),
            ("simulate {in}/s.mlhm --steps 2 --checkpoint 0 -o {out}/a.mlhm", Expect::Refused("between 1 and 10000000")),
        ],
    ),
    (
        "flythrough",
        &[
            ("flythrough {in}/f.tif --path {in}/p.json --frames 3 --output {out}/frames --size 16x9 --stats {out}/s.json", Expect::Ok),
            ("flythrough {in}/f.npy --path {in}/p.json --frames 2 -o {out}/frames --spacing 2,3 --north-up --z-scale 3 --surface boxes --tracer naive --sun -45,-10 --no-shadows --exposure 2 --size 16x9", Expect::Ok),
            ("flythrough {in}/f.npy --path {in}/p.json --frames 1 -o {out}/frames --tracer safety --safety cyl_ext+cone_ext --phi-max -5 --no-shadows --isotropic --positive --linear-surface --safety-reach 16 --no-cache --size 16x9", Expect::Ok),
            ("flythrough {in}/f.npy --path {in}/p.json --frames 1 -o {out}/frames --tracer safety --cache-dir {out} --size 16x9", Expect::Ok),
            ("flythrough {in}/f.png --path {in}/p.json --frames 1 -o {out}/frames --png-encoding grey --voids fill --max-memory 1G --texture {in}/t.png --size 16x9", Expect::Ok),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 1 -o {out}/frames --z-unit ft --size 16x9", Expect::Ok),
            ("flythrough --fbm-size 24 --seed 3 --path {in}/p.json --frames 2 -o {out}/frames --size 16x9", Expect::Ok),
            ("flythrough --fbm-size 24 --path {in}/p.json --frames 1 -o {out}/frames --size 16x9 --png-compression none", Expect::Ok),
            ("flythrough {in}/s.mlhm --path {in}/p.json --frames 2 -o {out}/frames --mode smooth --sigma 1 --preset low --no-ao --size 16x9", Expect::Ok),
            ("flythrough {in}/s.mlhm --path {in}/p.json --frames 1 -o {out}/frames --tracer hierarchy --backtrack miss --hierarchy-bounds f16 --size 16x9", Expect::Ok),
            ("flythrough {in}/s.mlhm --path {in}/p.json --frames 2 -o {out}/frames --mode mesh --tau 6 --voxel-height 4 --sigma 8 --size 16x9", Expect::Ok),
            ("flythrough {in}/st --path {in}/p.json --frames 3 -o {out}/frames --max-error-px 1 --cache-mb 16 --wait --stats {out}/s.json --size 16x9", Expect::Ok),
            ("flythrough {in}/st --path {in}/p.json --frames 2 -o {out}/frames --size 16x9", Expect::Ok),
            ("flythrough {in}/stt --path {in}/p.json --frames 2 -o {out}/frames --texture-filter bilinear --texture-cache-mb 16 --size 16x9", Expect::Ok),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 0 -o {out}/frames", Expect::Refused("between 1 and 100000")),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 2 -o {in}/f.tif", Expect::Refused("not a folder")),
            ("flythrough {in}/st --path {in}/p.json --frames 2 -o {in}/st", Expect::Refused("would overwrite the input")),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 2 -o {out}/frames --stats {out}/s.txt", Expect::Refused("the statistics are written as .json")),
            ("flythrough {in}/f.tif --path {out}/missing.json --frames 2 -o {out}/frames", Expect::Refused("missing.json")),
            ("flythrough {in}/f.tif --path {in}/f.tif --frames 2 -o {out}/frames", Expect::Refused("--path")),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 2 -o {out}/frames --eye 1,2,3 --target 0,0,0", Expect::Refused("--eye applies to relief render only, not to relief flythrough")),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 2 -o {out}/frames --view 45,30", Expect::Refused("--view applies to relief render only")),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 2 -o {out}/frames --array heights", Expect::Refused("--array applies to NumPy archives (.npz) only")),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 2 -o {out}/frames --wait", Expect::Refused("--wait applies to tile stores")),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 2 -o {out}/frames --max-error-px 1", Expect::Refused("--max-error-px applies to tile stores")),
            ("flythrough {in}/st --path {in}/p.json --frames 2 -o {out}/frames --tracer naive", Expect::Refused("--tracer applies to height files only")),
            ("flythrough {in}/f.tif --path {in}/p.json --frames 2 -o {out}/frames --tracer hybrid", Expect::Refused("relief flythrough draws with the naive, mipmap and safety tracers")),
        ],
    ),
];

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
        "shade no.tif --sky-rays -1",
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
