//! Building a store's texture pyramid from an ortho photo read row by row, in bounded memory
//! and resumably, after the height tiles.
//!
//! Level 0 is cut from bands of `tile + 2` rows of the photo's window (a tile row and its
//! ring), read in the file's order: from the north for a north-up photo, so the rows of tiles
//! are built from the north down; only a band and one row of the file are in memory. Each
//! coarser level is made from bands of the level below, read back from the store: every texel
//! the average of the (up to) 2x2 texels under it, in linear light (each byte decoded from
//! sRGB, averaged, encoded back and rounded to the nearest byte). As for the heights, a tile's
//! slot is written and synced before its record, so a build that stops resumes where it was.

use crate::format::{slot_checksum, SourceFile};
use crate::sized_file::open_sized;
use crate::texture_format::{
    texture_slot_bytes, texture_slot_offset, TextureHeader, TextureRecord, TEXEL_BYTES,
    TEXTURE_DATA_FILE, TEXTURE_ENCODING, TEXTURE_RECORD_BYTES, TEXTURE_TABLE_FILE,
};
use crate::texture_placement::TexturePlacement;
use crate::texture_store::{read_texture_slot, read_texture_table};
use crate::{PyramidLayout, TileError, TileId};
use rayon::prelude::*;
use relief_core::colour::{linear_to_srgb8, srgb8_to_linear_table};
use relief_io::OrthoRows;
use std::collections::HashMap;
use std::fs::File;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

/// Texture tiles cut and written at once.
const GROUP_TILES: usize = 16;

/// An ortho photo to drape over a store's DEM: its rows, where it lies, and the file.
pub struct TextureInput<'a> {
    /// The photo, read row by row.
    pub rows: &'a mut dyn OrthoRows,
    /// Its window over the DEM and its world placement ([`crate::place_ortho`]).
    pub placement: TexturePlacement,
    /// The file, as the build saw it (a resumed build refuses a changed photo).
    pub source: SourceFile,
}

impl TextureInput<'_> {
    /// The index's `texture` field for a pyramid of this photo in tiles of `tile` texels.
    pub fn header(&self, tile: u32) -> TextureHeader {
        let [_, _, width, height] = self.placement.window;
        TextureHeader {
            width,
            height,
            tile,
            levels: PyramidLayout::new(width, height, tile).level_count(),
            encoding: TEXTURE_ENCODING.into(),
            origin: self.placement.origin,
            texel: self.placement.texel,
            source: self.source.clone(),
            window: self.placement.window,
            north_up: self.placement.north_up,
        }
    }
}

/// The bytes the texture build holds at most for a window `width` texels wide of a photo
/// `file_width` pixels wide, in tiles of `tile`: a band of level 0 twice (kept rows and the
/// band cut from them) and a row of the file, or a band of fine rows with the coarse band made
/// from them, plus one group of tiles.
pub fn texture_working_set_bytes(width: u64, file_width: u64, tile: u32) -> u64 {
    let side = tile as u64 + 2;
    let texel = TEXEL_BYTES as u64;
    let level0 = 2 * side * width * texel + file_width * texel;
    let coarse = 2 * side * width * texel + side * width.div_ceil(2) * texel;
    level0.max(coarse) + GROUP_TILES as u64 * side * side * texel
}

/// The texture's files while they are built.
struct TextureWriter {
    dir: PathBuf,
    layout: PyramidLayout,
    table: File,
    data: File,
    records: Vec<Option<TextureRecord>>,
}

