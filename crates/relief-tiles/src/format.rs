//! The on-disk format of a tile store (docs/tile-store.md): a directory of three files.
//!
//! - `index.json`: the [`StoreHeader`] (format name, version, whether the build finished, the
//!   raster's size and geometry, the tile size, the precision, the inputs it was built from);
//! - `tiles.table`: one 32-byte [`TileRecord`] per tile, in [`PyramidLayout::index_of`] order;
//!   all zeros for a tile not built yet;
//! - `tiles.data`: one fixed-size slot per tile in the same order, `(tile + 2)^2` samples, row
//!   0 south, little-endian f32 or f16, NaN for voids. Slots are at fixed offsets, so the file
//!   can be memory-mapped and a build can resume at any tile;
//! - with an ortho photo, its pyramid in `texture.table` and `texture.data`
//!   ([`crate::TextureHeader`], described by the index's optional `texture` field).

use crate::{PyramidLayout, TileError, TileId};
use relief_core::{GridGeometry, Precision};
use serde::{Deserialize, Serialize};
use std::path::Path;
use xxhash_rust::xxh3::xxh3_64;

/// The `format` of every store's index.
pub const FORMAT_NAME: &str = "relief-tile-store";
/// The version this code writes and reads.
pub const FORMAT_VERSION: u32 = 1;
/// The index's file name inside the store.
pub const INDEX_FILE: &str = "index.json";
/// The tile table's file name.
pub const TABLE_FILE: &str = "tiles.table";
/// The tile data's file name.
pub const DATA_FILE: &str = "tiles.data";
/// Bytes of one [`TileRecord`].
pub const RECORD_BYTES: usize = 32;

/// Bytes of one stored sample at `precision`.
pub fn sample_bytes(precision: Precision) -> usize {
    match precision {
        Precision::F32 => 4,
        Precision::F16 => 2,
    }
}

/// The name of `precision` in the index and on the command line.
pub fn precision_name(precision: Precision) -> &'static str {
    match precision {
        Precision::F32 => "f32",
        Precision::F16 => "f16",
    }
}

/// Writes `samples` into `out` (`samples.len() * sample_bytes(precision)` bytes), little
/// endian; f16 rounds each value to the nearest half.
pub fn encode_samples(precision: Precision, samples: &[f32], out: &mut [u8]) {
    match precision {
        Precision::F32 => {
            for (v, o) in samples.iter().zip(out.chunks_exact_mut(4)) {
                o.copy_from_slice(&v.to_le_bytes());
            }
        }
        Precision::F16 => {
            for (v, o) in samples.iter().zip(out.chunks_exact_mut(2)) {
                o.copy_from_slice(&half::f16::from_f32(*v).to_le_bytes());
            }
        }
    }
}

/// Reads the samples of `bytes` into `out`.
pub fn decode_samples(precision: Precision, bytes: &[u8], out: &mut [f32]) {
    match precision {
        Precision::F32 => {
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
                *o = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            }
        }
        Precision::F16 => {
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(2)) {
                *o = half::f16::from_le_bytes([b[0], b[1]]).to_f32();
            }
        }
    }
}

/// The index writes a precision as its name.
mod precision_serde {
    use super::{precision_name, Precision};
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(p: &Precision, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(precision_name(*p))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Precision, D::Error> {
        match String::deserialize(d)?.as_str() {
            "f32" => Ok(Precision::F32),
            "f16" => Ok(Precision::F16),
            other => Err(serde::de::Error::custom(format!("unknown precision '{other}'"))),
        }
    }
}

/// One input file as the build saw it: a resumed build refuses inputs that changed.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SourceFile {
    /// The path as given.
    pub path: String,
    /// Its size in bytes.
    pub bytes: u64,
    /// Its modification time, nanoseconds since the Unix epoch (0 where unknown).
    pub modified_ns: u128,
}

/// The grid's placement, as in [`GridGeometry`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StoredGeometry {
    /// Texel size along x (east).
    pub dx: f64,
    /// Texel size along y (north).
    pub dy: f64,
    /// World z of a sample value of 1.
    pub z_scale: f64,
    /// World (x, y) of the raster's south-west corner.
    pub origin: [f64; 2],
}

