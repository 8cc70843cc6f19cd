//! How a shade map is cut into blocks: the halo its layers need around each block, the largest
//! blocks whose windows fit the memory budget, and the blocks in the order they are written.

use crate::memory::Budget;
use crate::RenderError;
use relief_core::GridGeometry;
use relief_shade::ShadeMapParams;
use std::ops::Range;

/// The largest block side tried: larger blocks gain little, and keep the progress coarse.
pub const MAX_BLOCK: usize = 4096;

/// A block of a shade map: its columns and rows (rows from the south).
pub type Block = (Range<usize>, Range<usize>);

/// The blocks of a shade map and the halo of their windows.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockPlan {
    /// Samples along a block's side (the last ones of a row or column may be shorter).
    pub block: usize,
    /// Samples around a block its window holds (where the raster has them).
    pub halo: usize,
    /// The blocks, the northern row of blocks first, each row from the west: the order of the
    /// tiles of a north-up file.
    pub blocks: Vec<Block>,
    /// Bytes one block's window, maps and buffers take at most.
    pub window_bytes: u64,
}

/// Bytes a window of `window` samples and its block of `block` samples take while shaded:
/// the height field, its tracer's pyramid and void mask, each horizon engine's frames, the
/// block's horizon angles in every direction (found a direction at a time), and the block's
/// bands (made per band of rows, gathered, then handed on: three copies at most).
pub fn window_bytes(params: &ShadeMapParams, window: u64, block: u64) -> u64 {
    let engines = params.horizon_engines() as u64;
    let frames = engines * params.horizon.engine_bytes_per_sample();
    let angles = engines * params.horizon.azimuths as u64 * 4;
    let bands = params.band_names().len() as u64;
    window * (4 + 2 + 1 + frames) + block * (angles + bands * 4 * 3)
}

/// Samples around a block that a window holds for the horizons, where they go on past it to
/// the raster's edge and memory allows: the lanes over the window find most horizons, and the
/// lines' far walks, whose bounds are coarser, start further out.
pub const HORIZON_HALO: usize = 1024;

/// Whether the layers of `params` follow horizons past a window (no radius).
fn far_horizons(params: &ShadeMapParams) -> bool {
    params.horizon_engines() > 0 && params.horizon.radius.is_none()
}

/// The halo the layers of `params` need around a block of a raster whose samples span `span`,
/// placed by `geometry` (see [`ShadeMapParams::halo_samples`]). Errors: a reach that is not
/// finite.
pub fn required_halo(
    params: &ShadeMapParams,
    span: [f32; 2],
    geometry: &GridGeometry,
) -> Result<usize, RenderError> {
    params.halo_samples(span, geometry).ok_or_else(|| {
        RenderError::Unsupported("the suns' rays reach no finite distance".to_string())
    })
}

/// The halo a window is given around a block of its own (one Dask chunk): what the layers
/// need, and [`HORIZON_HALO`] for horizons followed past the window.
pub fn chunk_halo(
    params: &ShadeMapParams,
    span: [f32; 2],
    geometry: &GridGeometry,
) -> Result<usize, RenderError> {
    let needed = required_halo(params, span, geometry)?;
    Ok(needed.max(if far_horizons(params) { HORIZON_HALO } else { 0 }))
}