/// Builds (or resumes) the texture pyramid `header` of the store at `dir` from `rows`,
/// reporting the tiles done to `progress`; returns the tiles this run built.
pub(crate) fn build_texture(
    dir: &Path,
    header: &TextureHeader,
    rows: &mut dyn OrthoRows,
    progress: &mut dyn FnMut(u64),
) -> Result<u64, TileError> {
    let layout = header.layout();
    let mut writer = TextureWriter::open(dir, &layout)?;
    let mut built = 0;
    built += build_level0(&mut writer, header, rows, progress)?;
    for level in 1..layout.level_count() {
        let (_, tiles_y) = layout.tiles_of(level);
        for row in 0..tiles_y {
            if writer.band_done(level, row) {
                continue;
            }
            let band = coarse_band(&writer, level, row)?;
            built += writer.write_band(&band, level, row)?;
            progress(writer.done());
        }
    }
    let done = writer.done();
    if done != layout.tile_count() {
        return Err(TileError::Incomplete {
            path: dir.to_path_buf(),
            done,
            total: layout.tile_count(),
        });
    }
    Ok(built)
}

impl TextureWriter {
    fn open(dir: &Path, layout: &PyramidLayout) -> Result<Self, TileError> {
        let open = |name: &str, len: u64| open_sized(&dir.join(name), len);
        let count = layout.tile_count();
        let table = open(TEXTURE_TABLE_FILE, count * TEXTURE_RECORD_BYTES as u64)?;
        let data = open(TEXTURE_DATA_FILE, count * texture_slot_bytes(layout))?;
        let records = read_texture_table(&dir.join(TEXTURE_TABLE_FILE), layout)?;
        Ok(TextureWriter { dir: dir.to_path_buf(), layout: layout.clone(), table, data, records })
    }

    fn done(&self) -> u64 {
        self.records.iter().filter(|r| r.is_some()).count() as u64
    }

    fn band_done(&self, level: u32, row: u32) -> bool {
        let (tiles_x, _) = self.layout.tiles_of(level);
        (0..tiles_x).all(|col| {
            self.records[self.layout.index_of(TileId { level, col, row }) as usize].is_some()
        })
    }

    /// Cuts the missing tiles of one row of tiles from `band` and writes them; returns how
    /// many.
    fn write_band(&mut self, band: &TexelBand, level: u32, row: u32) -> Result<u64, TileError> {
        let (tiles_x, _) = self.layout.tiles_of(level);
        let todo: Vec<TileId> = (0..tiles_x)
            .map(|col| TileId { level, col, row })
            .filter(|id| self.records[self.layout.index_of(*id) as usize].is_none())
            .collect();
        for group in todo.chunks(GROUP_TILES) {
            let tiles: Vec<(TileId, Vec<u8>)> =
                group.par_iter().map(|&id| (id, cut_tile(&self.layout, band, id))).collect();
            self.write_tiles(&tiles)?;
        }
        Ok(todo.len() as u64)
    }

    /// Writes a group of tiles, syncs them, then writes and syncs their records.
    fn write_tiles(&mut self, tiles: &[(TileId, Vec<u8>)]) -> Result<(), TileError> {
        let data_path = self.dir.join(TEXTURE_DATA_FILE);
        for (id, bytes) in tiles {
            let offset = texture_slot_offset(&self.layout, *id);
            self.data.write_all_at(bytes, offset).map_err(|e| TileError::io(&data_path, e))?;
        }
        self.data.sync_data().map_err(|e| TileError::io(&data_path, e))?;
        let table_path = self.dir.join(TEXTURE_TABLE_FILE);
        for (id, bytes) in tiles {
            let index = self.layout.index_of(*id);
            let record = TextureRecord { checksum: slot_checksum(bytes) };
            self.table
                .write_all_at(&record.to_bytes(), index * TEXTURE_RECORD_BYTES as u64)
                .map_err(|e| TileError::io(&table_path, e))?;
            self.records[index as usize] = Some(record);
        }
        self.table.sync_data().map_err(|e| TileError::io(&table_path, e))
    }
}

/// Rows `[first, first + rows)` of one level, `width` texels each, 3 sRGB bytes per texel.
struct TexelBand {
    first: i64,
    width: usize,
    rows: usize,
    texels: Vec<u8>,
}

