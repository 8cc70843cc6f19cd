//! `relief mesh`.

use crate::args::*;
use clap::Args;
use std::path::PathBuf;

/// `--lod`: a fixed level or the camera's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LodChoice {
    /// One level everywhere, 0 finest.
    Level(usize),
    /// The levels the camera needs.
    Auto,
}

fn parse_lod(s: &str) -> Result<LodChoice, String> {
    if s == "auto" {
        return Ok(LodChoice::Auto);
    }
    s.parse::<usize>()
        .map(LodChoice::Level)
        .map_err(|_| format!("'{s}' is not a level of detail (expected auto or 0, 1, 2, ...)"))
}

/// `relief mesh`: the scene options of `relief render` (input, camera, --sigma, --tau,
/// --voxel-height), the output, the level of detail and the stage timings. The options of
/// tracers, shading and MLHM rendering are hidden and refused (the sun and exposure, which have
/// defaults, are hidden and unused).
#[derive(Debug, Args)]
#[command(
    mut_arg("tracer", |a| a.hide(true)),
    mut_arg("surface", |a| a.hide(true)),
    mut_arg("mode", |a| a.hide(true)),
    mut_arg("preset", |a| a.hide(true)),
    mut_arg("hierarchy_bounds", |a| a.hide(true)),
    mut_arg("backtrack", |a| a.hide(true)),
    mut_arg("safety", |a| a.hide(true)),
    mut_arg("phi_max", |a| a.hide(true)),
    mut_arg("isotropic", |a| a.hide(true)),
    mut_arg("positive", |a| a.hide(true)),
    mut_arg("linear_surface", |a| a.hide(true)),
    mut_arg("safety_reach", |a| a.hide(true)),
    mut_arg("cache_dir", |a| a.hide(true)),
    mut_arg("no_cache", |a| a.hide(true)),
    mut_arg("sun", |a| a.hide(true)),
    mut_arg("no_shadows", |a| a.hide(true)),
    mut_arg("no_ao", |a| a.hide(true)),
    mut_arg("texture", |a| a.hide(true)),
    mut_arg("exposure", |a| a.hide(true)),
    mut_arg("node_budget", |a| a.hide(true))
)]
pub struct MeshArgs {
    /// The scene and camera (the camera matters with --lod auto).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output mesh: .glb (glTF 2.0 binary), .obj or .ply.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The level of detail, 0 the finest (the stacks themselves), each next level half as
    /// fine; or auto: per octree node, as fine as the camera needs for cells of at most --tau
    /// pixels [default: auto].
    #[arg(long, value_name = "N|auto", value_parser = parse_lod)]
    pub lod: Option<LodChoice>,
    /// Write the stage timings (load_ms, build_ms, mesh_ms, write_ms, total_ms) and the mesh's
    /// counts to this JSON file.
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
}
