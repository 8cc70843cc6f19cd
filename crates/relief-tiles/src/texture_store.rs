//! Reading a store's texture pyramid: its table at open, tiles on request, each checked
//! against its checksum.

use crate::record_table::read_record_table;
use crate::texture_format::{
    texture_slot_bytes, texture_slot_offset, TextureHeader, TextureRecord, TEXTURE_DATA_FILE,
    TEXTURE_TABLE_FILE,
};
use crate::{PyramidLayout, StoreHeader, TileError, TileId};
use std::fs::File;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

/// The texture pyramid of a store, opened for reading.
#[derive(Debug)]
pub struct TextureStore {
    dir: PathBuf,
    header: TextureHeader,
    layout: PyramidLayout,
    data: File,
    records: Vec<Option<TextureRecord>>,
}

/// One texture tile in memory: its texels and its ring, as stored.
#[derive(Debug)]
pub struct TextureTile {
    /// Which tile.
    pub id: TileId,
    /// `(tile + 2)^2` texels, row 0 south, R, G, B bytes in sRGB.
    pub texels: Vec<u8>,
    /// Bytes it holds.
    pub bytes: u64,
}

impl TextureStore {
    /// Opens the texture pyramid of the store at `dir`, whose index is `header`; `None` when
    /// the store has no texture. Fails when the texture's files are missing or damaged, or
    /// when a tile was never built.
    pub fn open(dir: &Path, header: &StoreHeader) -> Result<Option<TextureStore>, TileError> {
        let Some(texture) = &header.texture else { return Ok(None) };
        let format = |reason: String| TileError::Format { path: dir.join("index.json"), reason };
        texture.check().map_err(format)?;
        let layout = texture.layout();
        let records = read_texture_table(&dir.join(TEXTURE_TABLE_FILE), &layout)?;
        let done = records.iter().filter(|r| r.is_some()).count() as u64;
        if done != layout.tile_count() {
            return Err(TileError::Incomplete {
                path: dir.to_path_buf(),
                done,
                total: layout.tile_count(),
            });
        }
        let path = dir.join(TEXTURE_DATA_FILE);
        let data = File::open(&path).map_err(|e| TileError::io(&path, e))?;
        Ok(Some(TextureStore {
            dir: dir.to_path_buf(),
            header: texture.clone(),
            layout,
            data,
            records,
        }))
    }

    /// The texture's part of the index.
    pub fn header(&self) -> &TextureHeader {
        &self.header
    }

    /// The pyramid's layout.
    pub fn layout(&self) -> &PyramidLayout {
        &self.layout
    }

    /// Bytes a loaded tile holds.
    pub fn tile_bytes(&self) -> u64 {
        texture_slot_bytes(&self.layout)
    }

    /// Reads texture tile `id` and checks it against its checksum.
    pub fn load(&self, id: TileId) -> Result<TextureTile, TileError> {
        let path = self.dir.join(TEXTURE_DATA_FILE);
        let record =
            self.records[self.layout.index_of(id) as usize].ok_or_else(|| TileError::Corrupt {
                path: self.dir.join(TEXTURE_TABLE_FILE),
                tile: id,
                reason: "the texture tile was never built".into(),
            })?;
        let texels = read_texture_slot(&self.data, &path, &self.layout, id, &record)?;
        Ok(TextureTile { id, bytes: texels.len() as u64, texels })
    }
}

/// Reads the whole texture table, checking every record.
pub(crate) fn read_texture_table(
    path: &Path,
    layout: &PyramidLayout,
) -> Result<Vec<Option<TextureRecord>>, TileError> {
    read_record_table(path, layout, TextureRecord::from_bytes)
}

/// Reads the slot of texture tile `id`, checked against its record's checksum.
pub(crate) fn read_texture_slot(
    data: &File,
    path: &Path,
    layout: &PyramidLayout,
    id: TileId,
    record: &TextureRecord,
) -> Result<Vec<u8>, TileError> {
    let corrupt = |reason: String| TileError::Corrupt {
        path: path.to_path_buf(),
        tile: id,
        reason: format!("texture tile: {reason}"),
    };
    let mut bytes = vec![0u8; texture_slot_bytes(layout) as usize];
    data.read_exact_at(&mut bytes, texture_slot_offset(layout, id)).map_err(|e| {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            corrupt(format!("{TEXTURE_DATA_FILE} is truncated"))
        } else {
            TileError::io(path, e)
        }
    })?;
    if crate::format::slot_checksum(&bytes) != record.checksum {
        return Err(corrupt("its texels do not match their checksum".into()));
    }
    Ok(bytes)
}