impl TexelBand {
    /// Texel (col, row) of the level, the edge texel repeated beyond the level.
    fn at(&self, col: i64, row: i64) -> &[u8] {
        let c = col.clamp(0, self.width as i64 - 1) as usize;
        let r = (row.clamp(self.first, self.first + self.rows as i64 - 1) - self.first) as usize;
        let k = (c + r * self.width) * TEXEL_BYTES;
        &self.texels[k..k + TEXEL_BYTES]
    }
}

/// The stored texels of tile `id` cut from `band`.
fn cut_tile(layout: &PyramidLayout, band: &TexelBand, id: TileId) -> Vec<u8> {
    let side = layout.stored_side();
    let (c0, r0) = layout.stored_origin(id);
    let mut bytes = Vec::with_capacity(side * side * TEXEL_BYTES);
    for r in 0..side as i64 {
        for c in 0..side as i64 {
            bytes.extend_from_slice(band.at(c0 + c, r0 + r));
        }
    }
    bytes
}

/// Builds level 0 from the photo, a row of tiles at a time in the file's row order.
fn build_level0(
    writer: &mut TextureWriter,
    header: &TextureHeader,
    rows: &mut dyn OrthoRows,
    progress: &mut dyn FnMut(u64),
) -> Result<u64, TileError> {
    let layout = writer.layout.clone();
    let [col0, row0, width, height] = header.window;
    let (t, h) = (layout.tile() as i64, height as i64);
    let (_, tiles_y) = layout.tiles_of(0);
    if (0..tiles_y).all(|row| writer.band_done(0, row)) {
        return Ok(0);
    }
    let order: Vec<u32> =
        if header.north_up { (0..tiles_y).rev().collect() } else { (0..tiles_y).collect() };
    let file_width = rows.info().width as usize;
    let mut file_row = vec![[0u8; 3]; file_width];
    let mut next_file_row = 0u64;
    // Texture rows read and still needed, by texture row (0 south).
    let mut kept: HashMap<i64, Vec<u8>> = HashMap::new();
    let mut built = 0;
    for row in order {
        let (lo, hi) = ((row as i64 * t - 1).max(0), (row as i64 * t + t + 1).min(h));
        kept.retain(|&r, _| (lo..hi).contains(&r));
        while (lo..hi).any(|r| !kept.contains_key(&r)) {
            if next_file_row >= row0 + height {
                return Err(TileError::Invalid(format!(
                    "{}: the photo ended before its window's rows",
                    rows.info().path.display()
                )));
            }
            rows.read_next_row(&mut file_row)?;
            let f = next_file_row;
            next_file_row += 1;
            if f < row0 {
                continue;
            }
            let r =
                if header.north_up { (height - 1 - (f - row0)) as i64 } else { (f - row0) as i64 };
            let window = &file_row[col0 as usize..(col0 + width) as usize];
            kept.insert(r, window.iter().flatten().copied().collect());
        }
        if writer.band_done(0, row) {
            continue;
        }
        let mut texels = Vec::with_capacity((hi - lo) as usize * width as usize * TEXEL_BYTES);
        for r in lo..hi {
            texels.extend_from_slice(&kept[&r]);
        }
        let band = TexelBand { first: lo, width: width as usize, rows: (hi - lo) as usize, texels };
        built += writer.write_band(&band, 0, row)?;
        progress(writer.done());
    }
    Ok(built)
}

