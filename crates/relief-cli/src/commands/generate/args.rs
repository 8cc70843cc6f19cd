//! `relief generate`: stacks, MLHM scenes and the fBm terrain.

use crate::args::values::*;
use crate::parse;
use clap::{Args, Subcommand};
use std::path::PathBuf;

/// `relief generate`.
#[derive(Debug, Subcommand)]
pub enum GenerateCommand {
    /// Seeded fractional Brownian motion mountains.
    Fbm(FbmArgs),
    /// A multi-layered height map scene (the reference simulator's JSON + .dat).
    Mlhm(MlhmArgs),
    /// A material-stack terrain (Löffler et al. 2011): seeded fBm bedrock with overhangs,
    /// caves and arches, sand on gentle slopes and water below a sea level.
    Stacks(StacksGenArgs),
}

/// `relief generate stacks`.
#[derive(Debug, Args)]
pub struct StacksGenArgs {
    /// Stacks along x (1 to 65536; the paper's benchmark terrain is 2048 x 4096).
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub width: usize,
    /// Stacks along y (1 to 65536).
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub height: usize,
    /// Random seed.
    #[arg(long, default_value = "1", value_parser = seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Distance between neighbouring stacks in metres.
    #[arg(long, value_name = "M", default_value = "2", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub spacing: f64,
    /// Highest height of the terrain in metres (the paper's 512 voxels of 1.5 m).
    #[arg(long, value_name = "M", default_value = "768", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub max_height: f64,
    /// Memory generation may take, e.g. 512M, 8G (default: half the machine's or cgroup's memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// Output: a .stacks file (relief's own material-stack file).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `relief generate mlhm`.
#[derive(Debug, Args)]
pub struct MlhmArgs {
    /// Scene: rivers-rain (fBm hills on a slope, one column per cell), or a carved scene with
    /// overhangs: arches, cave, chasm, overhangs, combined. Every scene is 256 m square.
    #[arg(long, value_name = "NAME")]
    pub scene: String,
    /// Cells per side, 1 to 65536 (the cell size is 256 m / N; not image pixels).
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub size: usize,
    /// Seed of rivers-rain's noise (the carved scenes are fixed shapes and take none)
    /// [default: the reference simulator's].
    #[arg(long, value_parser = seed, allow_hyphen_values = true)]
    pub seed: Option<u64>,
    /// Column slots per cell, 1 to 127 (carved scenes need up to 4; fewer fills their
    /// thinnest air gaps).
    #[arg(long, default_value = "4", value_name = "L", value_parser = max_layers, allow_hyphen_values = true)]
    pub max_layers: usize,
    /// Store the values as f16 (rounded conservatively) instead of f32.
    #[arg(long)]
    pub half: bool,
    /// Memory generation may take, e.g. 512M, 8G (default: half the machine's or cgroup's memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// Output: scene.mlhm (relief's own file, an NPZ archive) or scene.json (the reference
    /// simulator's scene, its .dat written beside it with the same name).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `relief generate fbm`.
#[derive(Debug, Args)]
pub struct FbmArgs {
    /// Terrain samples per side, width and height (1 to 65536; not image pixels).
    #[arg(long, value_name = "N", default_value = "1024", value_parser = terrain_side, allow_hyphen_values = true)]
    pub size: usize,
    /// Random seed.
    #[arg(long, default_value = "1", value_parser = seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Output height file, in the format its extension names: .npy (float32), .tif/.tiff
    /// (float32 GeoTIFF), .asc, .png (16-bit grey: heights rounded to whole units 0..65535)
    /// or .hgt (1201 or 3601 samples only).
    #[arg(short, long)]
    pub output: PathBuf,
}
