//! The tiles of one level of a cloud-optimised GeoTIFF: how a level is cut into square tiles,
//! where each tile's compressed bytes lie in the spill file, and a tile's samples packed into
//! (and unpacked from) those bytes.

use crate::geotiff::float_strips::pack_rows;
use crate::geotiff::stored_chunk::{Predictor, StoredChunkDecoder, StoredCodec};
use crate::IoError;
use std::ops::Range;
use std::path::Path;
use tiff::encoder::compression::DeflateLevel;

/// A level of `width x height` samples cut into `tile x tile` tiles, the last column and row
/// of tiles padded past the level's edge. Tiles are counted in file order: row 0 is the
/// file's first row (the northernmost of a north-up file), each row west to east.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TileGrid {
    /// Columns of samples.
    pub(crate) width: usize,
    /// Rows of samples.
    pub(crate) height: usize,
    /// Side of a tile in samples.
    pub(crate) tile: usize,
    /// Tiles in a row.
    pub(crate) across: usize,
    /// Rows of tiles.
    pub(crate) down: usize,
}

impl TileGrid {
    /// The tiles of a `width x height` level (both at least 1), `tile` a side.
    pub(crate) fn new(width: usize, height: usize, tile: usize) -> TileGrid {
        TileGrid { width, height, tile, across: width.div_ceil(tile), down: height.div_ceil(tile) }
    }

    /// Tiles of one band.
    pub(crate) fn per_band(&self) -> usize {
        self.across * self.down
    }

    /// The index of band `band`'s tile in column `tx`, row `ty`, in the order of a TIFF's
    /// TileOffsets with separate planes: band by band, each row by row.
    pub(crate) fn index(&self, band: usize, tx: usize, ty: usize) -> usize {
        band * self.per_band() + ty * self.across + tx
    }

    /// The level's overview: half its size (rounded up) a side, as GDAL makes them.
    pub(crate) fn half(&self) -> TileGrid {
        TileGrid::new(self.width.div_ceil(2), self.height.div_ceil(2), self.tile)
    }

    /// The overview levels of this (full-resolution) level, largest first: each half the
    /// previous, until one fits in a single tile, as GDAL's COG driver makes them. None when
    /// this level fits in one tile.
    pub(crate) fn overviews(&self) -> Vec<TileGrid> {
        let mut levels = Vec::new();
        let mut level = *self;
        while level.width > level.tile || level.height > level.tile {
            level = level.half();
            levels.push(level);
        }
        levels
    }

    /// The tiles a block of grid columns `cols` and grid rows `rows` (row 0 south) covers, in
    /// a file whose first row is the grid's northern row, or its southern when `south_up`.
    /// Fails, saying why, when the block is empty, runs past the level or does not cover
    /// whole tiles.
    pub(crate) fn block(
        &self,
        cols: &Range<usize>,
        rows: &Range<usize>,
        south_up: bool,
    ) -> Result<BlockTiles, String> {
        let (w, h, t) = (self.width, self.height, self.tile);
        if cols.start >= cols.end || rows.start >= rows.end || cols.end > w || rows.end > h {
            return Err(format!(
                "block of columns {cols:?} and rows {rows:?} is empty or not within the {w} x \
                 {h} raster"
            ));
        }
        if !cols.start.is_multiple_of(t) || (!cols.end.is_multiple_of(t) && cols.end != w) {
            return Err(format!(
                "block columns {cols:?} do not cover whole tiles: they must start at a multiple \
                 of the tile side {t} and end at one or at the raster's width {w}"
            ));
        }
        let file_rows = if south_up { rows.clone() } else { h - rows.end..h - rows.start };
        if !file_rows.start.is_multiple_of(t)
            || (!file_rows.end.is_multiple_of(t) && file_rows.end != h)
        {
            let (first, last) =
                if south_up { ("southern", "northern") } else { ("northern", "southern") };
            return Err(format!(
                "block rows {rows:?} (row 0 south) are file rows {file_rows:?} of a {first}-row-first \
                 file of {h} rows, which do not cover whole tiles: the block's {first} edge must \
                 lie a multiple of the tile side {t} from the raster's {first} edge, and its \
                 {last} edge too unless it is the raster's"
            ));
        }
        Ok(BlockTiles {
            tile_cols: cols.start / t..cols.end.div_ceil(t),
            tile_rows: file_rows.start / t..file_rows.end.div_ceil(t),
        })
    }

    /// The grid columns and grid rows (row 0 south) tile (`tx`, `ty`) covers, as
    /// [`TileGrid::block`] takes them.
    pub(crate) fn tile_rectangle(
        &self,
        tx: usize,
        ty: usize,
        south_up: bool,
    ) -> (Range<usize>, Range<usize>) {
        let t = self.tile;
        let cols = tx * t..((tx + 1) * t).min(self.width);
        let file_rows = ty * t..((ty + 1) * t).min(self.height);
        let rows = if south_up {
            file_rows
        } else {
            self.height - file_rows.end..self.height - file_rows.start
        };
        (cols, rows)
    }
}