/// The rows of tile row `row` of `level` (with its ring), each texel the linear-light average
/// of the texels under it on the level below, read back from the store.
fn coarse_band(writer: &TextureWriter, level: u32, row: u32) -> Result<TexelBand, TileError> {
    let layout = &writer.layout;
    let t = layout.tile() as i64;
    let (width, level_h) = layout.level_size(level);
    let (fine_w, fine_h) = layout.level_size(level - 1);
    let first = (row as i64 * t - 1).max(0);
    let end = (row as i64 * t + t + 1).min(level_h as i64);
    let fine_first = 2 * first as u64;
    let fine_end = (2 * end as u64).min(fine_h);
    let fine = read_level_rows(writer, level - 1, fine_first, fine_end)?;
    let (width, fine_w) = (width as usize, fine_w as usize);
    let fine_rows = (fine_end - fine_first) as usize;
    let rows = (end - first) as usize;
    let mut texels = vec![0u8; rows * width * TEXEL_BYTES];
    let linear = srgb8_to_linear_table();
    texels.par_chunks_mut(width * TEXEL_BYTES).enumerate().for_each(|(r, out)| {
        for (c, texel) in out.chunks_exact_mut(TEXEL_BYTES).enumerate() {
            let mut sum = [0f32; 3];
            let mut n = 0;
            for (dc, dr) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (fc, fr) = (2 * c + dc, 2 * r + dr);
                if fc < fine_w && fr < fine_rows {
                    let k = (fc + fr * fine_w) * TEXEL_BYTES;
                    for (s, b) in sum.iter_mut().zip(&fine[k..k + TEXEL_BYTES]) {
                        *s += linear[*b as usize];
                    }
                    n += 1;
                }
            }
            for (o, s) in texel.iter_mut().zip(sum) {
                *o = linear_to_srgb8(s / n as f32);
            }
        }
    });
    Ok(TexelBand { first, width, rows, texels })
}

