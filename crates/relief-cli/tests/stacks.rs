//! `relief mesh` and `relief render --mode mesh` as a user types them: an MLHM scene meshed
//! into a .glb the Khronos glTF validator accepts and trimesh reads as a closed solid and a
//! closed water body, OBJ and PLY read back, the camera's levels of detail, and bad input
//! refused with exit code 2 and no file. A test whose client (the validator, trimesh) is missing
//! is reported ignored, with the reason (tests/common/clients.rs).

mod common;

use common::{clients, read_f32_npy, relief, scratch};
use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    clients::run(vec![
        clients::trial!(
            an_mlhm_scene_meshes_into_a_glb_the_validator_and_trimesh_accept,
            GltfValidator,
            Trimesh,
        ),
        clients::trial!(obj_and_ply_of_the_camera_levels_read_back, Trimesh),
        clients::trial!(render_mode_mesh_draws_the_lod_mesh_with_depth_and_stats),
        clients::trial!(a_stacks_file_meshes_and_bad_input_is_refused_with_exit_code_2),
        clients::trial!(a_height_file_meshes_as_bedrock_with_finer_voxels_when_asked),
    ]);
}

/// A scratch folder whose name has a space, as users' folders do.
fn folder(name: &str) -> PathBuf {
    let dir = scratch(&format!("stacks {name}"));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The carved MLHM scene with arches, caves and water, `size` cells a side (256 m), written
/// into `dir`.
fn scene(dir: &Path, size: &str) -> PathBuf {
    let path = dir.join("combined scene.json");
    let out = relief(&[
        "generate",
        "mlhm",
        "--scene",
        "combined",
        "--size",
        size,
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    path
}

/// Runs relief with `args`; it must succeed. Returns its stderr.
fn ok(args: &[&str]) -> String {
    let out = relief(args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{args:?}: {stderr}");
    stderr
}

/// Runs relief with `args`; it must fail with exit code 2 and a one-line error containing
/// `expected`.
fn refused(args: &[&str], expected: &str) {
    let out = relief(args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(stderr.contains(expected), "{args:?}: {stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
}

/// Python with trimesh (the harness has found it) runs `script` (the file's path as
/// sys.argv[1]); its stdout.
fn trimesh(script: &str, file: &Path) -> String {
    let out = Command::new("python3").args(["-c", script]).arg(file).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    stdout
}

fn an_mlhm_scene_meshes_into_a_glb_the_validator_and_trimesh_accept() {
    let dir = folder("glb");
    // 2 m cells: the scene's water, up to 2.9 m deep, is thick enough to mesh.
    let input = scene(&dir, "128");
    let glb = dir.join("terrain mesh.glb");
    let stats = dir.join("stats.json");
    let stderr = ok(&[
        "mesh",
        input.to_str().unwrap(),
        "--lod",
        "0",
        "-o",
        glb.to_str().unwrap(),
        "--stats",
        stats.to_str().unwrap(),
    ]);
    assert!(stderr.contains("level 0 of"), "{stderr}");
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    for key in ["load_ms", "mesh_ms", "write_ms", "total_ms", "nodes", "solid_faces"] {
        assert!(stats[key].as_f64().is_some(), "{key} in {stats}");
    }

    // The Khronos glTF validator.
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../relief-mesh/tests/validate_gltf.mjs");
    let out = Command::new("node").arg(&script).arg(&glb).output().expect("node runs");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stderr)));
    let issues = &report["issues"];
    assert_eq!(issues["numErrors"], 0, "{report}");
    assert_eq!(issues["numWarnings"], 0, "{report}");

    // trimesh: two named meshes, each closed and consistently wound, with volume.
    let report = trimesh(
        "import sys, trimesh\n\
         scene = trimesh.load(sys.argv[1])\n\
         for name in sorted(scene.geometry):\n\
         \x20   m = scene.geometry[name]\n\
         \x20   print(name, m.is_watertight, m.is_winding_consistent, round(float(m.volume), 1))\n",
        &glb,
    );
    let lines: Vec<&str> = report.lines().collect();
    assert_eq!(lines.len(), 2, "{report}");
    for (line, name) in lines.iter().zip(["solid", "water"]) {
        let fields: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(fields[..3], [name, "True", "True"], "{report}");
        assert!(fields[3].parse::<f64>().unwrap() > 0.0, "{report}");
    }
}

fn obj_and_ply_of_the_camera_levels_read_back() {
    let dir = folder("obj ply");
    let input = scene(&dir, "64");
    for name in ["terrain.obj", "terrain.ply"] {
        let path = dir.join(name);
        let stderr = ok(&[
            "mesh",
            input.to_str().unwrap(),
            "--eye",
            "-20,-30,40",
            "--target",
            "128,128,0",
            "--tau",
            "4",
            "-o",
            path.to_str().unwrap(),
        ]);
        assert!(stderr.contains("octree nodes for the camera"), "{stderr}");
        let report = trimesh(
            "import sys, trimesh\n\
             m = trimesh.load(sys.argv[1], force='mesh', process=False)\n\
             print(len(m.vertices), len(m.faces))\n",
            &path,
        );
        let counts: Vec<usize> = report.split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert!(counts[0] > 1000 && counts[1] > 1000, "{name}: {report}");
    }
}

fn render_mode_mesh_draws_the_lod_mesh_with_depth_and_stats() {
    let dir = folder("render");
    let input = scene(&dir, "64");
    let (png, depth, stats) =
        (dir.join("mesh view.png"), dir.join("depth.npy"), dir.join("stats.json"));
    let stderr = ok(&[
        "render",
        input.to_str().unwrap(),
        "--mode",
        "mesh",
        "--eye",
        "-60,-80,90",
        "--target",
        "128,128,0",
        "--size",
        "160x90",
        "-o",
        png.to_str().unwrap(),
        "--depth",
        depth.to_str().unwrap(),
        "--stats",
        stats.to_str().unwrap(),
    ]);
    assert!(stderr.contains("stacks mesh of"), "{stderr}");
    let (shape, values) = read_f32_npy(&depth);
    assert_eq!(shape, vec![90, 160]);
    assert!(values.iter().filter(|v| v.is_finite()).count() > 1000);
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    for key in ["load_ms", "build_ms", "trace_ms", "shade_ms", "total_ms"] {
        assert!(stats[key].as_f64().is_some(), "{key} in {stats}");
    }
}

/// A .stacks file by its documented layout (docs/stacks.md), one stack per entry.
fn stacks_file(path: &Path, width: u32, height: u32, stacks: &[Vec<(f32, f32, u8)>]) {
    let mut b = Vec::new();
    b.extend_from_slice(b"RELIEFSTK\0");
    b.extend_from_slice(&1u16.to_le_bytes());
    b.extend_from_slice(&width.to_le_bytes());
    b.extend_from_slice(&height.to_le_bytes());
    for v in [1.0f64, 1.0, 0.0, 0.0] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&1u16.to_le_bytes());
    b.extend_from_slice(&[0, 120, 110, 100]);
    b.extend_from_slice(&4u16.to_le_bytes());
    b.extend_from_slice(b"rock");
    let layers: usize = stacks.iter().map(Vec::len).sum();
    b.extend_from_slice(&(layers as u64).to_le_bytes());
    let mut offset = 0u32;
    b.extend_from_slice(&offset.to_le_bytes());
    for s in stacks {
        offset += s.len() as u32;
        b.extend_from_slice(&offset.to_le_bytes());
    }
    for (start, end, material) in stacks.iter().flatten() {
        b.extend_from_slice(&start.to_le_bytes());
        b.extend_from_slice(&end.to_le_bytes());
        b.push(*material);
    }
    std::fs::write(path, b).unwrap();
}

fn a_stacks_file_meshes_and_bad_input_is_refused_with_exit_code_2() {
    let dir = folder("refused");
    let good = dir.join("arch.stacks");
    let mut stacks = vec![vec![(0.0, 3.0, 0)]; 12 * 10];
    for (k, stack) in stacks.iter_mut().enumerate() {
        if (3..9).contains(&(k % 12)) {
            stack.push((6.0, 8.0, 0));
        }
    }
    stacks_file(&good, 12, 10, &stacks);
    let glb = dir.join("arch.glb");
    ok(&["mesh", good.to_str().unwrap(), "--lod", "0", "-o", glb.to_str().unwrap()]);
    assert!(std::fs::metadata(&glb).unwrap().len() > 1000);

    let out = dir.join("never.glb");
    let out_s = out.to_str().unwrap();
    // Layers that overlap, naming the stack and the layer.
    let bad = dir.join("overlap.stacks");
    let mut overlapping = vec![vec![(0.0, 2.0, 0)]; 2];
    overlapping[1].push((1.0, 3.0, 0));
    stacks_file(&bad, 2, 1, &overlapping);
    refused(&["mesh", bad.to_str().unwrap(), "-o", out_s], "stack (1, 0), layer 1");
    // A layer running backwards.
    stacks_file(&bad, 1, 1, &[vec![(3.0, 1.0, 0)]]);
    refused(&["mesh", bad.to_str().unwrap(), "-o", out_s], "stack (0, 0), layer 0");
    // A level beyond the mipmap, naming it.
    refused(&["mesh", good.to_str().unwrap(), "--lod", "40", "-o", out_s], "level of detail 40");
    // A format relief does not write.
    refused(&["mesh", good.to_str().unwrap(), "-o", dir.join("x.stl").to_str().unwrap()], ".glb");
    // --tau with a fixed level, and --tau where nothing is meshed.
    refused(&["mesh", good.to_str().unwrap(), "--lod", "0", "--tau", "5", "-o", out_s], "--tau");
    let png = dir.join("never.png");
    refused(&["render", "--tau", "5", "-o", png.to_str().unwrap()], "--tau");
    assert!(!png.exists());
    assert!(!out.exists(), "a refused run wrote {}", out.display());
}

fn a_height_file_meshes_as_bedrock_with_finer_voxels_when_asked() {
    let dir = folder("height file");
    let dem = dir.join("hills dem.npy");
    ok(&["generate", "fbm", "--size", "48", "-o", dem.to_str().unwrap()]);
    let faces = |voxel: Option<&str>| {
        let stats = dir.join("stats.json");
        let out = dir.join("hills.glb");
        let mut args = vec!["mesh", dem.to_str().unwrap(), "--lod", "0", "-o"];
        args.extend([out.to_str().unwrap(), "--stats", stats.to_str().unwrap()]);
        if let Some(v) = voxel {
            args.extend(["--voxel-height", v]);
        }
        ok(&args);
        let stats: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        stats["solid_faces"].as_u64().unwrap()
    };
    // Voxels a quarter of the spacing high resolve the slopes in more faces.
    let (cubic, fine) = (faces(None), faces(Some("0.25")));
    assert!(cubic > 1000 && 2 * fine > 3 * cubic, "{cubic} faces, then {fine}");
    let png = dir.join("never.png");
    refused(
        &["render", dem.to_str().unwrap(), "--voxel-height", "1", "-o", png.to_str().unwrap()],
        "--voxel-height",
    );
    assert!(!png.exists());
}
