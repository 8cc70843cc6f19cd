//! What a cloud-optimised GeoTIFF writer has written so far: its spill and journal, the
//! tile index and the blocks in; taken up from an interrupted writer's files, or started anew.

use crate::geotiff::cog_journal::{Journal, JournalBlock, JournalHeader};
use crate::geotiff::cog_spill::Spill;
use crate::geotiff::cog_tiles::{LevelTiles, TileGrid};
use crate::IoError;
use std::ops::Range;
use std::path::Path;

/// What a writer has written so far, and where.
pub(crate) struct Progress {
    /// Where each full-resolution tile lies in the spill.
    pub(crate) full: LevelTiles,
    /// The blocks in, as (grid columns, grid rows).
    pub(crate) done_blocks: Vec<(Range<usize>, Range<usize>)>,
    /// Whether some sample written was a void.
    pub(crate) voids: bool,
    /// The compressed tiles.
    pub(crate) spill: Spill,
    /// The record of the blocks in, appended to.
    pub(crate) journal: Journal,
}

/// Takes up the spill and journal (at `spill_path`, `journal_path`) an earlier writer of the
/// job `header` left, keeping the blocks whose tiles all lie in the spill, in `full` (the
/// empty index of `grid`); `None` when there are none of this job.
pub(crate) fn resume(
    (spill_path, journal_path): (&Path, &Path),
    header: &JournalHeader,
    grid: TileGrid,
    south_up: bool,
    mut full: LevelTiles,
) -> Result<Option<Progress>, IoError> {
    let Some(mut spill) = Spill::open(spill_path)? else { return Ok(None) };
    let spill_len = spill.len();
    let bands = header.bands.len();
    let (mut done_blocks, mut voids, mut end) = (Vec::new(), false, 0u64);
    let accept = |block: JournalBlock| {
        let Ok(tiles) = grid.block(&block.cols, &block.rows, south_up) else { return false };
        let tiles = tiles.tiles(bands);
        let in_spill = |&(offset, count): &(u64, u32)| {
            count > 0 && offset.checked_add(u64::from(count)).is_some_and(|e| e <= spill_len)
        };
        let fits = tiles.len() == block.tiles.len()
            && block.tiles.iter().all(in_spill)
            && tiles.iter().all(|&(b, tx, ty)| full.get(grid.index(b, tx, ty)).is_none());
        if !fits {
            return false;
        }
        for (&(b, tx, ty), &(offset, count)) in tiles.iter().zip(&block.tiles) {
            full.set(grid.index(b, tx, ty), offset, count);
            end = end.max(offset + u64::from(count));
        }
        done_blocks.push((block.cols, block.rows));
        voids |= block.voids;
        true
    };
    let Some(journal) = Journal::resume(journal_path, header, accept)? else { return Ok(None) };
    // Tiles of blocks not journaled (and overviews of a finish cut short) are dropped.
    spill.truncate(end)?;
    spill.sync()?;
    Ok(Some(Progress { full, done_blocks, voids, spill, journal }))
}

/// Starts the job `header` anew with the empty index `full`: creates (or empties) the spill
/// and journal at `spill_path`, `journal_path`.
pub(crate) fn start(
    (spill_path, journal_path): (&Path, &Path),
    header: &JournalHeader,
    full: LevelTiles,
) -> Result<Progress, IoError> {
    Ok(Progress {
        full,
        done_blocks: Vec::new(),
        voids: false,
        spill: Spill::create(spill_path)?,
        journal: Journal::create(journal_path, header)?,
    })
}