/// Rows `[first, end)` of `level` (their tiles' inner texels), read back from the store and
/// checked against their checksums.
fn read_level_rows(
    writer: &TextureWriter,
    level: u32,
    first: u64,
    end: u64,
) -> Result<Vec<u8>, TileError> {
    let layout = &writer.layout;
    let (width, _) = layout.level_size(level);
    let (tiles_x, _) = layout.tiles_of(level);
    let t = layout.tile() as u64;
    let side = layout.stored_side();
    let width = width as usize;
    let mut out = vec![0u8; (end - first) as usize * width * TEXEL_BYTES];
    let data_path = writer.dir.join(TEXTURE_DATA_FILE);
    for tile_row in (first / t) as u32..=((end - 1) / t) as u32 {
        let pieces: Vec<Result<(u32, Vec<u8>), TileError>> = (0..tiles_x)
            .into_par_iter()
            .map(|col| {
                let id = TileId { level, col, row: tile_row };
                let record =
                    writer.records[layout.index_of(id) as usize].expect("the level below is built");
                let texels = read_texture_slot(&writer.data, &data_path, layout, id, &record)?;
                Ok((col, texels))
            })
            .collect();
        for piece in pieces {
            let (col, texels) = piece?;
            let c0 = col as usize * t as usize;
            let n = (t as usize).min(width - c0);
            let rows = first.max(tile_row as u64 * t)..end.min(tile_row as u64 * t + t);
            for r in rows {
                let local = (r - tile_row as u64 * t) as usize + 1;
                let src = &texels[(local * side + 1) * TEXEL_BYTES..][..n * TEXEL_BYTES];
                let dst = ((r - first) as usize * width + c0) * TEXEL_BYTES;
                out[dst..dst + n * TEXEL_BYTES].copy_from_slice(src);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture_store::TextureStore;
    use crate::StoreHeader;
    use relief_io::{IoError, OrthoInfo};

    /// A photo in memory, served row by row from its top row.
    struct Photo {
        info: OrthoInfo,
        pixels: Vec<[u8; 3]>,
        next: usize,
    }

    impl OrthoRows for Photo {
        fn info(&self) -> &OrthoInfo {
            &self.info
        }
        fn read_next_row(&mut self, out: &mut [[u8; 3]]) -> Result<(), IoError> {
            let w = self.info.width as usize;
            out.copy_from_slice(&self.pixels[self.next * w..][..w]);
            self.next += 1;
            Ok(())
        }
    }

    fn photo(width: u32, height: u32) -> Photo {
        let pixels = (0..width * height)
            .map(|k| [(k * 37 % 256) as u8, (k * 11 % 256) as u8, ((k / width) * 9 % 256) as u8])
            .collect();
        let info = OrthoInfo { path: "p.png".into(), width, height, georeference: None };
        Photo { info, pixels, next: 0 }
    }

    #[test]
    fn levels_are_the_linear_2x2_averages_of_the_level_below() {
        let dir =
            std::env::temp_dir().join(format!("relief-texture-levels-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let (w, h) = (45u32, 27u32);
        let mut rows = photo(w, h);
        let pixels = rows.pixels.clone();
        let input = TextureInput {
            rows: &mut rows,
            placement: TexturePlacement {
                window: [0, 0, w as u64, h as u64],
                origin: [0.0, 0.0],
                texel: [1.0, 1.0],
                north_up: true,
            },
            source: SourceFile { path: "p.png".into(), bytes: 1, modified_ns: 0 },
        };
        let header = input.header(8);
        build_texture(&dir, &header, input.rows, &mut |_| {}).unwrap();
        let mut store_header: StoreHeader =
            serde_json::from_str(include_str!("../tests/fixtures/old-index.json")).unwrap();
        store_header.texture = Some(header.clone());
        let store = TextureStore::open(&dir, &store_header).unwrap().unwrap();
        let layout = header.layout();
        // Every level, read back texel by texel (row 0 south).
        let level = |l: u32| -> Vec<[u8; 3]> {
            let (lw, lh) = layout.level_size(l);
            let mut out = vec![[0u8; 3]; (lw * lh) as usize];
            let side = layout.stored_side();
            for index in 0..layout.tile_count() {
                let id = layout.id_at(index);
                if id.level != l {
                    continue;
                }
                let tile = store.load(id).unwrap();
                let (c0, r0) = layout.stored_origin(id);
                for r in 1..side - 1 {
                    for c in 1..side - 1 {
                        let (gc, gr) = (c0 + c as i64, r0 + r as i64);
                        if (gc as u64) < lw && (gr as u64) < lh {
                            let k = (c + r * side) * 3;
                            out[(gc as u64 + gr as u64 * lw) as usize]
                                .copy_from_slice(&tile.texels[k..k + 3]);
                        }
                    }
                }
            }
            out
        };
        // Level 0 is the photo, flipped so that row 0 is south.
        let level0 = level(0);
        for r in 0..h as usize {
            for c in 0..w as usize {
                assert_eq!(
                    level0[c + r * w as usize],
                    pixels[c + (h as usize - 1 - r) * w as usize]
                );
            }
        }
        let linear = srgb8_to_linear_table();
        for l in 1..layout.level_count() {
            let (fine, coarse) = (level(l - 1), level(l));
            let (fw, fh) = layout.level_size(l - 1);
            let (cw, ch) = layout.level_size(l);
            for r in 0..ch {
                for c in 0..cw {
                    let mut sum = [0f64; 3];
                    let mut n = 0.0;
                    for (fc, fr) in [
                        (2 * c, 2 * r),
                        (2 * c + 1, 2 * r),
                        (2 * c, 2 * r + 1),
                        (2 * c + 1, 2 * r + 1),
                    ] {
                        if fc < fw && fr < fh {
                            let texel = fine[(fc + fr * fw) as usize];
                            for k in 0..3 {
                                sum[k] += linear[texel[k] as usize] as f64;
                            }
                            n += 1.0;
                        }
                    }
                    let got = coarse[(c + r * cw) as usize];
                    for k in 0..3 {
                        let want = relief_core::colour::linear_to_srgb((sum[k] / n) as f32) * 255.0;
                        assert!(
                            (got[k] as f32 - want).abs() <= 0.5 + 1e-3,
                            "level {l} ({c}, {r}): {got:?}"
                        );
                    }
                }
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
