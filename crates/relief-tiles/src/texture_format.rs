//! The on-disk format of a store's texture pyramid (docs/tile-store.md, "Texture pyramid"):
//! the ortho photo draped over the DEM, in two files beside the height tiles.
//!
//! - `index.json`'s `texture` field: the [`TextureHeader`] (the pyramid's size, tile size and
//!   levels, the texel encoding, where level 0 lies in the world, the photo it came from);
//! - `texture.table`: one 16-byte [`TextureRecord`] per tile, in [`PyramidLayout::index_of`]
//!   order of the texture's own layout; all zeros for a tile not built yet;
//! - `texture.data`: one fixed-size slot per tile in the same order, `(tile + 2)^2` texels
//!   (the tile and a ring of one texel, the edge texel repeated beyond the texture), row 0
//!   south, 3 bytes each: R, G, B in 8-bit sRGB.

use crate::format::SourceFile;
use crate::{PyramidLayout, TileId};
use serde::{Deserialize, Serialize};
use xxhash_rust::xxh3::xxh3_64;

/// The texture table's file name.
pub const TEXTURE_TABLE_FILE: &str = "texture.table";
/// The texture data's file name.
pub const TEXTURE_DATA_FILE: &str = "texture.data";
/// Bytes of one [`TextureRecord`].
pub const TEXTURE_RECORD_BYTES: usize = 16;
/// Bytes of one stored texel.
pub const TEXEL_BYTES: usize = 3;
/// The texel encoding this version writes and reads.
pub const TEXTURE_ENCODING: &str = "srgb8";

/// The `texture` field of a store's `index.json`: an ortho photo's mip pyramid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TextureHeader {
    /// Texels per row of level 0 (the photo's pixels over the DEM).
    pub width: u64,
    /// Rows of level 0.
    pub height: u64,
    /// Texels along a tile's side (its ring of one more texel on each side not counted).
    pub tile: u32,
    /// Levels of the pyramid: level `l + 1` averages 2x2 texels of level `l`, in linear light.
    pub levels: u32,
    /// How texels are stored: `"srgb8"`, R, G, B bytes in sRGB.
    pub encoding: String,
    /// World (x, y) of level 0's south-west corner.
    pub origin: [f64; 2],
    /// World width and height of a level-0 texel.
    pub texel: [f64; 2],
    /// The ortho photo, as the build saw it.
    pub source: SourceFile,
    /// The photo's pixels the pyramid holds: first column, first row (counted from the file's
    /// first row), columns, rows.
    pub window: [u64; 4],
    /// Whether the file's first row is its northernmost.
    pub north_up: bool,
}

impl TextureHeader {
    /// The pyramid's layout.
    pub fn layout(&self) -> PyramidLayout {
        PyramidLayout::new(self.width, self.height, self.tile)
    }

    /// Checks the fields a reader relies on; the reason when one is wrong.
    pub fn check(&self) -> Result<(), String> {
        if self.encoding != TEXTURE_ENCODING {
            return Err(format!(
                "texture encoding '{}' (this relief reads '{TEXTURE_ENCODING}')",
                self.encoding
            ));
        }
        if self.width == 0 || self.height == 0 || self.tile < crate::layout::MIN_TILE {
            return Err("an empty texture or a texture tile below 4 texels".into());
        }
        if self.layout().level_count() != self.levels {
            return Err(format!("{} texture levels do not fit its size and tile", self.levels));
        }
        let finite = self.origin.iter().chain(&self.texel).all(|v| v.is_finite());
        if !finite || self.texel[0] <= 0.0 || self.texel[1] <= 0.0 {
            return Err("invalid texture placement".into());
        }
        Ok(())
    }
}

/// What the texture table says about one tile: the checksum of its slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextureRecord {
    /// XXH3-64 of the tile's slot in `texture.data`.
    pub checksum: u64,
}

impl TextureRecord {
    /// The record's 16 bytes: the data checksum (u64), then an XXH3-64 of those 8 bytes
    /// with the flag byte 1 (built) after them.
    pub fn to_bytes(&self) -> [u8; TEXTURE_RECORD_BYTES] {
        let mut b = [0u8; TEXTURE_RECORD_BYTES];
        b[..8].copy_from_slice(&self.checksum.to_le_bytes());
        let check = record_check(&b[..8]);
        b[8..].copy_from_slice(&check.to_le_bytes());
        b
    }

    /// The record in `b`: `Ok(None)` for a tile not built yet (all zeros), an error message
    /// for bytes that are neither.
    pub fn from_bytes(b: &[u8; TEXTURE_RECORD_BYTES]) -> Result<Option<TextureRecord>, String> {
        if b.iter().all(|&x| x == 0) {
            return Ok(None);
        }
        let u64_at = |k: usize| u64::from_le_bytes(b[k..k + 8].try_into().expect("8 bytes"));
        if u64_at(8) != record_check(&b[..8]) {
            return Err("its texture table record does not match its checksum".into());
        }
        Ok(Some(TextureRecord { checksum: u64_at(0) }))
    }
}

/// The check of a record's first 8 bytes.
fn record_check(checksum: &[u8]) -> u64 {
    let mut bytes = [1u8; 9];
    bytes[..8].copy_from_slice(checksum);
    xxh3_64(&bytes)
}

/// Bytes of one texture slot.
pub fn texture_slot_bytes(layout: &PyramidLayout) -> u64 {
    (layout.stored_samples() * TEXEL_BYTES) as u64
}

/// Offset of a texture tile's slot in `texture.data`.
pub fn texture_slot_offset(layout: &PyramidLayout, id: TileId) -> u64 {
    layout.index_of(id) * texture_slot_bytes(layout)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_round_trip_and_damage_is_noticed() {
        let r = TextureRecord { checksum: 0x1234_5678_9abc_def0 };
        let mut b = r.to_bytes();
        assert_eq!(TextureRecord::from_bytes(&b), Ok(Some(r)));
        assert_eq!(TextureRecord::from_bytes(&[0; TEXTURE_RECORD_BYTES]), Ok(None));
        b[3] ^= 4;
        assert!(TextureRecord::from_bytes(&b).is_err());
    }
}