impl From<GridGeometry> for StoredGeometry {
    fn from(g: GridGeometry) -> Self {
        StoredGeometry { dx: g.dx, dy: g.dy, z_scale: g.z_scale, origin: [g.origin.x, g.origin.y] }
    }
}

impl From<StoredGeometry> for GridGeometry {
    fn from(g: StoredGeometry) -> Self {
        GridGeometry {
            dx: g.dx,
            dy: g.dy,
            z_scale: g.z_scale,
            origin: relief_core::DVec2::new(g.origin[0], g.origin[1]),
        }
    }
}

/// The store's `index.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoreHeader {
    /// Always `"relief-tile-store"`.
    pub format: String,
    /// The format version, 1.
    pub version: u32,
    /// Whether every tile was built and checked. A store that is not complete is being built
    /// or was interrupted: renderers refuse it, `relief tile` resumes it.
    pub complete: bool,
    /// Samples per row of level 0.
    pub width: u64,
    /// Rows of level 0.
    pub height: u64,
    /// Samples along a tile's side (its ring of one more sample on each side not counted).
    pub tile: u32,
    /// Levels of the pyramid.
    pub levels: u32,
    /// How samples are stored: `f32`, or `f16` (rounded to the nearest half).
    #[serde(with = "precision_serde")]
    pub precision: Precision,
    /// The grid's placement in the world.
    pub geometry: StoredGeometry,
    /// The inputs, in the order given.
    pub sources: Vec<SourceFile>,
    /// The ortho photo's pyramid, when the store has one (`texture.table`, `texture.data`);
    /// absent from the index of a store without, as in stores written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<crate::TextureHeader>,
    /// Where the raster lies on the earth (its source's GeoTIFF tags), when the source was
    /// georeferenced; absent from stores written before it was kept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub georeference: Option<crate::StoredGeoreference>,
    /// The source's nodata value, when it declared a finite one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nodata: Option<f64>,
}

impl StoreHeader {
    /// The pyramid's layout.
    pub fn layout(&self) -> PyramidLayout {
        PyramidLayout::new(self.width, self.height, self.tile)
    }

    /// Reads and checks `index.json` of the store at `dir`.
    pub fn read(dir: &Path) -> Result<StoreHeader, TileError> {
        let path = dir.join(INDEX_FILE);
        let text = std::fs::read_to_string(&path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound && dir.is_dir() {
                let reason = format!("not a tile store (no {INDEX_FILE})");
                TileError::Format { path: dir.to_path_buf(), reason }
            } else {
                TileError::io(&path, e)
            }
        })?;
        let format = |reason: String| TileError::Format { path: path.clone(), reason };
        let header: StoreHeader =
            serde_json::from_str(&text).map_err(|e| format(format!("not a tile index: {e}")))?;
        if header.format != FORMAT_NAME {
            return Err(format(format!("format is '{}', not '{FORMAT_NAME}'", header.format)));
        }
        if header.version != FORMAT_VERSION {
            return Err(format(format!(
                "version {} (this relief reads version {FORMAT_VERSION})",
                header.version
            )));
        }
        if header.width == 0 || header.height == 0 || header.tile < crate::layout::MIN_TILE {
            return Err(format("empty raster or tile size below 4".into()));
        }
        if GridGeometry::from(header.geometry).validate().is_err() {
            return Err(format("invalid geometry".into()));
        }
        if header.layout().level_count() != header.levels {
            return Err(format(format!("{} levels do not fit the raster and tile", header.levels)));
        }
        if let Some(texture) = &header.texture {
            texture.check().map_err(format)?;
        }
        Ok(header)
    }

    /// Writes `index.json` of the store at `dir` (through a temporary file and a rename, so the
    /// index is always whole).
    pub fn write(&self, dir: &Path) -> Result<(), TileError> {
        let path = dir.join(INDEX_FILE);
        let temp = dir.join(format!("{INDEX_FILE}.tmp"));
        let text = serde_json::to_string_pretty(self).expect("a header serializes");
        std::fs::write(&temp, text + "\n").map_err(|e| TileError::io(&temp, e))?;
        std::fs::File::open(&temp)
            .and_then(|f| f.sync_all())
            .map_err(|e| TileError::io(&temp, e))?;
        std::fs::rename(&temp, &path).map_err(|e| TileError::io(&path, e))
    }
}

