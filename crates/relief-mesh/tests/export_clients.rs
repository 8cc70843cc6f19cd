//! The exported .glb, .obj and .ply files read back by the real clients of those formats: the
//! Khronos glTF validator (npm `gltf-validator`, run by node through `validate_gltf.mjs`) and
//! trimesh (Python). A test whose client is missing is reported ignored, with the reason, or
//! fails with RELIEF_REQUIRE_CLIENTS=1 (.ci/run installs them and sets it): the harness in
//! relief-io's tests/common/clients.rs.

#[path = "../../relief-io/tests/common/clients.rs"]
mod clients;

use relief_core::DVec3;
use relief_mesh::export::{to_glb_bytes, to_obj_bytes, to_ply_bytes, MeshFormat};
use relief_mesh::{MeshPart, TerrainMesh};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    clients::run(vec![
        clients::trial!(the_gltf_validator_accepts_the_glb_files, GltfValidator),
        clients::trial!(trimesh_reads_the_glb_obj_and_ply_files, Trimesh),
        clients::trial!(the_extension_names_the_format),
        clients::accounting_trial(
            "the_gltf_validator_accepts_the_glb_files",
            clients::Client::GltfValidator,
        ),
        clients::accounting_trial(
            "trimesh_reads_the_glb_obj_and_ply_files",
            clients::Client::Trimesh,
        ),
    ]);
}

/// A fresh, empty directory under the system's temporary directory, removed when dropped.
struct TestDir(PathBuf);

