//! `relief compare`.

use crate::parse;
use clap::Args;
use std::path::PathBuf;

/// `relief compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The reference depth image (.npy, f32, H x W, +inf where the ray missed), e.g. the exact
    /// tracer's `relief render --depth`.
    pub reference: PathBuf,
    /// The depth image to judge against it, of the same shape.
    pub test: PathBuf,
    /// Print the metrics as one JSON object (psnr_db, null for identical images;
    /// wrong_pixel_fraction; max_rel_error; and the counts).
    #[arg(long)]
    pub json: bool,
    /// The terrain both were rendered from (any input relief render takes): R is the
    /// bounding-box diagonal of its solid and the cell its grid spacing (the larger of DX and
    /// DY). Without --terrain, --diagonal and --cell, R is the largest finite reference depth
    /// and the cell 1.
    #[arg(long, value_name = "IN")]
    pub terrain: Option<PathBuf>,
    /// With --terrain: its texel spacing `DX[,DY]`, as relief render's --spacing.
    #[arg(long, value_parser = parse::spacing, requires = "terrain", allow_hyphen_values = true)]
    pub spacing: Option<(f64, f64)>,
    /// With --terrain: the factor from its samples to world heights, as relief render's
    /// --z-scale [default: 1].
    #[arg(long, value_parser = parse::z_scale, requires = "terrain", allow_hyphen_values = true)]
    pub z_scale: Option<f64>,
    /// R of the PSNR in world units (overrides --terrain's).
    #[arg(long, value_name = "R", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub diagonal: Option<f64>,
    /// A hit more than this far from the reference's (world units, along the ray) is a wrong
    /// pixel (overrides --terrain's grid spacing).
    #[arg(long, value_name = "C", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub cell: Option<f64>,
    /// Memory each depth image (and --terrain) may take, e.g. 512M, 8G (default: half the
    /// machine's or cgroup's memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
}