/// What the table says about one tile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TileRecord {
    /// Lowest valid stored sample (ring included); +inf when every sample is a void.
    pub min: f32,
    /// Highest valid stored sample (ring included); -inf when every sample is a void.
    pub max: f32,
    /// Largest vertical distance, in sample units, between a level-0 sample under the tile and
    /// the tile's sample over it (0 on level 0): the tile's world-space error before z scale.
    pub error: f32,
    /// Whether some stored sample is a void.
    pub has_voids: bool,
    /// XXH3-64 of the tile's slot in `tiles.data`.
    pub checksum: u64,
}

impl TileRecord {
    /// Whether every stored sample is a void (no surface in this tile).
    pub fn is_void(&self) -> bool {
        self.min > self.max
    }

    /// The record's 32 bytes: min, max, error (f32), flags (u32: 1 built, 2 has voids), the
    /// data checksum (u64), and an XXH3-64 of the 24 bytes before it.
    pub fn to_bytes(&self) -> [u8; RECORD_BYTES] {
        let mut b = [0u8; RECORD_BYTES];
        b[0..4].copy_from_slice(&self.min.to_le_bytes());
        b[4..8].copy_from_slice(&self.max.to_le_bytes());
        b[8..12].copy_from_slice(&self.error.to_le_bytes());
        let flags = 1u32 | if self.has_voids { 2 } else { 0 };
        b[12..16].copy_from_slice(&flags.to_le_bytes());
        b[16..24].copy_from_slice(&self.checksum.to_le_bytes());
        let check = xxh3_64(&b[..24]);
        b[24..32].copy_from_slice(&check.to_le_bytes());
        b
    }

    /// The record in `b`: `Ok(None)` for a tile not built yet (all zeros), an error message
    /// for bytes that are neither.
    pub fn from_bytes(b: &[u8; RECORD_BYTES]) -> Result<Option<TileRecord>, String> {
        if b.iter().all(|&x| x == 0) {
            return Ok(None);
        }
        let u64_at = |k: usize| u64::from_le_bytes(b[k..k + 8].try_into().expect("8 bytes"));
        let f32_at = |k: usize| f32::from_le_bytes(b[k..k + 4].try_into().expect("4 bytes"));
        if u64_at(24) != xxh3_64(&b[..24]) {
            return Err("its table record does not match its checksum".into());
        }
        let flags = u32::from_le_bytes(b[12..16].try_into().expect("4 bytes"));
        if flags & 1 == 0 || flags > 3 {
            return Err(format!("its table record has unknown flags {flags:#x}"));
        }
        Ok(Some(TileRecord {
            min: f32_at(0),
            max: f32_at(4),
            error: f32_at(8),
            has_voids: flags & 2 != 0,
            checksum: u64_at(16),
        }))
    }
}

/// The checksum of a tile's slot bytes.
pub fn slot_checksum(bytes: &[u8]) -> u64 {
    xxh3_64(bytes)
}

/// Offset of a tile's slot in `tiles.data`.
pub fn slot_offset(layout: &PyramidLayout, precision: Precision, id: TileId) -> u64 {
    layout.index_of(id) * slot_bytes(layout, precision)
}

/// Bytes of one slot.
pub fn slot_bytes(layout: &PyramidLayout, precision: Precision) -> u64 {
    (layout.stored_samples() * sample_bytes(precision)) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_round_trip_and_damage_is_noticed() {
        let r = TileRecord { min: -3.5, max: 812.25, error: 1.5, has_voids: true, checksum: 42 };
        let mut b = r.to_bytes();
        assert_eq!(TileRecord::from_bytes(&b), Ok(Some(r)));
        assert_eq!(TileRecord::from_bytes(&[0; RECORD_BYTES]), Ok(None));
        b[5] ^= 1;
        assert!(TileRecord::from_bytes(&b).is_err());
    }

    #[test]
    fn f16_samples_round_trip_to_the_nearest_half() {
        let v = [0.0f32, 1.0, 1234.5, -7.25, f32::NAN];
        let mut bytes = [0u8; 10];
        encode_samples(Precision::F16, &v, &mut bytes);
        let mut back = [0f32; 5];
        decode_samples(Precision::F16, &bytes, &mut back);
        assert_eq!(&back[..4], &[0.0, 1.0, 1234.0, -7.25]);
        assert!(back[4].is_nan());
    }
}
