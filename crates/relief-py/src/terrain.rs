//! The height field of a north-up heights array: its rows flipped into relief's order (row 0
//! south), placed by a grid geometry, its voids (NaN) resolved as the command line resolves a
//! file's (relief_io's void filling, or holes).

use crate::arrays::ArrayGrid;
use relief_core::{GridGeometry, HeightField};
use relief_io::{IoError, VoidPolicy};
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
    let (width, height) = (grid.width, grid.height);
    let mut samples = flip_rows(&grid.samples, width);
    let name = Path::new("heights");
    let invalid =
        |reason: String| IoError::InvalidData { path: name.to_path_buf(), reason }.to_string();
    let has_voids = samples.iter().any(|v| v.is_nan());
    if has_voids && samples.iter().all(|v| v.is_nan()) {
        return Err(invalid("every sample is a void (nodata)".into()));
    }
    let holes = match voids {
        VoidPolicy::Fill if has_voids => {
            relief_io::fill_voids(width, height, &mut samples);
            None
        }
        VoidPolicy::Hole if has_voids => {
            let holes: Vec<bool> = samples.iter().map(|v| v.is_nan()).collect();
            samples.iter_mut().filter(|v| v.is_nan()).for_each(|v| *v = 0.0);
            Some(holes)
        }
        _ => None,
    };
    let field =
        HeightField::new(width, height, samples, geometry).map_err(|e| invalid(e.to_string()))?;
    let field = match holes {
        Some(holes) => field.with_holes(holes).map_err(|e| invalid(e.to_string()))?,
        None => field,
    };
    Ok(Arc::new(field))
}
