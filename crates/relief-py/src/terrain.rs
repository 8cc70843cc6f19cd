//! The height field of a north-up heights array: its rows flipped into relief's order (row 0
//! south), placed by a grid geometry, its voids (NaN) resolved as the command line resolves a
//! file's (relief_io's void filling, or holes).

use crate::arrays::ArrayGrid;
use relief_core::{GridGeometry, HeightField};
use relief_io::VoidPolicy;
use std::path::Path;
use std::sync::Arc;

/// Flips the rows of a row-major `width`-column grid: north-up to relief's south-first order
/// and back.
pub fn flip_rows(samples: &[f32], width: usize) -> Vec<f32> {
    samples.chunks_exact(width.max(1)).rev().flatten().copied().collect()
}

/// The height field of `grid` (row 0 its north edge) placed by `geometry`, with its voids
/// filled (nearest valid sample, then smoothed) or kept as holes as `voids` says. The message
/// of an error names the array `heights` (a grid of nothing but voids, for one).
pub fn height_field(
    grid: &ArrayGrid,
    geometry: GridGeometry,
    voids: VoidPolicy,
) -> Result<Arc<HeightField>, String> {
    let samples = flip_rows(&grid.samples, grid.width);
    let name = Path::new("heights");
    let field =
        relief_io::height_field_of_samples(grid.width, grid.height, samples, geometry, name, voids)
            .map_err(|e| e.to_string())?;
    Ok(Arc::new(field))
}