/// The tiles a block covers: columns and rows of tiles (file order).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct BlockTiles {
    /// Columns of tiles.
    pub(crate) tile_cols: Range<usize>,
    /// Rows of tiles, row 0 the file's first.
    pub(crate) tile_rows: Range<usize>,
}

impl BlockTiles {
    /// The block's tiles of every band as (band, column, row), in the order they are spilled
    /// and journaled: row by row of tiles, each west to east, each tile band by band.
    pub(crate) fn tiles(&self, bands: usize) -> Vec<(usize, usize, usize)> {
        let mut out = Vec::with_capacity(self.tile_cols.len() * self.tile_rows.len() * bands);
        for ty in self.tile_rows.clone() {
            for tx in self.tile_cols.clone() {
                out.extend((0..bands).map(|band| (band, tx, ty)));
            }
        }
        out
    }
}

/// Where a block's samples lie, to cut its tiles out of them.
pub(crate) struct BlockSource {
    pub(crate) grid: TileGrid,
    pub(crate) south_up: bool,
    /// The value voids are written as.
    pub(crate) void: f32,
    pub(crate) cols: Range<usize>,
    pub(crate) rows: Range<usize>,
}

impl BlockSource {
    /// Tile (`tx`, `ty`) of a band of the block (which covers it): its `tile x tile` samples
    /// in file order, voids and the padding past the raster's edge as the void value; and
    /// whether some sample was a void.
    pub(crate) fn tile(&self, band: &[f32], tx: usize, ty: usize) -> (Vec<f32>, bool) {
        let (t, width, height) = (self.grid.tile, self.grid.width, self.grid.height);
        let mut samples = vec![self.void; t * t];
        let mut voids = false;
        let (x0, x1) = (tx * t, ((tx + 1) * t).min(width));
        let block_width = self.cols.len();
        for r in 0..t {
            let file_row = ty * t + r;
            if file_row >= height {
                break;
            }
            let row = if self.south_up { file_row } else { height - 1 - file_row };
            let start = (row - self.rows.start) * block_width + x0 - self.cols.start;
            let source = &band[start..start + x1 - x0];
            for (sample, &value) in samples[r * t..].iter_mut().zip(source) {
                if value.is_nan() {
                    voids = true;
                } else {
                    *sample = value;
                }
            }
        }
        (samples, voids)
    }
}

/// Where each tile of a level lies in the spill file: offset and byte count, by tile index
/// ([`TileGrid::index`]); a count of 0 marks a tile not written yet. 12 bytes a tile.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LevelTiles {
    /// The level's tiles.
    pub(crate) grid: TileGrid,
    /// Bands (planes) of tiles.
    pub(crate) bands: usize,
    offsets: Vec<u64>,
    counts: Vec<u32>,
}

impl LevelTiles {
    /// A level of `bands` bands of which no tile is written yet.
    pub(crate) fn new(grid: TileGrid, bands: usize) -> LevelTiles {
        let n = grid.per_band() * bands;
        LevelTiles { grid, bands, offsets: vec![0; n], counts: vec![0; n] }
    }

    /// [`LevelTiles::new`], or `None` when the memory for the index cannot be had.
    pub(crate) fn try_new(grid: TileGrid, bands: usize) -> Option<LevelTiles> {
        let n = grid.per_band().checked_mul(bands)?;
        let (mut offsets, mut counts) = (Vec::new(), Vec::new());
        offsets.try_reserve_exact(n).ok()?;
        counts.try_reserve_exact(n).ok()?;
        offsets.resize(n, 0);
        counts.resize(n, 0);
        Some(LevelTiles { grid, bands, offsets, counts })
    }

    /// Tiles over every band.
    pub(crate) fn len(&self) -> usize {
        self.counts.len()
    }

    /// Where tile `index` lies in the spill (offset, byte count), or `None` when not written.
    pub(crate) fn get(&self, index: usize) -> Option<(u64, u32)> {
        let count = self.counts[index];
        (count > 0).then(|| (self.offsets[index], count))
    }

    /// Records that tile `index` lies at `offset`, `count` bytes (at least 1) long.
    pub(crate) fn set(&mut self, index: usize, offset: u64, count: u32) {
        self.offsets[index] = offset;
        self.counts[index] = count;
    }

    /// The byte count of every tile, in index order.
    pub(crate) fn counts(&self) -> &[u32] {
        &self.counts
    }

    /// The first tile not written yet (band, column, row of tiles) and how many are missing.
    pub(crate) fn missing(&self) -> Option<((usize, usize, usize), usize)> {
        let first = self.counts.iter().position(|&c| c == 0)?;
        let per_band = self.grid.per_band();
        let within = first % per_band;
        let at = (first / per_band, within % self.grid.across, within / self.grid.across);
        Some((at, self.counts.iter().filter(|&&c| c == 0).count()))
    }
}