impl TestDir {
    fn new(name: &str) -> Self {
        let path = std::env::temp_dir()
            .join(format!("relief-mesh-export-clients-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap();
        TestDir(path)
    }
}

impl Drop for TestDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// An axis-aligned cube from `min` with edge `size`: 8 shared corners and 6 outward quads
/// (counter-clockwise seen from outside), normals along the corners' diagonals, each corner's
/// colour its position in the unit cube.
fn cube(name: &str, min: DVec3, size: f64, base_color: [f32; 4]) -> MeshPart {
    let mut part = MeshPart::new(name, base_color);
    for k in 0..8u32 {
        let corner = DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64);
        part.positions.push(min + corner * size);
        let n = (corner * 2.0 - DVec3::ONE).normalize();
        part.normals.push([n.x as f32, n.y as f32, n.z as f32]);
        part.colors.push([corner.x as f32, corner.y as f32, corner.z as f32]);
    }
    part.quads =
        vec![[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    part
}

/// A unit `solid` cube at `origin` and a translucent `water` cube of edge 0.5 two metres east.
fn two_cubes(origin: DVec3) -> TerrainMesh {
    TerrainMesh {
        parts: vec![
            cube("solid", origin, 1.0, [0.6, 0.5, 0.4, 1.0]),
            cube("water", origin + DVec3::new(2.0, 0.0, 0.0), 0.5, [0.1, 0.3, 0.6, 0.7]),
        ],
    }
}

/// The Khronos validator's report on the .glb at `path` (the harness has found node and the
/// validator).
fn gltf_validator(path: &Path) -> Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/validate_gltf.mjs");
    let out = Command::new("node").arg(&script).arg(path).output().expect("node runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{}: {stderr}", script.display());
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Runs a Python script with trimesh on `args` and returns what it printed, parsed as JSON
/// (the harness has found python3 with trimesh).
fn trimesh(script: &str, args: &[&Path]) -> Value {
    let out = Command::new("python3").arg("-c").arg(script).args(args).output().unwrap();
    assert!(out.status.success(), "{script}\n{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Asserts that the validator found no errors, warnings or infos (listing them if it did).
fn assert_clean(report: &Value) {
    let issues = &report["issues"];
    for count in ["numErrors", "numWarnings", "numInfos"] {
        assert_eq!(issues[count], 0, "{count}: {:#}", issues["messages"]);
    }
}

fn the_gltf_validator_accepts_the_glb_files() {
    let dir = TestDir::new("validator");
    // Near the origin, far out in UTM-like coordinates, and without any faces.
    let meshes = [
        ("cubes.glb", two_cubes(DVec3::ZERO)),
        ("utm.glb", two_cubes(DVec3::new(500_000.25, 5_200_000.5, 1234.0))),
        ("empty.glb", TerrainMesh { parts: vec![MeshPart::new("solid", [1.0; 4])] }),
    ];
    for (name, mesh) in &meshes {
        let path = dir.0.join(name);
        std::fs::write(&path, to_glb_bytes(mesh).unwrap()).unwrap();
        let report = gltf_validator(&path);
        println!("{name}: validator {} {}", report["validatorVersion"], report["issues"]);
        assert_clean(&report);
        if name == &"cubes.glb" {
            // The control: the same file cut short is reported, so the validator did read it.
            let bytes = std::fs::read(&path).unwrap();
            let cut = dir.0.join("cut.glb");
            std::fs::write(&cut, &bytes[..bytes.len() - 40]).unwrap();
            let report = gltf_validator(&cut);
            assert!(report["issues"]["numErrors"].as_u64().unwrap() > 0, "{report:#}");
        }
        let info = &report["info"];
        assert_eq!(info["version"], "2.0", "{name}");
        assert_eq!(info["generator"], "relief", "{name}");
        let faces = mesh.face_count();
        assert_eq!(info["drawCallCount"], if faces == 0 { 0 } else { 2 }, "{name}");
        if faces > 0 {
            assert_eq!(info["totalVertexCount"], 16, "{name}");
            assert_eq!(info["totalTriangleCount"], 24, "{name}");
            assert_eq!(info["materialCount"], 2, "{name}");
        }
    }
}

/// Loads the .glb, .obj and .ply files given as arguments with trimesh and prints what the
/// test checks, as JSON.
const TRIMESH_SCRIPT: &str = r#"
import json, sys
import numpy as np
import trimesh

def summary(mesh):
    return {
        "vertices": len(mesh.vertices),
        "faces": len(mesh.faces),
        "watertight": bool(mesh.is_watertight),
        "winding_consistent": bool(mesh.is_winding_consistent),
        "volume": float(mesh.volume),
        "bounds": mesh.bounds.tolist(),
        "colors": mesh.visual.vertex_colors[:, :3].tolist()
            if mesh.visual.kind == "vertex" else None,
    }

glb, obj, ply = sys.argv[1:4]
scene = trimesh.load(glb, force="scene")
out = {"glb": {
    "geometry": {name: summary(g) for name, g in scene.geometry.items()},
    "nodes": sorted(scene.graph.nodes_geometry),
    "bounds": scene.bounds.tolist(),
}}
for key, path in (("obj", obj), ("ply", ply)):
    mesh = trimesh.load(path, force="mesh", process=False)
    parts = sorted(mesh.split(only_watertight=False), key=lambda m: -abs(m.volume))
    out[key] = {"mesh": summary(mesh), "parts": [summary(p) for p in parts]}
print(json.dumps(out))
"#;

fn trimesh_reads_the_glb_obj_and_ply_files() {
    let dir = TestDir::new("trimesh");
    let mut mesh = two_cubes(DVec3::new(10.0, 20.0, 30.0));
    // Linear 0.2159 is sRGB 128/255: the colours of .obj and .ply files are sRGB-encoded.
    mesh.parts[0].colors[0] = [0.215_861; 3];
    let paths = ["cubes.glb", "cubes.obj", "cubes.ply"].map(|name| dir.0.join(name));
    std::fs::write(&paths[0], to_glb_bytes(&mesh).unwrap()).unwrap();
    std::fs::write(&paths[1], to_obj_bytes(&mesh).unwrap()).unwrap();
    std::fs::write(&paths[2], to_ply_bytes(&mesh).unwrap()).unwrap();
    let report = trimesh(TRIMESH_SCRIPT, &paths.each_ref().map(PathBuf::as_path));
    println!("trimesh: {report}");
    let close = |value: &Value, want: f64| (value.as_f64().unwrap() - want).abs() < 1e-6;

    // glb: the two named geometries, closed, outward (positive volume), in glTF's y-up axes:
    // relief's (x, y, z) is (x, z, -y), so the bounds are x 10..12.5, y 30..31, z -21..-20.
    let glb = &report["glb"];
    let geometry = glb["geometry"].as_object().unwrap();
    assert_eq!(geometry.keys().collect::<Vec<_>>(), ["solid", "water"], "{glb:#}");
    for (name, volume) in [("solid", 1.0), ("water", 0.125)] {
        let part = &geometry[name];
        assert_eq!((part["vertices"].as_u64(), part["faces"].as_u64()), (Some(8), Some(12)));
        assert_eq!(part["watertight"], true, "{name}");
        assert_eq!(part["winding_consistent"], true, "{name}");
        assert!(close(&part["volume"], volume), "{name}: {}", part["volume"]);
    }
    assert_eq!(glb["nodes"], serde_json::json!(["solid", "water"]), "{glb:#}");
    let bounds = [[10.0, 30.0, -21.0], [12.5, 31.0, -20.0]];
    for (k, corner) in bounds.iter().enumerate() {
        for (j, &want) in corner.iter().enumerate() {
            assert!(close(&glb["bounds"][k][j], want), "{}", glb["bounds"]);
        }
    }

    // obj and ply: one mesh of both cubes (quads triangulated by trimesh), relief's z-up axes,
    // colours sRGB-encoded; split apart, the solid cube is closed with volume 1.
    for key in ["obj", "ply"] {
        let whole = &report[key]["mesh"];
        assert_eq!(whole["vertices"], 16, "{key}");
        assert_eq!(whole["faces"], 24, "{key}");
        let bounds = [[10.0, 20.0, 30.0], [12.5, 21.0, 31.0]];
        for (k, corner) in bounds.iter().enumerate() {
            for (j, &want) in corner.iter().enumerate() {
                assert!(close(&whole["bounds"][k][j], want), "{key}: {}", whole["bounds"]);
            }
        }
        // Corner 7 of the solid (1, 1, 1) is white, corner 1 (1, 0, 0) red, corner 0 grey.
        let colors = &whole["colors"];
        assert_eq!(colors[0], serde_json::json!([128, 128, 128]), "{key}");
        assert_eq!(colors[7], serde_json::json!([255, 255, 255]), "{key}");
        assert_eq!(colors[1], serde_json::json!([255, 0, 0]), "{key}");
        let parts = report[key]["parts"].as_array().unwrap();
        assert_eq!(parts.len(), 2, "{key}");
        for (part, volume) in parts.iter().zip([1.0, 0.125]) {
            assert_eq!(part["faces"], 12, "{key}");
            assert_eq!(part["watertight"], true, "{key}");
            assert!(close(&part["volume"], volume), "{key}: {}", part["volume"]);
        }
    }
}

fn the_extension_names_the_format() {
    let dir = TestDir::new("extension");
    let mesh = two_cubes(DVec3::ZERO);
    for (name, format) in
        [("a.GLB", MeshFormat::Glb), ("b.Obj", MeshFormat::Obj), ("c.ply", MeshFormat::Ply)]
    {
        assert_eq!(MeshFormat::from_path(&dir.0.join(name)).unwrap(), format);
        let bytes = format.to_bytes(&mesh).unwrap();
        let expected = match format {
            MeshFormat::Glb => to_glb_bytes(&mesh),
            MeshFormat::Obj => to_obj_bytes(&mesh),
            MeshFormat::Ply => to_ply_bytes(&mesh),
        };
        assert_eq!(bytes, expected.unwrap());
    }
    let err = MeshFormat::from_path(&dir.0.join("d.stl")).unwrap_err();
    assert!(err.to_string().contains(".glb, .obj or .ply"), "{err}");
}
