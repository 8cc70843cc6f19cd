//! Writing a cloud-optimised GeoTIFF block by block, never whole in memory: blocks compressed
//! tile by tile into a spill file beside the output and journaled, so that a rerun resumes an
//! interrupted write; at the end the overviews are built from the spill and the file is laid
//! out as GDAL's COG driver lays it out, under a temporary name, then renamed into place.

use crate::geotiff::cog_journal::{Journal, JournalBlock, JournalHeader};
use crate::geotiff::cog_layout::{data_order, lay_out, write_tile, CogMetadata};
use crate::geotiff::cog_overviews::{build_overviews, overview_bytes_per_thread, stored_bound};
use crate::geotiff::cog_progress::{resume, start};
use crate::geotiff::cog_spill::Spill;
use crate::geotiff::cog_tiles::{pack_tile, BlockSource, BlockTiles, LevelTiles, TileGrid};
use crate::layer_raster::{check_nodata, nodata_text};
use crate::{Georeference, IoError};
use rayon::prelude::*;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Error, ErrorKind, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Bytes of the buffer the finished file is written through.
const OUTPUT_BUFFER: usize = 1 << 20;

/// A float32 GeoTIFF of named bands in the cloud-optimised layout, written block by block
/// (in any order) and never whole in memory, resumable after a kill.
///
/// The file is what GDAL's COG driver writes, and what its validator and rio-cogeo's
/// `cog_validate` accept:
///
/// - internal tiles of `tile x tile` samples, Deflate-compressed with the floating-point
///   predictor (at Deflate's fast level, as relief's strip writers), edge tiles padded with
///   the nodata value;
/// - overviews, each half the previous (rounded up), until one fits in a tile, each sample
///   the mean of the 2 x 2 under it ignoring voids (a void where all four are), as GDAL's
///   AVERAGE resampling;
/// - GDAL's ghost area of structural metadata after the header (LAYOUT=IFDS_BEFORE_DATA,
///   BLOCK_ORDER=ROW_MAJOR, BLOCK_LEADER=SIZE_AS_UINT4, BLOCK_TRAILER=LAST_4_BYTES_REPEATED,
///   so that GDAL takes it for a COG), then the directories of the full resolution and of the
///   overviews (NewSubfileType 1) with their tags' values, then the tile offset and byte
///   count arrays, then the tiles, from the smallest overview to the full resolution, each
///   level band by band and row by row, each tile after its size and before its last 4 bytes
///   repeated;
/// - the bands in separate planes (PlanarConfiguration 2, GDAL's INTERLEAVE=BAND) rather than
///   GDAL's default pixel interleaving: relief's bands are separate quantities (shade layers)
///   that readers take one at a time, a band's tile compresses better alone, and relief's own
///   reader ([`read_layers_geotiff`](crate::geotiff::read_layers_geotiff)) and
///   [`write_layers_geotiff`](crate::geotiff::write_layers_geotiff) store bands so;
/// - the band descriptions (GDAL_METADATA), the georeference tags unchanged and GDAL_NODATA as
///   [`write_layers_geotiff`](crate::geotiff::write_layers_geotiff) writes them;
/// - a classic TIFF when the file fits in 4 GiB, else a BigTIFF (decided at
///   [`finish`](Self::finish), when the compressed sizes are known).
///
/// Each [`write_block`](Self::write_block) compresses its block's tiles in parallel (rayon)
/// and appends them to a hidden spill file beside `path` (`.<name>.cog-spill`), then records
/// the block in a journal (`.<name>.cog-journal`), both synced before it returns. Memory
/// holds the tile index (12 bytes a tile and band) and a few tiles per thread; see
/// [`memory_bytes`](Self::memory_bytes).
///
/// Nothing is written under `path` until [`finish`](Self::finish) renames the complete file
/// over it, so an existing file there is replaced only then. A writer dropped (or a process
/// killed) before leaves the spill and journal, which a later [`create`](Self::create) of the
/// same job (same path, size, bands, tile, nodata and fingerprint) resumes; another job's are
/// removed.
///
/// ```
/// use relief_io::geotiff::{read_layers_geotiff, CogWriter};
/// let dir = std::env::temp_dir().join(format!("relief-io-cog-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("shade.tif");
/// let names = vec!["hillshade".to_string()];
/// let mut out = CogWriter::create(&path, 300, 200, &names, None, None, 128, "job 1")?;
/// // Two blocks: the northern 128 rows (grid rows 72..200), then the rest.
/// out.write_block(0..300, 72..200, &[&vec![1.0; 300 * 128]])?;
/// out.write_block(0..300, 0..72, &[&vec![f32::NAN; 300 * 72]])?;
/// out.finish()?;
/// let back = read_layers_geotiff(&path, &relief_io::ReadOptions::default())?;
/// assert_eq!(back.layers[0].name, "hillshade");
/// assert!(back.layers[0].samples[0].is_nan() && back.layers[0].samples[72 * 300] == 1.0);
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct CogWriter {
    path: PathBuf,
    /// Where the finished file is written before it is renamed to `path`.
    temp: PathBuf,
    spill_path: PathBuf,
    journal_path: PathBuf,
    band_names: Vec<String>,
    georeference: Option<Georeference>,
    nodata: Option<f64>,
    /// Whether file row 0 is the grid's southern row (a south-up georeference).
    south_up: bool,
    /// Where each full-resolution tile lies in the spill.
    full: LevelTiles,
    spill: Spill,
    journal: Journal,
    resumed: bool,
    done_blocks: Vec<(Range<usize>, Range<usize>)>,
    /// Whether some sample written was a void.
    voids: bool,
    force_big: bool,
}

