//! `relief mesh`: a material-stack terrain dual-contoured at one level of detail or at the
//! camera's levels, written as glTF binary, OBJ or PLY.

pub mod args;

use crate::args::MlhmRenderMode;
use crate::opening::open_stacks;
use crate::{outputs, progress};
use anyhow::{bail, Result};
use args::{LodChoice, MeshArgs};
use relief_mesh::{MeshStats, TerrainMesh};
use serde_json::json;
use std::time::Instant;

/// The screen-space error of `--lod auto` when `--tau` is not given, pixels (the paper's).
use relief_render::options::DEFAULT_TAU_PX;

/// Runs `relief mesh`.
pub fn run(args: &MeshArgs) -> Result<()> {
    let started = Instant::now();
    outputs::check_writable(&args.output)?;
    let format = mesh_format(&args.output)?;
    if let Some(path) = &args.stats {
        outputs::check_stats(path)?;
    }
    let inputs: Vec<&std::path::Path> = args.scene.input.input.as_deref().into_iter().collect();
    let mut all = vec![("-o", args.output.as_path())];
    if let Some(path) = &args.stats {
        all.push(("--stats", path.as_path()));
    }
    outputs::check_distinct(&all, &inputs)?;
    let scene = &args.scene;
    for (given, option) in [
        (scene.mode.is_some_and(|m| m != MlhmRenderMode::Mesh), "--mode"),
        (scene.no_shadows, "--no-shadows"),
    ] {
        if given {
            return Err(crate::applies::refuse(option, "relief render", "relief mesh"));
        }
    }
    if scene.node_budget.is_some() {
        return Err(crate::applies::refuse(
            "--node-budget",
            "relief view and relief flythrough",
            "relief mesh",
        ));
    }
    let lod = args.lod.unwrap_or(LodChoice::Auto);
    if lod != LodChoice::Auto && args.scene.tau.is_some() {
        bail!("--tau applies to --lod auto, not to a fixed level");
    }
    let load_started = Instant::now();
    let (mut scene, camera) = open_stacks(&args.scene, "relief mesh")?;
    let load_ms = outputs::ms_since(load_started);
    let levels = scene.mesher.level_count();
    let bar = progress::spinner("meshing");
    let mesh_started = Instant::now();
    let (mesh, mesh_stats): (TerrainMesh, MeshStats) = match lod {
        LodChoice::Level(level) => {
            if level >= levels {
                bail!(
                    "level of detail {level} is beyond the mipmap: its levels are 0 to {}",
                    levels - 1
                );
            }
            scene.mesher.mesh_level(level)?
        }
        LodChoice::Auto => {
            let tau = args.scene.tau.unwrap_or(DEFAULT_TAU_PX);
            scene.mesher.mesh_for_camera(&camera, tau)
        }
    };
    let nodes = mesh_stats.nodes;
    let mesh_ms = outputs::ms_since(mesh_started);
    bar.finish_and_clear();
    let write_started = Instant::now();
    relief_io::write_bytes_atomically(&args.output, &format.to_bytes(&mesh)?)?;
    let write_ms = outputs::ms_since(write_started);
    let count = |name: &str| {
        mesh.part(name).map_or((0, 0), |p| (p.vertex_count(), p.quads.len() + p.triangles.len()))
    };
    let (solid_vertices, solid_faces) = count("solid");
    let (water_vertices, water_faces) = count("water");
    eprintln!(
        "wrote {} (solid: {solid_vertices} vertices, {solid_faces} faces; water: \
         {water_vertices} vertices, {water_faces} faces; {})",
        args.output.display(),
        match lod {
            LodChoice::Level(level) => format!("level {level} of {levels}"),
            LodChoice::Auto => format!("{nodes} octree nodes for the camera"),
        }
    );
    if let Some(path) = &args.stats {
        let stacks = &scene.mesher.mipmap().levels()[0];
        // The level meshed (for --lod auto, the finest).
        let level_stacks = match lod {
            LodChoice::Level(level) => &scene.mesher.mipmap().levels()[level],
            LodChoice::Auto => stacks,
        };
        let stats = json!({
            "levels": levels,
            "lod": match lod { LodChoice::Level(l) => json!(l), LodChoice::Auto => json!("auto") },
            "nodes": nodes,
            "nodes_per_level": &mesh_stats.per_level[..levels.min(16)],
            "select_ms": mesh_stats.select_ms,
            "nodes_ms": mesh_stats.mesh_ms,
            "join_ms": mesh_stats.join_ms,
            "node_ms": if nodes > 0 { mesh_stats.mesh_ms / nodes as f64 } else { 0.0 },
            "threads": rayon::current_num_threads(),
            "mipmap_bytes": scene.mesher.mipmap().memory_bytes(),
            "solid_vertices": solid_vertices,
            "solid_faces": solid_faces,
            "water_vertices": water_vertices,
            "water_faces": water_faces,
            "solid_m3": mesh.part("solid").map_or(0.0, |p| p.enclosed_volume()),
            "water_m3": mesh.part("water").map_or(0.0, |p| p.enclosed_volume()),
            "stacks_solid_m3": stacks.volume(|m| !m.is_liquid()),
            "stacks_water_m3": stacks.volume(|m| m.is_liquid()),
            "level_solid_m3": level_stacks.volume(|m| !m.is_liquid()),
            "level_water_m3": level_stacks.volume(|m| m.is_liquid()),
            "solid_pieces": mesh.part("solid").map_or(0, |p| p.components().len()),
            "water_pieces": mesh.part("water").map_or(0, |p| p.components().len()),
            "load_ms": load_ms,
            "mesh_ms": mesh_ms,
            "write_ms": write_ms,
            "total_ms": outputs::ms_since(started),
        });
        outputs::write_stats(path, &stats)?;
    }
    Ok(())
}

/// The mesh format of `-o`, by its extension.
fn mesh_format(path: &std::path::Path) -> Result<relief_mesh::export::MeshFormat> {
    Ok(relief_mesh::export::MeshFormat::from_path(path)?)
}
