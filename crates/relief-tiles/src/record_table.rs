//! A store's table of tile records (the heights' or the texture's), read whole and checked.

use crate::{PyramidLayout, TileError};
use std::path::Path;

/// Reads the table at `path` of one `N`-byte record per tile of `layout`, in the layout's
/// order, each decoded by `decode` (`None` for a tile not built yet); a truncated table or a
/// damaged record is named with its tile.
pub(crate) fn read_record_table<R, const N: usize>(
    path: &Path,
    layout: &PyramidLayout,
    decode: impl Fn(&[u8; N]) -> Result<Option<R>, String>,
) -> Result<Vec<Option<R>>, TileError> {
    let bytes = std::fs::read(path).map_err(|e| TileError::io(path, e))?;
    let name = path.file_name().unwrap_or(path.as_os_str()).to_string_lossy();
    (0..layout.tile_count() as usize)
        .map(|k| {
            let corrupt = |reason: String| TileError::Corrupt {
                path: path.to_path_buf(),
                tile: layout.id_at(k as u64),
                reason,
            };
            let b: &[u8; N] = bytes
                .get(k * N..(k + 1) * N)
                .and_then(|b| b.try_into().ok())
                .ok_or_else(|| corrupt(format!("{name} is truncated")))?;
            decode(b).map_err(corrupt)
        })
        .collect()
}
