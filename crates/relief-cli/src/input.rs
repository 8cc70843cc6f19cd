//! Loading the height field a command works on: a file, or the seeded fBm terrain.

use crate::args::InputArgs;
use anyhow::{Context, Result};
use relief_core::{GridGeometry, HeightField};
use relief_sim::{fbm_terrain, FbmParams};
use std::sync::Arc;

/// Reads `args.input` (or generates the default terrain) and applies spacing and z scale.
pub fn load(args: &InputArgs) -> Result<Arc<HeightField>> {
    let field = match &args.input {
        Some(path) => relief_io::read_npy_height_field(path)?,
        None => fbm(args.fbm_size, args.seed)?,
    };
    let field = if args.north_up { field.flip_rows() } else { field };
    let (dx, dy) = args.spacing.unwrap_or((1.0, 1.0));
    let geometry = GridGeometry { dx, dy, z_scale: args.z_scale, ..*field.geometry() };
    Ok(Arc::new(field.with_geometry(geometry).context("invalid placement")?))
}

/// The seeded fBm terrain of `size` x `size` samples.
pub fn fbm(size: usize, seed: u64) -> Result<HeightField> {
    if size == 0 || size > 65536 {
        anyhow::bail!("terrain size {size} must be between 1 and 65536");
    }
    fbm_terrain(size, size, seed, &FbmParams::for_size(size, size))
        .context("generating fBm terrain")
}
