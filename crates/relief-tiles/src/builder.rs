//! Building a tile store from a raster read band by band, resumably.
//!
//! Level 0 is cut from bands of `tile + 2` rows of the input (a tile's rows and its ring); each
//! coarser level from bands of the level below, read back from the store and averaged 2x2. A
//! band's tiles are written to their slots, the data synced, then their table records written
//! and synced: a record on disk means its tile is on disk. A build that stops (killed, or a
//! disk that filled) leaves `index.json` saying the store is incomplete; the same command run
//! again keeps every recorded tile and builds the rest. The index says complete only after the
//! last record is synced.

use crate::format::{
    decode_samples, encode_samples, precision_name, sample_bytes, slot_bytes, slot_checksum,
    slot_offset, SourceFile, StoreHeader, TileRecord, DATA_FILE, FORMAT_NAME, FORMAT_VERSION,
    INDEX_FILE, RECORD_BYTES, TABLE_FILE,
};
use crate::sized_file::open_sized;
use crate::texture_builder::{texture_working_set_bytes, TextureInput};
use crate::{PyramidLayout, TileError, TileId};
use rayon::prelude::*;
use relief_core::Precision;
use relief_io::RowSource;
use std::fs::File;
use std::os::unix::fs::FileExt;
use std::path::Path;
use std::time::Instant;

/// Options of a build.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildOptions {
    /// Samples along a tile's side (default 512).
    pub tile: u32,
    /// How samples are stored.
    pub precision: Precision,
    /// The most memory the build's buffers may take, in bytes; a build that would need more
    /// (a very wide raster with big tiles) is refused before it starts.
    pub max_memory: u64,
    /// For tests: stop with [`TileError::Injected`] after building this many tiles.
    pub fail_after: Option<u64>,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions { tile: 512, precision: Precision::F32, max_memory: 1 << 30, fail_after: None }
    }
}

/// What a build did.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildReport {
    /// Tiles of the store, the texture's included.
    pub tiles: u64,
    /// Tiles of the texture pyramid (0 without a texture).
    pub texture_tiles: u64,
    /// Texture tiles built by this run.
    pub texture_built: u64,
    /// Tiles built by this run.
    pub built: u64,
    /// Tiles a previous, interrupted run had built and this one kept.
    pub resumed: u64,
    /// Input samples read.
    pub samples_read: u64,
    /// Seconds spent.
    pub seconds: f64,
    /// Of those, seconds spent on the texture pyramid.
    pub texture_seconds: f64,
    /// The largest buffers the build held at once, in bytes (its working set).
    pub working_set_bytes: u64,
}

/// The bytes a build of a `width`-sample-wide raster in tiles of `tile` holds at most: a band
/// of fine rows for the coarse level, the coarse band (with its deviations) and its encoded
/// tiles.
pub fn working_set_bytes(width: u64, tile: u32) -> u64 {
    let side = tile as u64 + 2;
    let tiles_x = width.div_ceil(tile as u64);
    // Level 0: one band of side rows and the band's tiles, encoded. Level 1: 2 * side rows of
    // level 0, side rows of half the width with their deviations, and its tiles, encoded.
    let level0 = side * width * 4 + tiles_x * side * side * 4;
    let level1 = 2 * side * width * 4
        + 2 * side * width.div_ceil(2) * 4
        + tiles_x.div_ceil(2) * side * side * 4;
    level0.max(level1)
}

