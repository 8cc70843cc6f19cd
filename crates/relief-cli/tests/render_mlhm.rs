//! End-to-end tests of `relief render scene.json`: a multi-layered height map scene renders
//! as boxes at every preset, its depth is the same from the naive and the hierarchy tracer and
//! from every preset, a hand-made scene gives the depths worked out by hand (from above and
//! from under water), the real scene renders at every preset, and bad options or files are
//! refused with exit code 2 before anything is written.
//! In a bare clone (no ../shared) a test that reads the shared data is reported ignored.

mod common;

use common::{
    assert_refused, clients, depth_straight_down, read_f32_npy, relief, render_depth, scratch,
    shared_data,
};
use relief_core::{Mlhm, MlhmColumn};
use relief_io::{read_mlhm_scene, write_mlhm_scene, MlhmScene, ReadOptions};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn main() {
    clients::run(vec![
        clients::trial!(a_carved_scene_renders_with_depth_and_normals),
        clients::trial!(naive_and_hierarchy_tracers_give_the_same_depth),
        clients::trial!(straight_down_depths_match_the_hand_made_scene),
        clients::trial!(every_preset_renders_the_same_surfaces_with_more_rays_for_more_quality),
        clients::trial!(a_camera_under_water_sees_the_bottom_below_and_the_surface_above),
        clients::trial_reading!(
            the_real_scene_renders_at_every_preset,
            "data/ngwm24-scene/scene.json"
        ),
        clients::trial!(the_smooth_surface_renders_at_every_preset_with_and_without_the_hierarchy),
        clients::trial!(a_flat_scene_renders_smooth_as_its_plane),
        clients::trial!(bad_options_and_files_are_refused_with_exit_code_2_and_write_nothing),
    ]);
}