impl BlockPlan {
    /// The plan of a `width x height` raster whose samples span `span`, placed by `geometry`:
    /// blocks whose sides are multiples of `align` (but for the last ones), as large as the
    /// `budget` allows once `fixed` bytes are taken. Errors: layers whose reach is not finite,
    /// and a budget too small for the smallest blocks.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        width: usize,
        height: usize,
        span: [f32; 2],
        geometry: &GridGeometry,
        params: &ShadeMapParams,
        align: usize,
        budget: &Budget,
        fixed: u64,
    ) -> Result<BlockPlan, RenderError> {
        let needed = required_halo(params, span, geometry)?;
        let align = align.max(1);
        let largest = MAX_BLOCK.max(align).min(width.max(height).div_ceil(align) * align);
        let fits = |block: usize, halo: usize| {
            let (bw, bh) = (block.min(width), block.min(height));
            let window = ((bw + 2 * halo).min(width) * (bh + 2 * halo).min(height)) as u64;
            let bytes = window_bytes(params, window, (bw * bh) as u64);
            (fixed + bytes <= budget.bytes, bytes)
        };
        // The horizons' halo where it fits with any block (the lanes over a window skip by
        // finer bounds than the far walks: on 8192^2, shadow and 8 directions of sky at 1 GiB
        // took 109.6 s in blocks of 2560 with a halo of 512 and 99.7 s in blocks of 2048 with
        // a halo of 1024), else the halo the other layers need.
        let wide = needed.max(if far_horizons(params) { HORIZON_HALO } else { 0 });
        let mut halo = wide;
        let mut block = largest;
        loop {
            let (ok, bytes) = fits(block, halo);
            if ok {
                return Ok(BlockPlan {
                    block,
                    halo,
                    blocks: blocks(width, height, block),
                    window_bytes: bytes,
                });
            }
            if halo > needed && block <= align {
                (halo, block) = (needed, largest);
                continue;
            }
            if block <= align {
                let hint = if halo > 4 * align {
                    format!(
                        "; the halo is the reach of the suns' rays or the --radius, {halo} samples"
                    )
                } else {
                    String::new()
                };
                return Err(RenderError::ShadeOverBudget {
                    block,
                    halo,
                    needed: fixed + bytes,
                    budget: budget.clone(),
                    hint,
                });
            }
            block -= align;
        }
    }

    /// Samples of the largest window.
    pub fn window_samples(&self, width: usize, height: usize) -> u64 {
        let side = |n: usize| (self.block.min(n) + 2 * self.halo).min(n) as u64;
        side(width) * side(height)
    }
}

/// The blocks of `block` samples of a `width x height` raster, aligned to its north-west corner
/// (as the tiles of a north-up file), the northern row first.
pub fn blocks(width: usize, height: usize, block: usize) -> Vec<Block> {
    let mut all = Vec::new();
    for top in (0..height).step_by(block) {
        let rows = height.saturating_sub(top + block)..height - top;
        for left in (0..width).step_by(block) {
            all.push((left..(left + block).min(width), rows.clone()));
        }
    }
    all
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_tile_the_raster_north_first() {
        let all = blocks(10, 7, 4);
        assert_eq!(all[0], (0..4, 3..7));
        assert_eq!(all[2], (8..10, 3..7));
        assert_eq!(all[3], (0..4, 0..3));
        let covered: usize = all.iter().map(|(c, r)| c.len() * r.len()).sum();
        assert_eq!(covered, 70);
    }

    #[test]
    fn the_largest_blocks_that_fit_are_chosen() {
        let params = ShadeMapParams::default();
        let g = GridGeometry { dx: 10.0, dy: 10.0, ..GridGeometry::unit() };
        let budget = |bytes| Budget { bytes, origin: "--max-memory".into() };
        let big = BlockPlan::new(2048, 2048, [0.0, 100.0], &g, &params, 256, &budget(1 << 34), 0)
            .unwrap();
        assert_eq!(big.block, 2048);
        let small =
            BlockPlan::new(2048, 2048, [0.0, 100.0], &g, &params, 256, &budget(40 << 20), 0)
                .unwrap();
        assert!(small.block < 2048 && small.block.is_multiple_of(256), "{}", small.block);
        assert!(small.window_bytes <= 40 << 20);
        let none = BlockPlan::new(2048, 2048, [0.0, 100.0], &g, &params, 256, &budget(1 << 20), 0);
        assert!(matches!(none, Err(RenderError::ShadeOverBudget { .. })));
    }
}