/// Builds (or resumes) the tile store at `dir` from `source`, reporting `(tiles done, tiles in
/// all)` to `progress`. `sources` names the input files; a store that exists at `dir` is
/// resumed only when it was started from the same files (size and modification time) with the
/// same options, and is refused otherwise.
pub fn build_store(
    source: &mut dyn RowSource,
    sources: Vec<SourceFile>,
    dir: &Path,
    options: &BuildOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<BuildReport, TileError> {
    build_textured_store(source, sources, None, dir, options, progress)
}

/// As [`build_store`], with the pyramid of an ortho photo draped over the raster (see
/// [`crate::place_ortho`]) in tiles of the same size, built after the height tiles; the
/// progress counts the tiles of both. The store is complete when both are.
pub fn build_textured_store(
    source: &mut dyn RowSource,
    sources: Vec<SourceFile>,
    texture: Option<TextureInput<'_>>,
    dir: &Path,
    options: &BuildOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<BuildReport, TileError> {
    let started = Instant::now();
    if options.tile < crate::layout::MIN_TILE {
        return Err(TileError::Invalid(format!("--tile {} is below 4 samples", options.tile)));
    }
    let (width, height) = (source.width() as u64, source.height() as u64);
    let layout = PyramidLayout::new(width, height, options.tile);
    let working_set = working_set_bytes(width, options.tile);
    if working_set > options.max_memory {
        return Err(TileError::Invalid(format!(
            "tiles of {} samples over a raster {width} samples wide need {} MiB of buffers, \
             more than the memory limit of {} MiB; choose a smaller --tile or a larger \
             --max-memory",
            options.tile,
            working_set >> 20,
            options.max_memory >> 20
        )));
    }
    let header = StoreHeader {
        format: FORMAT_NAME.into(),
        version: FORMAT_VERSION,
        complete: false,
        width,
        height,
        tile: options.tile,
        levels: layout.level_count(),
        precision: options.precision,
        geometry: source.geometry().into(),
        sources,
        texture: texture.as_ref().map(|t| t.header(options.tile)),
        georeference: source.info().georeference.as_ref().map(Into::into),
        nodata: source.info().nodata.filter(|v| v.is_finite()),
    };
    if let (Some(t), Some(texture)) = (&header.texture, &texture) {
        let file_width = texture.rows.info().width as u64;
        let needed = texture_working_set_bytes(t.width, file_width, t.tile);
        if needed > options.max_memory {
            return Err(TileError::Invalid(format!(
                "tiles of {} texels over a photo {file_width} pixels wide need {} MiB of \
                 buffers, more than the memory limit of {} MiB; choose a smaller --tile or a \
                 larger --max-memory",
                t.tile,
                needed >> 20,
                options.max_memory >> 20
            )));
        }
    }
    let texture_tiles = header.texture.as_ref().map_or(0, |t| t.layout().tile_count());
    let mut store = StoreWriter::open(dir, header, &layout)?;
    let total = layout.tile_count() + texture_tiles;
    let resumed = store.records.iter().filter(|r| r.is_some()).count() as u64;
    let mut run = Run { built: 0, samples_read: 0, fail_after: options.fail_after };
    progress(resumed, total);
    for level in 0..layout.level_count() {
        let (_, tiles_y) = layout.tiles_of(level);
        for row in 0..tiles_y {
            if store.band_done(&layout, level, row) {
                continue;
            }
            build_band(&mut store, &layout, source, level, row, &mut run)?;
            progress(store.records.iter().filter(|r| r.is_some()).count() as u64, total);
        }
    }
    let texture_started = Instant::now();
    let heights_done = store.records.iter().filter(|r| r.is_some()).count() as u64;
    let texture_built = match (texture, store.header.texture.clone()) {
        (Some(input), Some(header)) => {
            let mut report = |done: u64| progress(heights_done + done, total);
            crate::texture_builder::build_texture(dir, &header, input.rows, &mut report)?
        }
        _ => 0,
    };
    let texture_seconds = texture_started.elapsed().as_secs_f64();
    store.finish()?;
    Ok(BuildReport {
        texture_seconds,
        tiles: total,
        texture_tiles,
        texture_built,
        built: run.built,
        resumed,
        samples_read: run.samples_read,
        seconds: started.elapsed().as_secs_f64(),
        working_set_bytes: working_set,
    })
}

/// Counters of one run.
struct Run {
    built: u64,
    samples_read: u64,
    fail_after: Option<u64>,
}

/// The store's files while it is built.
struct StoreWriter {
    dir: std::path::PathBuf,
    header: StoreHeader,
    table: File,
    data: File,
    records: Vec<Option<TileRecord>>,
    slot: u64,
}

impl StoreWriter {
    /// Creates the store at `dir`, or opens the interrupted build there.
    fn open(dir: &Path, header: StoreHeader, layout: &PyramidLayout) -> Result<Self, TileError> {
        let mismatch = |reason: String| TileError::Mismatch { path: dir.to_path_buf(), reason };
        if dir.join(INDEX_FILE).exists() {
            let old = StoreHeader::read(dir)?;
            let fresh = StoreHeader { complete: old.complete, ..header.clone() };
            if old != fresh {
                return Err(mismatch(describe_difference(&old, &header)));
            }
        } else if dir.exists()
            && std::fs::read_dir(dir).map_err(|e| TileError::io(dir, e))?.next().is_some()
        {
            return Err(mismatch("exists and is not a tile store".into()));
        }
        std::fs::create_dir_all(dir).map_err(|e| TileError::io(dir, e))?;
        let open = |name: &str, len: u64| open_sized(&dir.join(name), len);
        let count = layout.tile_count();
        let slot = slot_bytes(layout, header.precision);
        let table = open(TABLE_FILE, count * RECORD_BYTES as u64)?;
        let data = open(DATA_FILE, count * slot)?;
        let mut header = header;
        header.complete = false;
        header.write(dir)?;
        let records = crate::store::read_table(&dir.join(TABLE_FILE), layout)?;
        Ok(StoreWriter { dir: dir.to_path_buf(), header, table, data, records, slot })
    }

    fn band_done(&self, layout: &PyramidLayout, level: u32, row: u32) -> bool {
        let (tiles_x, _) = layout.tiles_of(level);
        (0..tiles_x)
            .all(|col| self.records[layout.index_of(TileId { level, col, row }) as usize].is_some())
    }

    /// Writes a band's encoded tiles, syncs them, then writes and syncs their records.
    fn write_tiles(
        &mut self,
        layout: &PyramidLayout,
        tiles: &[(TileId, Vec<u8>, TileRecord)],
    ) -> Result<(), TileError> {
        let data_path = self.dir.join(DATA_FILE);
        for (id, bytes, _) in tiles {
            let offset = slot_offset(layout, self.header.precision, *id);
            debug_assert_eq!(bytes.len() as u64, self.slot);
            self.data.write_all_at(bytes, offset).map_err(|e| TileError::io(&data_path, e))?;
        }
        self.data.sync_data().map_err(|e| TileError::io(&data_path, e))?;
        let table_path = self.dir.join(TABLE_FILE);
        for (id, _, record) in tiles {
            let index = layout.index_of(*id);
            let offset = index * RECORD_BYTES as u64;
            self.table
                .write_all_at(&record.to_bytes(), offset)
                .map_err(|e| TileError::io(&table_path, e))?;
            self.records[index as usize] = Some(*record);
        }
        self.table.sync_data().map_err(|e| TileError::io(&table_path, e))
    }

    /// Marks the store complete once every tile is recorded.
    fn finish(mut self) -> Result<(), TileError> {
        let done = self.records.iter().filter(|r| r.is_some()).count() as u64;
        if done != self.records.len() as u64 {
            return Err(TileError::Incomplete {
                path: self.dir.clone(),
                done,
                total: self.records.len() as u64,
            });
        }
        self.header.complete = true;
        self.header.write(&self.dir)
    }
}

/// Says how an existing store differs from the one asked for.
fn describe_difference(old: &StoreHeader, new: &StoreHeader) -> String {
    if old.sources != new.sources {
        return "a tile store built from other input files (or from files changed since)".into();
    }
    if (old.width, old.height) != (new.width, new.height) || old.geometry != new.geometry {
        return "a tile store of another raster".into();
    }
    if old.texture != new.texture && old.tile == new.tile {
        return match (&old.texture, &new.texture) {
            (None, _) => "a tile store without a texture".into(),
            (_, None) => "a tile store with a texture (--texture)".into(),
            _ => "a tile store with another texture (or one changed since)".into(),
        };
    }
    format!(
        "a tile store with other options (--tile {} --precision {}, asked for --tile {} --precision {})",
        old.tile,
        precision_name(old.precision),
        new.tile,
        precision_name(new.precision)
    )
}

/// Rows `[first, first + rows)` of one level, `width` samples each.
struct Band {
    first: i64,
    width: usize,
    rows: usize,
    samples: Vec<f32>,
    /// Per sample of a coarse level: the largest distance from it to the samples it averages.
    deviation: Vec<f32>,
}

impl Band {
    /// Where row `row` of the level starts in `samples`, the edge row repeated beyond the band.
    fn row_start(&self, row: i64) -> usize {
        (row.clamp(self.first, self.first + self.rows as i64 - 1) - self.first) as usize
            * self.width
    }
}

/// Builds and writes the tiles of one row of tiles of `level`.
fn build_band(
    store: &mut StoreWriter,
    layout: &PyramidLayout,
    source: &mut dyn RowSource,
    level: u32,
    row: u32,
    run: &mut Run,
) -> Result<(), TileError> {
    let (level_w, level_h) = layout.level_size(level);
    let t = layout.tile() as i64;
    let first = (row as i64 * t - 1).max(0);
    let end = (row as i64 * t + t + 1).min(level_h as i64);
    let band = if level == 0 {
        let mut samples = vec![0f32; (end - first) as usize * level_w as usize];
        source.read_rows(first as usize, &mut samples)?;
        run.samples_read += samples.len() as u64;
        Band {
            first,
            width: level_w as usize,
            rows: (end - first) as usize,
            samples,
            deviation: Vec::new(),
        }
    } else {
        coarse_band(store, layout, level, first, end)?
    };
    let (tiles_x, _) = layout.tiles_of(level);
    let todo: Vec<TileId> = (0..tiles_x)
        .map(|col| TileId { level, col, row })
        .filter(|id| store.records[layout.index_of(*id) as usize].is_none())
        .collect();
    let precision = store.header.precision;
    let mut encoded: Vec<(TileId, Vec<u8>, TileRecord)> = todo
        .par_iter()
        .map(|&id| {
            let (bytes, mut record) = cut_tile(layout, &band, id, precision);
            record.error += layout
                .children(id)
                .filter_map(|c| store.records[layout.index_of(c) as usize])
                .map(|r| r.error)
                .fold(0.0, f32::max);
            (id, bytes, record)
        })
        .collect();
    drop(band);
    if let Some(limit) = run.fail_after {
        let room = limit.saturating_sub(run.built) as usize;
        if room < encoded.len() {
            encoded.truncate(room);
            store.write_tiles(layout, &encoded)?;
            return Err(TileError::Injected(limit));
        }
    }
    store.write_tiles(layout, &encoded)?;
    run.built += encoded.len() as u64;
    Ok(())
}

/// The stored samples of tile `id` cut from `band`, encoded, with their record (the error of
/// this level alone: the caller adds the children's).
fn cut_tile(
    layout: &PyramidLayout,
    band: &Band,
    id: TileId,
    precision: Precision,
) -> (Vec<u8>, TileRecord) {
    let side = layout.stored_side();
    let (c0, r0) = layout.stored_origin(id);
    let mut samples = vec![0f32; side * side];
    let mut error = 0f32;
    // The columns of the level this tile's stored columns show: the edge column repeated
    // beyond the level.
    let last_col = band.width as i64 - 1;
    let columns: Vec<usize> =
        (0..side).map(|c| (c0 + c as i64).clamp(0, last_col) as usize).collect();
    let inside = columns[1]..=columns[side - 2];
    for (r, out) in samples.chunks_exact_mut(side).enumerate() {
        let k = band.row_start(r0 + r as i64);
        let row = &band.samples[k..k + band.width];
        for (o, &c) in out.iter_mut().zip(&columns) {
            *o = row[c];
        }
        if (1..side - 1).contains(&r) && !band.deviation.is_empty() {
            let dev = &band.deviation[k + inside.start()..=k + inside.end()];
            error = dev.iter().copied().fold(error, f32::max);
        }
    }
    let mut bytes = vec![0u8; side * side * sample_bytes(precision)];
    encode_samples(precision, &samples, &mut bytes);
    if precision != Precision::F32 {
        // The record describes the samples as stored (f16 rounds them).
        decode_samples(precision, &bytes, &mut samples);
    }
    let (min, max, has_voids) = bounds(&samples);
    let record = TileRecord { min, max, error, has_voids, checksum: slot_checksum(&bytes) };
    (bytes, record)
}

/// The smallest and largest non-void sample of `samples`, and whether any is a void (NaN).
fn bounds(samples: &[f32]) -> (f32, f32, bool) {
    // Eight lanes that the compiler turns into vector compares; a NaN compares false and
    // leaves the bounds as they are.
    const LANES: usize = 8;
    let (mut lo, mut hi, mut nan) = ([f32::INFINITY; LANES], [f32::NEG_INFINITY; LANES], false);
    let chunks = samples.chunks_exact(LANES);
    let rest = chunks.remainder();
    for chunk in chunks {
        for i in 0..LANES {
            let v = chunk[i];
            nan |= v.is_nan();
            lo[i] = if v < lo[i] { v } else { lo[i] };
            hi[i] = if v > hi[i] { v } else { hi[i] };
        }
    }
    for &v in rest {
        nan |= v.is_nan();
        lo[0] = if v < lo[0] { v } else { lo[0] };
        hi[0] = if v > hi[0] { v } else { hi[0] };
    }
    (
        lo.into_iter().fold(f32::INFINITY, f32::min),
        hi.into_iter().fold(f32::NEG_INFINITY, f32::max),
        nan,
    )
}

/// Rows `[first, end)` of `level`, each the 2x2 average of the level below (voids left out; a
/// sample over four voids is a void), read back from the store's tiles.
fn coarse_band(
    store: &StoreWriter,
    layout: &PyramidLayout,
    level: u32,
    first: i64,
    end: i64,
) -> Result<Band, TileError> {
    let (fine_w, fine_h) = layout.level_size(level - 1);
    let (width, _) = layout.level_size(level);
    let fine_first = (2 * first) as u64;
    let fine_end = ((2 * end) as u64).min(fine_h);
    let fine = read_level_rows(store, layout, level - 1, fine_first, fine_end)?;
    let fine_w = fine_w as usize;
    let rows = (end - first) as usize;
    let width = width as usize;
    let mut samples = vec![0f32; rows * width];
    let mut deviation = vec![0f32; rows * width];
    let fine_rows = (fine_end - fine_first) as usize;
    let fine_row = |r: usize| match r < fine_rows {
        true => &fine[r * fine_w..(r + 1) * fine_w],
        false => &[][..],
    };
    samples.par_chunks_mut(width).zip(deviation.par_chunks_mut(width)).enumerate().for_each(
        |(r, (out, dev))| {
            let (south, north) = (fine_row(2 * r), fine_row(2 * r + 1));
            let at = |row: &[f32], c: usize| row.get(c).copied().unwrap_or(f32::NAN);
            for (c, (o, d)) in out.iter_mut().zip(dev.iter_mut()).enumerate() {
                let (fc, fc1) = (2 * c, 2 * c + 1);
                let values = [at(south, fc), at(south, fc1), at(north, fc), at(north, fc1)];
                (*o, *d) = average(values);
            }
        },
    );
    Ok(Band { first, width, rows, samples, deviation })
}

/// The mean of the non-void `values` and the largest distance from it to them; a void (NaN)
/// where all four are voids.
fn average(values: [f32; 4]) -> (f32, f32) {
    let (mut sum, mut n) = (0f64, 0u32);
    for v in values.into_iter().filter(|v| !v.is_nan()) {
        sum += v as f64;
        n += 1;
    }
    if n == 0 {
        return (f32::NAN, 0.0);
    }
    let mean = (sum / n as f64) as f32;
    let deviation = values.into_iter().filter(|v| !v.is_nan()).map(|v| (v - mean).abs());
    (mean, deviation.fold(0.0, f32::max))
}

/// Rows `[first, end)` of `level` (their tiles' inner samples), read back from the store and
/// checked against their checksums.
fn read_level_rows(
    store: &StoreWriter,
    layout: &PyramidLayout,
    level: u32,
    first: u64,
    end: u64,
) -> Result<Vec<f32>, TileError> {
    let (width, _) = layout.level_size(level);
    let (tiles_x, _) = layout.tiles_of(level);
    let t = layout.tile() as u64;
    let side = layout.stored_side();
    let width = width as usize;
    let mut out = vec![0f32; (end - first) as usize * width];
    let data_path = store.dir.join(DATA_FILE);
    for tile_row in (first / t) as u32..=((end - 1) / t) as u32 {
        let rows: Vec<u64> =
            (first.max(tile_row as u64 * t)..end.min(tile_row as u64 * t + t)).collect();
        let pieces: Vec<Result<(u32, Vec<f32>), TileError>> = (0..tiles_x)
            .into_par_iter()
            .map(|col| {
                let id = TileId { level, col, row: tile_row };
                let record =
                    store.records[layout.index_of(id) as usize].expect("the level below is built");
                let samples = crate::store::read_slot(
                    &store.data,
                    &data_path,
                    layout,
                    store.header.precision,
                    id,
                    &record,
                )?;
                Ok((col, samples))
            })
            .collect();
        for piece in pieces {
            let (col, samples) = piece?;
            let c0 = col as usize * t as usize;
            let n = (t as usize).min(width - c0);
            for &r in &rows {
                let local = (r - tile_row as u64 * t) as usize + 1;
                let src = &samples[local * side + 1..local * side + 1 + n];
                let dst = (r - first) as usize * width + c0;
                out[dst..dst + n].copy_from_slice(src);
            }
        }
    }
    Ok(out)
}