impl std::fmt::Debug for CogWriter {
    /// The output, its size, bands and tile, and how far the write is (not the tile index).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let grid = self.full.grid;
        f.debug_struct("CogWriter")
            .field("path", &self.path)
            .field("width", &grid.width)
            .field("height", &grid.height)
            .field("band_names", &self.band_names)
            .field("tile", &grid.tile)
            .field("nodata", &self.nodata)
            .field("resumed", &self.resumed)
            .field("done_blocks", &self.done_blocks.len())
            .finish_non_exhaustive()
    }
}

impl CogWriter {
    /// Starts (or resumes) writing `path`: `width` x `height` samples, one float32 band per
    /// name in `band_names` (GDAL band descriptions), placed by `georeference` (None: no
    /// georeference tags), NaN written as `nodata` (None: NaN, GDAL_NODATA "nan" when some
    /// sample is a void, as [`write_layers_geotiff`](crate::geotiff::write_layers_geotiff)
    /// does), internal tiles of `tile` x `tile`. The file is north-up unless the
    /// georeference says its file was south-up; then the grid's southern row comes first.
    ///
    /// `fingerprint` identifies the job (the caller's input and options): if an interrupted
    /// writer of the same path, size, bands, tile, nodata and fingerprint left its spill and
    /// journal, this one resumes it ([`resumed`](Self::resumed) is true,
    /// [`done_blocks`](Self::done_blocks) lists the blocks already in; a block whose journal
    /// line is cut short or whose tiles lie past the spill's end is not, and is to be written
    /// again); otherwise any stale spill is removed and it starts over. The georeference
    /// given here is the one written.
    ///
    /// Errors: [`IoError::InvalidData`] for an empty raster, no bands, a tile side that is
    /// not a power of two from 128 to 1024, or a nodata value float32 cannot hold;
    /// [`IoError::Unsupported`] for a side longer than 2^32 - 1 samples, more than 65535
    /// bands or a tile index too large for memory; [`IoError::Io`] when the spill or journal
    /// cannot be created.
    #[allow(clippy::too_many_arguments)]
    pub fn create(
        path: &Path,
        width: usize,
        height: usize,
        band_names: &[String],
        georeference: Option<&Georeference>,
        nodata: Option<f64>,
        tile: usize,
        fingerprint: &str,
    ) -> Result<CogWriter, IoError> {
        check_dimensions(path, width, height, band_names.len(), tile)?;
        check_nodata(path, nodata)?;
        if path.is_dir() {
            let reason = "is a directory, not a file to write";
            return Err(IoError::io(path, Error::new(ErrorKind::InvalidInput, reason)));
        }
        let south_up = georeference.is_some_and(Georeference::is_south_up);
        let spill_path = hidden_beside(path, "cog-spill")?;
        let journal_path = hidden_beside(path, "cog-journal")?;
        let temp = hidden_beside(path, "cog-tmp")?;
        // A finish killed while writing the file leaves it: it is never resumed.
        remove_if_present(&temp)?;
        let grid = TileGrid::new(width, height, tile);
        let bands = band_names.len();
        let new_index = || {
            LevelTiles::try_new(grid, bands).ok_or_else(|| {
                IoError::unsupported(
                    path,
                    format!("a tile index of {} tiles (too large for memory)", grid.per_band()),
                )
            })
        };
        let header = JournalHeader {
            width,
            height,
            bands: band_names.to_vec(),
            tile,
            nodata,
            south_up,
            fingerprint: fingerprint.to_string(),
        };
        let files = (spill_path.as_path(), journal_path.as_path());
        let resumed = resume(files, &header, grid, south_up, new_index()?)?;
        let (progress, resumed) = match resumed {
            Some(progress) => (progress, true),
            None => {
                let progress = start(files, &header, new_index()?)?;
                sync_directory(path);
                (progress, false)
            }
        };
        Ok(CogWriter {
            path: path.to_path_buf(),
            temp,
            spill_path,
            journal_path,
            band_names: band_names.to_vec(),
            georeference: georeference.cloned(),
            nodata,
            south_up,
            full: progress.full,
            spill: progress.spill,
            journal: progress.journal,
            resumed,
            done_blocks: progress.done_blocks,
            voids: progress.voids,
            force_big: false,
        })
    }