/// A tile's samples (`tile x tile`, row-major, file order) as stored: the floating-point
/// predictor over each row, then Deflate at its fast level, as
/// [`FloatStrips::push_band`](crate::geotiff::float_strips::FloatStrips::push_band) stores
/// strips. `path` names the file in errors.
pub(crate) fn pack_tile(path: &Path, samples: &[f32], tile: usize) -> Result<Vec<u8>, IoError> {
    pack_rows(path, samples, tile, DeflateLevel::Fast)
}

/// Unpacks a tile's stored bytes (from [`pack_tile`]) into its `tile x tile` samples.
/// `bytes` is scratch space. Fails, saying why, on bytes that do not decode to a whole tile.
pub(crate) fn unpack_tile(
    stored: &[u8],
    tile: usize,
    bytes: &mut Vec<u8>,
) -> Result<Vec<f32>, String> {
    let mut decoder =
        StoredChunkDecoder::new(StoredCodec::Deflate, Predictor::FloatingPoint, 4, false);
    bytes.resize(tile * tile * 4, 0);
    let decoded = decoder.decode(stored, bytes, tile * 4)?;
    if decoded != bytes.len() {
        return Err(format!("a tile decodes to {decoded} bytes, not {}", bytes.len()));
    }
    Ok(bytes.chunks_exact(4).map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]])).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overview_levels_halve_until_one_tile_holds_the_level() {
        let sizes = |w, h, t| {
            TileGrid::new(w, h, t)
                .overviews()
                .iter()
                .map(|g| (g.width, g.height))
                .collect::<Vec<_>>()
        };
        assert_eq!(sizes(1000, 700, 128), [(500, 350), (250, 175), (125, 88)]);
        assert_eq!(sizes(129, 10, 128), [(65, 5)]);
        assert_eq!(sizes(128, 128, 128), []);
        assert_eq!(
            sizes(32768, 32768, 512),
            [(16384, 16384), (8192, 8192), (4096, 4096), (2048, 2048), (1024, 1024), (512, 512)]
        );
        let grid = TileGrid::new(1000, 700, 128);
        assert_eq!((grid.across, grid.down, grid.per_band()), (8, 6, 48));
        assert_eq!(grid.index(1, 2, 3), 48 + 3 * 8 + 2);
    }

    #[test]
    fn blocks_must_cover_whole_tiles_of_the_file() {
        let grid = TileGrid::new(1000, 700, 128);
        // North-up: file rows 700 - rows.end .. 700 - rows.start.
        let block = grid.block(&(256..512), &(188..444), false).unwrap();
        assert_eq!(block, BlockTiles { tile_cols: 2..4, tile_rows: 2..4 });
        assert_eq!(block.tiles(2)[..3], [(0, 2, 2), (1, 2, 2), (0, 3, 2)]);
        // The southern edge block ends at grid row 0, the eastern one at the width.
        let edge = grid.block(&(896..1000), &(0..60), false).unwrap();
        assert_eq!(edge, BlockTiles { tile_cols: 7..8, tile_rows: 5..6 });
        assert_eq!(grid.tile_rectangle(7, 5, false), (896..1000, 0..60));
        assert_eq!(grid.tile_rectangle(0, 0, true), (0..128, 0..128));
        for (cols, rows, why) in [
            (0..128, 0..128, "file rows 572..700"),
            (1..128, 572..700, "columns 1..128"),
            (0..100, 572..700, "columns 0..100"),
            (0..128, 572..701, "not within"),
            (0..0, 572..700, "empty"),
        ] {
            let err = grid.block(&cols, &rows, false).unwrap_err();
            assert!(err.contains(why), "{err}");
        }
        // South-up: file rows are grid rows.
        assert!(grid.block(&(0..128), &(0..128), true).is_ok());
        assert!(grid.block(&(0..128), &(640..700), true).is_ok());
        assert!(grid.block(&(0..128), &(572..700), true).is_err());
    }

    #[test]
    fn tiles_pack_and_unpack_and_the_index_finds_what_is_missing() {
        let samples: Vec<f32> = (0..128 * 128usize)
            .map(|i| if i.is_multiple_of(7) { f32::NAN } else { i as f32 * 0.5 })
            .collect();
        let stored = pack_tile(Path::new("t.tif"), &samples, 128).unwrap();
        let back = unpack_tile(&stored, 128, &mut Vec::new()).unwrap();
        assert!(back.iter().zip(&samples).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert!(unpack_tile(&stored[..stored.len() / 2], 128, &mut Vec::new()).is_err());
        assert!(unpack_tile(&stored, 256, &mut Vec::new()).unwrap_err().contains("decodes to"));
        let mut level = LevelTiles::new(TileGrid::new(300, 200, 128), 2);
        assert_eq!(level.len(), 12);
        assert_eq!(level.missing(), Some(((0, 0, 0), 12)));
        for index in 0..8 {
            level.set(index, 10 * index as u64, 5);
        }
        assert_eq!(level.get(7), Some((70, 5)));
        assert_eq!(level.get(8), None);
        // Band 1's tile in column 2, row 0.
        assert_eq!(level.missing(), Some(((1, 2, 0), 4)));
    }
}