/// The cave scene at 32 x 32 cells, generated once per test process.
fn cave() -> &'static Path {
    static CAVE: OnceLock<PathBuf> = OnceLock::new();
    CAVE.get_or_init(|| {
        let json = scratch("render-cave.json");
        let out = relief(&[
            "generate",
            "mlhm",
            "--scene",
            "cave",
            "--size",
            "32",
            "-o",
            json.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        json
    })
}

/// Renders `scene` at 64 x 48 with `extra` options; returns (depth, stderr).
fn render(scene: &Path, name: &str, extra: &[&str]) -> (Vec<f32>, String) {
    let mut args = vec![scene.to_str().unwrap(), "--size", "64x48"];
    args.extend(extra);
    let (shape, depth, stderr) = render_depth(name, &args);
    assert_eq!(shape, [48, 64], "{name}");
    assert!(std::fs::read(scratch(&format!("{name}.png"))).unwrap()[1..4] == *b"PNG", "{name}");
    (depth, stderr)
}

fn a_carved_scene_renders_with_depth_and_normals() {
    let normals = scratch("cave-normals.npy");
    let (depth, stderr) = render(cave(), "cave", &["--normals", normals.to_str().unwrap()]);
    assert!(stderr.contains("hierarchy tracer, stack"), "{stderr}");
    // The framed view sees the scene in the middle of the image.
    assert!(depth[24 * 64 + 32].is_finite() && depth[24 * 64 + 32] > 0.0);
    let hits = depth.iter().filter(|d| d.is_finite()).count();
    assert!(hits > depth.len() / 4, "{hits} hits");
    assert!(depth.iter().all(|d| d.is_finite() || *d == f32::INFINITY));
    let (shape, n) = read_f32_npy(&normals);
    assert_eq!(shape, [48, 64, 3]);
    for (d, n) in depth.iter().zip(n.chunks_exact(3)) {
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!(if d.is_finite() { (len - 1.0).abs() < 1e-5 } else { len == 0.0 });
    }
}

/// An eye inside the cave, in the air gap of the cell with the most columns, and a point a
/// little below the horizon to look at.
fn eye_in_the_cave() -> (String, String) {
    let map = read_mlhm_scene(cave(), &ReadOptions::default()).unwrap().mlhm;
    let (x, y) = (0..map.height())
        .flat_map(|y| (0..map.width()).map(move |x| (x, y)))
        .max_by_key(|&(x, y)| (map.layer_count(x, y), x, y))
        .unwrap();
    assert!(map.layer_count(x, y) >= 2, "the cave has no overhang");
    let ground = map.column(x, y, 0);
    let z = 0.5 * (ground.water_top() + ground.ceiling) as f64;
    let s = map.cell_size();
    let (ex, ey) = ((x as f64 + 0.5) * s, (y as f64 + 0.5) * s);
    (format!("{ex},{ey},{z}"), format!("{},{},{}", ex + 100.0, ey + 37.0, z - 10.0))
}

fn naive_and_hierarchy_tracers_give_the_same_depth() {
    let (eye, target) = eye_in_the_cave();
    let inside = ["--eye", eye.as_str(), "--target", target.as_str(), "--fov", "90"];
    let views: [&[&str]; 2] = [&[], &inside];
    for (v, view) in views.into_iter().enumerate() {
        let with = |extra: &[&'static str]| [view, extra].concat();
        let (naive, stderr) = render(cave(), &format!("naive-{v}"), &with(&["--tracer", "naive"]));
        assert!(stderr.contains("naive tracer"), "{stderr}");
        let hits = naive.iter().filter(|d| d.is_finite()).count();
        assert!(hits > naive.len() / 4, "view {v}: {hits} hits");
        for (backtrack, bounds) in [("stack", "f32"), ("miss", "f32"), ("stack", "f16")] {
            let extra =
                ["--tracer", "hierarchy", "--backtrack", backtrack, "--hierarchy-bounds", bounds];
            let name = format!("{backtrack}-{bounds}-{v}");
            let (depth, stderr) = render(cave(), &name, &with(&extra));
            assert!(stderr.contains(&format!("{bounds} bounds")), "{stderr}");
            for (k, (a, b)) in naive.iter().zip(&depth).enumerate() {
                let same = a == b || (a - b).abs() <= 1e-5 * a.abs().max(b.abs());
                assert!(same, "view {v}, {backtrack}, {bounds}: pixel {k}: naive {a} vs {b}");
            }
        }
    }
}

/// A 2 x 2 scene of 2 m cells: cell (0, 0) holds ground of bedrock to 1 m, 0.5 m of sand and
/// 0.5 m of water (surface at 2 m) under a rock slab from 3 m to 4 m; cell (1, 0) is rock to
/// 5 m; cells (0, 1) and (1, 1) are bedrock to 1 m and 0.25 m.
fn hand_scene() -> PathBuf {
    let mut map = Mlhm::new(2, 2, 2, 2.0).unwrap();
    let inf = f32::INFINITY;
    map.set_cell(0, 0, &[MlhmColumn::new(1.0, 0.5, 0.5, 3.0), MlhmColumn::new(4.0, 0.0, 0.0, inf)])
        .unwrap();
    map.set_cell(1, 0, &[MlhmColumn::new(5.0, 0.0, 0.0, inf)]).unwrap();
    map.set_cell(0, 1, &[MlhmColumn::new(1.0, 0.0, 0.0, inf)]).unwrap();
    map.set_cell(1, 1, &[MlhmColumn::new(0.25, 0.0, 0.0, inf)]).unwrap();
    let json = scratch("hand.json");
    write_mlhm_scene(&json, &MlhmScene::new(map)).unwrap();
    json
}

fn straight_down_depths_match_the_hand_made_scene() {
    let json = hand_scene();
    for tracer in [&["--tracer", "naive"][..], &[], &["--backtrack", "miss"]] {
        // From 10 m: the slab's top at 4 m, the rock at 5 m, the grounds at 1 m and 0.25 m.
        assert_eq!(depth_straight_down(&json, 1.0, 1.0, 10.0, tracer), 6.0, "{tracer:?}");
        assert_eq!(depth_straight_down(&json, 3.0, 1.0, 10.0, tracer), 5.0, "{tracer:?}");
        assert_eq!(depth_straight_down(&json, 1.0, 3.0, 10.0, tracer), 9.0, "{tracer:?}");
        assert_eq!(depth_straight_down(&json, 3.0, 3.0, 10.0, tracer), 9.75, "{tracer:?}");
        // From inside the cave under the slab: the water's surface at 2 m, not the sand.
        assert_eq!(depth_straight_down(&json, 1.0, 1.0, 2.75, tracer), 0.75, "{tracer:?}");
        // Off the scene: a miss.
        assert_eq!(depth_straight_down(&json, 5.0, 1.0, 10.0, tracer), f32::INFINITY);
    }
}

/// The rays per pixel `relief render` reports on `stderr`.
fn rays_per_pixel(stderr: &str) -> f64 {
    let before = stderr.split(" rays per pixel").next().unwrap();
    before.rsplit(' ').next().unwrap().parse().unwrap_or_else(|_| panic!("{stderr}"))
}

fn every_preset_renders_the_same_surfaces_with_more_rays_for_more_quality() {
    let json = scratch("presets-combined.json");
    let args = ["generate", "mlhm", "--scene", "combined", "--size", "48", "-o"];
    let out = relief(&[&args[..], &[json.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut previous: Option<(Vec<f32>, f64)> = None;
    for preset in ["low", "mid", "high", "max"] {
        let (depth, stderr) = render(&json, &format!("preset-{preset}"), &["--preset", preset]);
        assert!(stderr.contains(&format!("preset {preset}")), "{stderr}");
        let rays = rays_per_pixel(&stderr);
        match &previous {
            None => assert_eq!(rays, 1.0, "low traces camera rays only: {stderr}"),
            Some((first, fewer)) => {
                assert!(rays >= *fewer && rays > 1.0, "{preset}: {rays} after {fewer}");
                assert!(first.iter().zip(&depth).all(|(a, b)| a == b || a.is_nan() && b.is_nan()));
            }
        }
        previous = Some((previous.map_or(depth, |p| p.0), rays));
    }
    let (_, no_shadows) = render(&json, "preset-mid-unlit", &["--preset", "mid", "--no-shadows"]);
    let (_, shadows) = render(&json, "preset-mid-lit", &["--preset", "mid"]);
    assert!(rays_per_pixel(&no_shadows) < rays_per_pixel(&shadows));
}

fn a_camera_under_water_sees_the_bottom_below_and_the_surface_above() {
    let json = hand_scene();
    // Cell (0, 0): sand top at 1.5 m, water surface at 2 m; the eye is in the water at 1.75 m.
    for extra in [&["--preset", "low"][..], &["--preset", "high"]] {
        assert_eq!(depth_straight_down(&json, 1.0, 1.0, 1.75, extra), 0.25, "{extra:?}");
        let view = ["--eye", "1,1,1.75", "--target", "1,1,10", "--up", "0,1,0"];
        let mut args = vec![json.to_str().unwrap(), "--fov", "1", "--size", "1x1"];
        args.extend(view);
        args.extend(extra);
        let (_, up, _) = render_depth("under-water-up", &args);
        assert_eq!(up, [0.25], "the surface from below, {extra:?}");
    }
    // A wide view from under water renders the bottom, the surface (with total internal
    // reflection) and the slab: no pixel is black.
    let png = scratch("under-water.png");
    let out = relief(&[
        "render",
        json.to_str().unwrap(),
        "--eye",
        "0.2,0.2,1.8",
        "--target",
        "3,3,2.2",
        "--fov",
        "120",
        "--size",
        "32x24",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let image = relief_io::read_png_rgb(&png).unwrap();
    assert!(image.pixels.iter().all(|p| p.iter().any(|&c| c > 0)), "a black pixel");
}

fn the_real_scene_renders_at_every_preset() {
    let Some(json) = shared_data("data/ngwm24-scene/scene.json") else { return };
    for preset in ["low", "mid", "high", "max"] {
        let (depth, stderr) = render(&json, &format!("real-{preset}"), &["--preset", preset]);
        assert!(stderr.contains("256x256 MLHM scene"), "{stderr}");
        let hits = depth.iter().filter(|d| d.is_finite()).count();
        assert!(hits > depth.len() / 3, "{preset}: {hits} hits");
    }
}

fn the_smooth_surface_renders_at_every_preset_with_and_without_the_hierarchy() {
    let mut previous = 0.0;
    for preset in ["low", "mid", "high", "max"] {
        let extra = ["--mode", "smooth", "--preset", preset];
        let (depth, stderr) = render(cave(), &format!("smooth-{preset}"), &extra);
        assert!(stderr.contains("as a smooth surface (sigma 8 m)"), "{stderr}");
        let hits = depth.iter().filter(|d| d.is_finite()).count();
        assert!(hits > depth.len() / 4, "{preset}: {hits} hits");
        let rays = rays_per_pixel(&stderr);
        assert!(rays >= previous, "{preset}: {rays} rays per pixel after {previous}");
        previous = rays;
    }
    // Marching the whole ray finds the same surface as marching inside the padded nodes,
    // within the march's tolerance (1% of sigma = 8 cm, plus the corrective step).
    let (with, _) = render(cave(), "smooth-hierarchy", &["--mode", "smooth"]);
    let (without, stderr) =
        render(cave(), "smooth-marching", &["--mode", "smooth", "--tracer", "naive"]);
    assert!(stderr.contains("marching without the hierarchy"), "{stderr}");
    let differing =
        with.iter().zip(&without).filter(|(a, b)| !(a == b || (*a - *b).abs() < 0.5)).count();
    assert!(differing * 200 < with.len(), "{differing} of {} pixels differ", with.len());
}

fn a_flat_scene_renders_smooth_as_its_plane() {
    let mut map = Mlhm::new(16, 16, 1, 0.5).unwrap();
    for y in 0..16 {
        for x in 0..16 {
            map.set_cell(x, y, &[MlhmColumn::new(3.0, 0.0, 0.0, f32::INFINITY)]).unwrap();
        }
    }
    let json = scratch("flat.json");
    write_mlhm_scene(&json, &MlhmScene::new(map)).unwrap();
    // At least sigma from the grid's edges, where the surface rounds off.
    for (x, y) in [(4.0, 4.0), (1.3, 6.9), (7.25, 0.75)] {
        let depth = depth_straight_down(&json, x, y, 10.0, &["--mode", "smooth"]);
        // The march stops within 1% of sigma (0.5 m) of the plane z = 3.
        assert!((7.0 - 0.005..=7.0).contains(&depth), "({x}, {y}): {depth}");
    }
}

fn bad_options_and_files_are_refused_with_exit_code_2_and_write_nothing() {
    let cave = cave().to_str().unwrap().to_string();
    let garbage = scratch("garbage.json");
    std::fs::write(&garbage, b"{ not json").unwrap();
    let no_dat = scratch("no-dat.json");
    std::fs::copy(cave.as_str(), &no_dat).unwrap();
    let json = |p: &PathBuf| p.to_str().unwrap().to_string();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec![cave.clone(), "--tracer".into(), "mipmap".into()], "height fields only"),
        (vec![cave.clone(), "--tracer".into(), "safety".into()], "height fields only"),
        (vec![cave.clone(), "--tracer".into(), "cyl_all".into()], "height fields only"),
        (
            vec![
                cave.clone(),
                "--tracer".into(),
                "naive".into(),
                "--backtrack".into(),
                "miss".into(),
            ],
            "--backtrack",
        ),
        (vec![cave.clone(), "--backtrack".into(), "up".into()], "expected stack or miss"),
        (vec![cave.clone(), "--hierarchy-bounds".into(), "f8".into()], "expected f32 or f16"),
        (
            vec![
                cave.clone(),
                "--tracer".into(),
                "naive".into(),
                "--hierarchy-bounds".into(),
                "f16".into(),
            ],
            "--hierarchy-bounds",
        ),
        (vec![cave.clone(), "--preset".into(), "ultra".into()], "expected low, mid, high or max"),
        (vec![cave.clone(), "--sigma".into(), "1".into()], "--mode smooth only"),
        (
            vec![cave.clone(), "--mode".into(), "smooth".into(), "--sigma".into(), "0".into()],
            "must be a positive length",
        ),
        (
            vec![cave.clone(), "--mode".into(), "smooth".into(), "--sigma".into(), "nan".into()],
            "must be a positive length",
        ),
        (vec![cave.clone(), "--mode".into(), "spheres".into()], "expected boxes, smooth or mesh"),
        (vec![cave.clone(), "--surface".into(), "triangles".into()], "--surface triangles"),
        (vec![cave.clone(), "--z-scale".into(), "2".into()], "--z-scale"),
        (vec![cave.clone(), "--max-memory".into(), "8K".into()], "memory limit"),
        (vec![json(&garbage)], "garbage.json"),
        (vec![json(&scratch("missing.json"))], "missing.json"),
        (
            vec!["--fbm-size".into(), "16".into(), "--tracer".into(), "hierarchy".into()],
            "MLHM scenes (.json, .mlhm) only",
        ),
        (vec!["--fbm-size".into(), "16".into(), "--mode".into(), "boxes".into()], "--mode"),
        (vec!["--fbm-size".into(), "16".into(), "--preset".into(), "max".into()], "--preset"),
        (
            vec!["--fbm-size".into(), "16".into(), "--backtrack".into(), "stack".into()],
            "--backtrack",
        ),
    ];
    // The .dat the copied JSON names is the cave's own: point it at one that does not exist.
    let text = std::fs::read_to_string(&no_dat).unwrap().replace("render-cave.dat", "gone.dat");
    std::fs::write(&no_dat, text).unwrap();
    let cases = cases.into_iter().chain([(vec![json(&no_dat)], "gone.dat")]);
    for (k, (args, mentions)) in cases.enumerate() {
        let (png, depth) =
            (scratch(&format!("refused-{k}.png")), scratch(&format!("refused-{k}.npy")));
        let mut all = vec![
            "render",
            "--size",
            "8x6",
            "-o",
            png.to_str().unwrap(),
            "--depth",
            depth.to_str().unwrap(),
        ];
        all.extend(args.iter().map(String::as_str));
        let out = relief(&all);
        assert_refused(&out, mentions);
        let stderr = String::from_utf8_lossy(&out.stderr);
        if !stderr.contains("For more information") {
            assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr}");
        }
        assert!(!png.exists() && !depth.exists(), "{args:?} wrote");
    }
}