    /// Whether an interrupted writer of `path` left its journal beside it (which
    /// [`create`](Self::create) resumes, or removes when the job differs).
    pub fn interrupted_at(path: &Path) -> bool {
        hidden_beside(path, "cog-journal").is_ok_and(|journal| journal.exists())
    }

    /// Side of the internal tiles, in samples.
    pub fn tile(&self) -> usize {
        self.full.grid.tile
    }

    /// Whether this writer took up an interrupted writer's blocks (see
    /// [`create`](Self::create)).
    pub fn resumed(&self) -> bool {
        self.resumed
    }

    /// The blocks already written, by an earlier run and by this one, as (grid columns,
    /// grid rows), row 0 south.
    pub fn done_blocks(&self) -> &[(Range<usize>, Range<usize>)] {
        &self.done_blocks
    }

    /// Writes a BigTIFF even when a classic TIFF would hold the file (GDAL's BIGTIFF=YES),
    /// for readers that want one.
    pub fn force_big_tiff(&mut self) {
        self.force_big = true;
    }

    /// Writes one block of every band. Grid coordinates as everywhere in relief: row 0 is the
    /// southern row; `bands[b]` holds `cols.len() * rows.len()` values row-major, first the
    /// block's southern row (`rows.start`), each row west to east; NaN is a void (written as
    /// the nodata value). The file is north-up (file row = height - 1 - grid row), so the
    /// block must cover whole file tiles: `cols.start % tile == 0`, `cols.end % tile == 0` or
    /// `cols.end == width`, `(height - rows.end) % tile == 0`, `(height - rows.start) % tile
    /// == 0` or `rows.start == 0` (for a south-up file, the same of `rows` itself).
    ///
    /// Blocks may come in any order, each sample exactly once. The block's tiles are
    /// compressed in parallel, appended to the spill and recorded in the journal, both synced,
    /// before this returns, so a kill after it returns loses nothing of the block.
    ///
    /// Errors: [`IoError::InvalidData`] for a block that is empty, runs past the raster, does
    /// not cover whole tiles or overlaps a block already written, for a band count other than
    /// the writer's or a band of the wrong length; [`IoError::Io`] when writing the spill or
    /// journal fails. After an error the writer goes on as if the call had not been made.
    pub fn write_block(
        &mut self,
        cols: Range<usize>,
        rows: Range<usize>,
        bands: &[&[f32]],
    ) -> Result<(), IoError> {
        let grid = self.full.grid;
        let block = grid
            .block(&cols, &rows, self.south_up)
            .map_err(|reason| IoError::invalid_data(&self.path, reason))?;
        self.check_block_samples(&cols, &rows, bands)?;
        let tiles = block.tiles(bands.len());
        if tiles.iter().any(|&(b, tx, ty)| self.full.get(grid.index(b, tx, ty)).is_some()) {
            let overlapped = self.done_blocks.iter().find(|(c, r)| {
                c.start < cols.end && cols.start < c.end && r.start < rows.end && rows.start < r.end
            });
            let other = overlapped.map_or(String::new(), |(c, r)| {
                format!(" (the block of columns {c:?} and rows {r:?})")
            });
            return Err(IoError::invalid_data(
                &self.path,
                format!(
                    "block of columns {cols:?} and rows {rows:?} overlaps a block already \
                     written{other}"
                ),
            ));
        }
        let start = self.spill.len();
        let written = self.spill_block(&block, &cols, &rows, bands, &tiles).and_then(|spilled| {
            self.spill.sync()?;
            let record = JournalBlock { cols, rows, voids: spilled.1, tiles: spilled.0 };
            self.journal.append(&record)?;
            Ok(record)
        });
        let record = match written {
            Ok(record) => record,
            Err(e) => {
                self.spill.rewind(start);
                return Err(e);
            }
        };
        for (&(b, tx, ty), &(offset, count)) in tiles.iter().zip(&record.tiles) {
            self.full.set(grid.index(b, tx, ty), offset, count);
        }
        self.voids |= record.voids;
        self.done_blocks.push((record.cols, record.rows));
        Ok(())
    }

