//! Shade maps block by block, from rasters of any size: each block is shaded over a window that
//! holds it and the halo its layers need ([`relief_shade::ShadeMapParams::halo_samples`]),
//! while the horizons go on past the window through the whole raster (its far field). So a
//! block's values are those of the whole raster shaded in memory, bit for bit, whatever the
//! blocks: the same code serves `relief shade` on a raster larger than memory, one block a
//! time within `--max-memory`, and a Dask chunk on a worker (`relief.shade_window`).

mod plan;
mod source;

pub use plan::{
    blocks, chunk_halo, required_halo, window_bytes, Block, BlockPlan, HORIZON_HALO, MAX_BLOCK,
};
pub use source::{ShadeSource, DEFAULT_TILE_CACHE};

use crate::RenderError;
use relief_core::{DVec2, GridGeometry, HeightField, Surface};
use relief_shade::horizon::FarField;
use relief_shade::shade_map::{shade_map_region, ShadeMap, ShadeRegion};
use relief_shade::ShadeMapParams;
use relief_trace::{build_tracer, TracerKind};
use std::ops::Range;
use std::sync::Arc;

/// The shade map of the samples of columns `cols` and rows `rows` of `source` (rows from the
/// south), made over a window `halo` samples wider on every side (where the raster has them),
/// its sun rays traced on `surface`. `progress` is called with the samples done. Errors: a
/// window that cannot be read, or the map's own.
pub fn shade_block(
    source: &ShadeSource,
    params: &ShadeMapParams,
    surface: Surface,
    halo: usize,
    cols: Range<usize>,
    rows: Range<usize>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ShadeMap, RenderError> {
    let (width, height) = (source.width(), source.height());
    if cols.is_empty() || rows.is_empty() || cols.end > width || rows.end > height {
        return Err(RenderError::ShadeSource {
            path: source.path().to_path_buf(),
            reason: format!(
                "columns {cols:?} and rows {rows:?} are not a region of its {width} x {height} \
                 samples"
            ),
        });
    }
    let wc = cols.start.saturating_sub(halo)..(cols.end + halo).min(width);
    let wr = rows.start.saturating_sub(halo)..(rows.end + halo).min(height);
    let (samples, void) = source.window(wc.clone(), wr.clone())?;
    let g = source.geometry();
    let origin = g.origin + DVec2::new(wc.start as f64 * g.dx, wr.start as f64 * g.dy);
    let field =
        Arc::new(HeightField::new(wc.len(), wr.len(), samples, GridGeometry { origin, ..g })?);
    let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
    let region = ShadeRegion {
        cols: cols.start - wc.start..cols.end - wc.start,
        rows: rows.start - wr.start..rows.end - wr.start,
        far: Some(FarField { terrain: source, col0: wc.start, row0: wr.start }),
        raster_span: Some(source.span()),
    };
    let mask = void.as_deref().filter(|v| v.contains(&true));
    let columns = cols.len() as u64;
    let map = shade_map_region(&field, &*tracer, mask, params, &region, &|rows| {
        progress(rows * columns)
    })?;
    Ok(map)
}

/// What [`shade_blocks`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BlocksDone {
    /// Blocks shaded.
    pub shaded: usize,
    /// Blocks skipped (done by an earlier run).
    pub skipped: usize,
    /// Rays cast towards the suns.
    pub rays: u64,
}

/// Shades the blocks of `plan` that `skip` does not pass over, one after the other (each in
/// parallel), and hands each map to `sink` with its block. `progress` is called with the
/// samples done, skipped blocks included.
pub fn shade_blocks(
    source: &ShadeSource,
    params: &ShadeMapParams,
    surface: Surface,
    plan: &BlockPlan,
    skip: &dyn Fn(&Block) -> bool,
    sink: &mut dyn FnMut(&Block, ShadeMap) -> Result<(), RenderError>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<BlocksDone, RenderError> {
    let mut done = BlocksDone::default();
    let mut before = 0u64;
    for block in &plan.blocks {
        let samples = (block.0.len() * block.1.len()) as u64;
        if skip(block) {
            done.skipped += 1;
        } else {
            let map = shade_block(
                source,
                params,
                surface,
                plan.halo,
                block.0.clone(),
                block.1.clone(),
                &|n| progress(before + n),
            )?;
            done.rays += map.rays;
            done.shaded += 1;
            sink(block, map)?;
        }
        before += samples;
        progress(before);
    }
    Ok(done)
}