    /// Refuses a band count other than the writer's and a band whose length is not the
    /// block's sample count.
    fn check_block_samples(
        &self,
        cols: &Range<usize>,
        rows: &Range<usize>,
        bands: &[&[f32]],
    ) -> Result<(), IoError> {
        if bands.len() != self.band_names.len() {
            return Err(IoError::invalid_data(
                &self.path,
                format!("{} bands given; the file has {}", bands.len(), self.band_names.len()),
            ));
        }
        let needed = cols.len() * rows.len();
        for (band, name) in bands.iter().zip(&self.band_names) {
            if band.len() != needed {
                return Err(IoError::invalid_data(
                    &self.path,
                    format!(
                        "band {name:?} holds {} samples; a block of {} columns and {} rows \
                         needs {needed}",
                        band.len(),
                        cols.len(),
                        rows.len()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Compresses the block's `tiles` (a few per thread at a time) and appends them to the
    /// spill; returns where each lies and whether some sample was a void.
    fn spill_block(
        &mut self,
        block: &BlockTiles,
        cols: &Range<usize>,
        rows: &Range<usize>,
        bands: &[&[f32]],
        tiles: &[(usize, usize, usize)],
    ) -> Result<(Vec<(u64, u32)>, bool), IoError> {
        debug_assert!(tiles
            .iter()
            .all(|&(_, tx, ty)| block.tile_cols.contains(&tx) && block.tile_rows.contains(&ty)));
        let source = BlockSource {
            grid: self.full.grid,
            south_up: self.south_up,
            void: void_value(self.nodata),
            cols: cols.clone(),
            rows: rows.clone(),
        };
        let path = &self.path;
        let mut spilled = Vec::with_capacity(tiles.len());
        let mut voids = false;
        for batch in tiles.chunks(rayon::current_num_threads().max(1)) {
            let packed: Vec<Result<(Vec<u8>, bool), IoError>> = batch
                .par_iter()
                .map(|&(b, tx, ty)| {
                    let (samples, void) = source.tile(bands[b], tx, ty);
                    Ok((pack_tile(path, &samples, source.grid.tile)?, void))
                })
                .collect();
            for packed in packed {
                let (bytes, void) = packed?;
                let offset = self.spill.append(&bytes)?;
                // A stored tile is never empty (zlib's frame alone has 6 bytes) and at most
                // stored_bound(4 MiB) long.
                spilled.push((offset, bytes.len() as u32));
                voids |= void;
            }
        }
        Ok((spilled, voids))
    }

    /// Once every sample is in: builds the overviews, writes the file in the COG layout under
    /// a temporary name beside `path` (`.<name>.cog-tmp`), syncs it, renames it over `path`
    /// (replacing an existing file only now) and removes the spill and journal.
    ///
    /// Errors: [`IoError::InvalidData`] when some tiles were never written, naming how many
    /// and where the first lies (the spill and journal are kept: a rerun of the job resumes
    /// them); [`IoError::Io`] when reading the spill or writing the file fails;
    /// [`IoError::Format`] when the spill was damaged. On any error `path` is left as it was.
    pub fn finish(mut self) -> Result<(), IoError> {
        if let Some(((band, tx, ty), missing)) = self.full.missing() {
            let (cols, rows) = self.full.grid.tile_rectangle(tx, ty, self.south_up);
            return Err(IoError::invalid_data(
                &self.path,
                format!(
                    "finished with {missing} of {} tiles not written; the first is band {:?}, \
                     columns {cols:?}, rows {rows:?} (row 0 south)",
                    self.full.len(),
                    self.band_names[band],
                ),
            ));
        }
        let void = void_value(self.nodata);
        let overviews = build_overviews(&self.path, &mut self.spill, &self.full, void)?;
        let mut levels = vec![&self.full];
        levels.extend(&overviews);
        let metadata = CogMetadata {
            band_names: &self.band_names,
            georeference: self.georeference.as_ref(),
            nodata_text: nodata_text(self.nodata, || self.voids),
        };
        let layout = lay_out(&levels, &metadata, self.force_big)
            .map_err(|reason| IoError::unsupported(&self.path, reason))?;
        let file = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(&self.temp)
            .map_err(|e| IoError::io(&self.path, e))?;
        let written = (|| {
            let io = |e| IoError::io(&self.path, e);
            let mut out = BufWriter::with_capacity(OUTPUT_BUFFER, &file);
            out.write_all(&layout.header).map_err(io)?;
            let mut stored = Vec::new();
            for (level, index) in data_order(&levels) {
                let (offset, count) = levels[level].get(index).ok_or_else(|| {
                    IoError::invalid_data(&self.path, format!("tile {index} of level {level} lost"))
                })?;
                self.spill.read(offset, count, &mut stored)?;
                write_tile(&mut out, &stored).map_err(io)?;
            }
            out.flush().map_err(io)?;
            drop(out);
            let written = file.metadata().map_err(io)?.len();
            if written != layout.file_len {
                return Err(IoError::format(
                    &self.path,
                    format!("wrote {written} bytes; the layout holds {}", layout.file_len),
                ));
            }
            file.sync_all().map_err(io)?;
            std::fs::rename(&self.temp, &self.path).map_err(io)
        })();
        if let Err(e) = written {
            // Best effort: the original error matters more than a failed clean-up.
            let _ = std::fs::remove_file(&self.temp);
            return Err(e);
        }
        sync_directory(&self.path);
        // The file is complete: a spill or journal left behind is only dead weight, which
        // the next create of this path removes or finds complete.
        let _ = std::fs::remove_file(&self.journal_path);
        let _ = std::fs::remove_file(&self.spill_path);
        Ok(())
    }

    /// At most how many bytes of memory a writer of `width x height` samples, `bands` bands
    /// and `tile`-sided tiles holds (for the caller's memory budget), not counting the
    /// caller's block: the tile index of every level (12 bytes a tile and band) and the list
    /// of blocks written (at most one a tile); the journal line of a block (at most 128
    /// bytes a tile and band, as text and parsed, when it is written or replayed); and the largest of what
    /// `write_block` (per thread: a tile's samples, predicted bytes, stored bytes and a
    /// Deflate encoder), building the overviews (per thread: 2 x 2 source tiles stored and
    /// decoded, the output tile, its predicted and stored bytes) and writing the file (the
    /// directories, 16 bytes a tile and band, one stored tile and a 1 MiB buffer) hold.
    /// Dimensions [`create`](Self::create) refuses count as the nearest it accepts.
    pub fn memory_bytes(width: usize, height: usize, bands: usize, tile: usize) -> u64 {
        // Dimensions create refuses count as the nearest it accepts.
        let side = |n: usize| n.clamp(1, u32::MAX as usize) as u64;
        let (mut w, mut h) = (side(width), side(height));
        let tile = tile.clamp(128, 1024) as u64;
        let bands = bands.clamp(1, usize::from(u16::MAX)) as u64;
        let full_tiles = w.div_ceil(tile) * h.div_ceil(tile);
        let mut per_band = full_tiles;
        while w > tile || h > tile {
            (w, h) = (w.div_ceil(2), h.div_ceil(2));
            per_band += w.div_ceil(tile) * h.div_ceil(tile);
        }
        // Up to 2^50 tiles a band, 2^16 bands: products saturate.
        let tiles = per_band.saturating_mul(bands);
        let index = tiles.saturating_mul(12);
        let blocks = full_tiles * std::mem::size_of::<(Range<usize>, Range<usize>)>() as u64;
        let journal_line = full_tiles.saturating_mul(bands * 128);
        let threads = rayon::current_num_threads().max(1) as u64;
        let raw = tile * tile * 4;
        // miniz_oxide's compressor state is about 300 KiB.
        let encoder = 512 << 10;
        let write = threads * (2 * raw + stored_bound(raw) + encoder);
        let overviews = threads * (overview_bytes_per_thread(raw) + encoder);
        let file = tiles
            .saturating_mul(16)
            .saturating_add((64 << 10) + stored_bound(raw) + OUTPUT_BUFFER as u64);
        index
            .saturating_add(blocks)
            .saturating_add(journal_line)
            .saturating_add(write.max(overviews).max(file))
    }
}

/// The value voids are written as: the nodata value, or NaN.
fn void_value(nodata: Option<f64>) -> f32 {
    nodata.map_or(f32::NAN, |v| v as f32)
}

/// Refuses an empty raster, no bands, more than 65535, sides beyond u32, and a tile side
/// that is not a power of two from 128 to 1024.
fn check_dimensions(
    path: &Path,
    width: usize,
    height: usize,
    bands: usize,
    tile: usize,
) -> Result<(), IoError> {
    if width == 0 || height == 0 {
        return Err(IoError::invalid_data(
            path,
            format!("a raster of {width} x {height} samples is empty"),
        ));
    }
    if bands == 0 {
        return Err(IoError::invalid_data(path, "no bands to write"));
    }
    if bands > usize::from(u16::MAX) {
        return Err(IoError::unsupported(path, format!("{bands} bands (at most 65535)")));
    }
    if u32::try_from(width).is_err() || u32::try_from(height).is_err() {
        return Err(IoError::unsupported(
            path,
            format!("{width} x {height} samples in a GeoTIFF (at most 2^32 - 1 a side)"),
        ));
    }
    if !tile.is_power_of_two() || !(128..=1024).contains(&tile) {
        return Err(IoError::invalid_data(
            path,
            format!("tile side {tile} is not a power of two from 128 to 1024"),
        ));
    }
    Ok(())
}

/// `.<name>.<suffix>` beside `path`.
fn hidden_beside(path: &Path, suffix: &str) -> Result<PathBuf, IoError> {
    let name = path.file_name().ok_or_else(|| {
        IoError::io(path, Error::new(ErrorKind::InvalidInput, "path does not name a file"))
    })?;
    let mut hidden = std::ffi::OsString::from(".");
    hidden.push(name);
    hidden.push(format!(".{suffix}"));
    Ok(path.with_file_name(hidden))
}

/// Removes the file at `path` if there is one.
fn remove_if_present(path: &Path) -> Result<(), IoError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != ErrorKind::NotFound => Err(IoError::io(path, e)),
        _ => Ok(()),
    }
}

/// Syncs the directory holding `path`, so that files created or renamed there survive a
/// crash of the system; best effort (not every system syncs directories).
fn sync_directory(path: &Path) {
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    if let Ok(dir) = File::open(dir) {
        let _ = dir.sync_all();
    }
}

#[cfg(test)]
#[path = "cog_writer_tests.rs"]
mod tests;
