//! Reading a tile store: its index and table at open, tiles on request (checked against their
//! checksums), each loaded tile made a height field with its own tracer (the store's
//! [`TileTracerFactory`]: by default a max-mipmap tracer).

use crate::format::{
    decode_samples, sample_bytes, slot_offset, StoreHeader, TileRecord, DATA_FILE, TABLE_FILE,
};
use crate::layout::Rect;
use crate::record_table::read_record_table;
use crate::tile_tracer::{TileTracerFactory, TracedHeights};
use crate::{PyramidLayout, TileError, TileId};
use relief_core::{Aabb, DVec2, DVec3, GridGeometry, HeightField, Precision, Surface};
use std::fs::File;
use std::ops::Range;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A tile store opened for reading.
#[derive(Debug)]
pub struct TileStore {
    dir: PathBuf,
    header: StoreHeader,
    layout: PyramidLayout,
    data: File,
    records: Vec<Option<TileRecord>>,
    /// Per tile: the highest stored sample of the tile and every tile under it.
    subtree_max: Vec<f32>,
    floor: f32,
    top: f32,
    /// Makes each loaded tile's tracer.
    tile_tracers: TileTracerFactory,
}

impl TileStore {
    /// Opens a complete store; an incomplete one is refused with [`TileError::Incomplete`].
    pub fn open(dir: &Path) -> Result<TileStore, TileError> {
        let store = TileStore::open_any(dir)?;
        let (done, total) = store.progress();
        if !store.header.complete || done != total {
            return Err(TileError::Incomplete { path: dir.to_path_buf(), done, total });
        }
        Ok(store)
    }

    /// Opens a store whether or not its build finished (for `relief info`).
    pub fn open_any(dir: &Path) -> Result<TileStore, TileError> {
        let header = StoreHeader::read(dir)?;
        let layout = header.layout();
        let records = read_table(&dir.join(TABLE_FILE), &layout)?;
        let data_path = dir.join(DATA_FILE);
        let data = File::open(&data_path).map_err(|e| TileError::io(&data_path, e))?;
        let mut subtree_max: Vec<f32> =
            records.iter().map(|r| r.map_or(f32::NEG_INFINITY, |r| r.max)).collect();
        for index in 0..layout.tile_count() {
            let id = layout.id_at(index);
            if let Some(parent) = layout.parent(id) {
                let p = layout.index_of(parent) as usize;
                subtree_max[p] = subtree_max[p].max(subtree_max[index as usize]);
            }
        }
        let level0 = &records[..layout.tiles_of(0).0 as usize * layout.tiles_of(0).1 as usize];
        let floor = level0.iter().flatten().map(|r| r.min).fold(f32::INFINITY, f32::min);
        let top = level0.iter().flatten().map(|r| r.max).fold(f32::NEG_INFINITY, f32::max);
        Ok(TileStore {
            dir: dir.to_path_buf(),
            header,
            layout,
            data,
            records,
            subtree_max,
            floor,
            top,
            tile_tracers: TileTracerFactory::default(),
        })
    }

    /// The store whose loaded tiles are traced by tracers `tile_tracers` makes (max-mipmap
    /// tracers unless this is called): any tracer nests in the frames' [`crate::TiledTerrain`].
    pub fn with_tile_tracers(mut self, tile_tracers: TileTracerFactory) -> Self {
        self.tile_tracers = tile_tracers;
        self
    }

    /// What makes each loaded tile's tracer.
    pub fn tile_tracers(&self) -> &TileTracerFactory {
        &self.tile_tracers
    }

    /// The store's directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The store's index.
    pub fn header(&self) -> &StoreHeader {
        &self.header
    }

    /// The pyramid's layout.
    pub fn layout(&self) -> &PyramidLayout {
        &self.layout
    }

    /// The raster's placement.
    pub fn geometry(&self) -> GridGeometry {
        self.header.geometry.into()
    }

    /// Tiles built, and tiles in all.
    pub fn progress(&self) -> (u64, u64) {
        (self.records.iter().filter(|r| r.is_some()).count() as u64, self.records.len() as u64)
    }

    /// The record of tile `id`; `None` while it is not built.
    pub fn record(&self, id: TileId) -> Option<TileRecord> {
        self.records[self.layout.index_of(id) as usize]
    }

    /// The highest stored sample of `id` and of every tile under it (sample units).
    pub fn subtree_max(&self, id: TileId) -> f32 {
        self.subtree_max[self.layout.index_of(id) as usize]
    }

    /// The bottom of the solid: the raster's lowest valid sample (sample units).
    pub fn floor(&self) -> f32 {
        self.floor
    }

    /// The raster's highest valid sample (sample units).
    pub fn top(&self) -> f32 {
        self.top
    }

    /// The solid's world bounds for `surface`, as the untiled raster's.
    pub fn world_bounds(&self, surface: Surface) -> Aabb {
        let g = self.geometry();
        let rect = self.layout.rect(self.layout.root(), &g, surface);
        Aabb::new(
            DVec3::new(rect.min[0], rect.min[1], self.floor as f64 * g.z_scale),
            DVec3::new(rect.max[0], rect.max[1], self.top as f64 * g.z_scale),
        )
    }

    /// The stored samples of tile `id`: its `(N + 2)^2` samples with their ring (see
    /// [`PyramidLayout::stored_origin`]), rows from the south, voids NaN, checked against
    /// their checksum. Errors: a tile never built, a truncated data file, a checksum that does
    /// not match (each naming the tile).
    pub fn stored_samples(&self, id: TileId) -> Result<Vec<f32>, TileError> {
        let data_path = self.dir.join(DATA_FILE);
        let record = self.record(id).ok_or_else(|| TileError::Corrupt {
            path: self.dir.join(TABLE_FILE),
            tile: id,
            reason: "it was never built".into(),
        })?;
        read_slot(&self.data, &data_path, &self.layout, self.header.precision, id, &record)
    }

    /// Reads tile `id`, checks it and builds its tracer for `surface` (with
    /// [`TileStore::tile_tracers`]).
    pub fn load(&self, id: TileId, surface: Surface) -> Result<LoadedTile, TileError> {
        let record = self.record(id).ok_or_else(|| TileError::Corrupt {
            path: self.dir.join(TABLE_FILE),
            tile: id,
            reason: "it was never built".into(),
        })?;
        let rect = self.layout.rect(id, &self.geometry(), surface);
        if record.is_void() {
            return Ok(LoadedTile { id, rect, record, heights: None, bytes: 0 });
        }
        let data_path = self.dir.join(DATA_FILE);
        let samples =
            read_slot(&self.data, &data_path, &self.layout, self.header.precision, id, &record)?;
        let side = self.layout.stored_side();
        let invalid = |e: relief_core::CoreError| TileError::Corrupt {
            path: data_path.clone(),
            tile: id,
            reason: e.to_string(),
        };
        let stored = StoredSamples { samples: &samples, side, record: &record };
        let field_of = |columns: Range<usize>, rows: Range<usize>| {
            let geometry = self.layout.tile_geometry(id, &self.geometry());
            stored.field(columns, rows, geometry, self.floor).map(Arc::new).map_err(invalid)
        };
        let field = field_of(0..side, 0..side)?;
        // The ring repeats the raster's edge samples beyond its edges. Beside a hole, the
        // `triangles` surface would join the repeats into squares the raster does not have,
        // with no wall where the raster has one: a level-0 tile with voids traces the raster's
        // own samples only, so that its surface and walls are exactly the raster's. (Without
        // voids, the squares of repeats lie outside the tile's rectangle, whose edge stands
        // where the raster's wall does, so they change nothing. A coarser tile keeps the
        // repeats: they carry its surface, whose samples lie further in, out to the edge of its
        // rectangle.)
        let (columns, rows) = self.layout.stored_within_level(id);
        let mut bytes =
            (side * side) as u64 * (4 + 2) + record.has_voids as u64 * (side * side) as u64;
        let cut = (columns.len(), rows.len()) != (side, side);
        let traced = match surface {
            Surface::Triangles if id.level == 0 && record.has_voids && cut => {
                let within = field_of(columns, rows)?;
                bytes += (within.width() * within.height()) as u64 * (4 + 1);
                within
            }
            _ => field.clone(),
        };
        let tracer = self.tile_tracers.make(traced, surface);
        Ok(LoadedTile { id, rect, record, heights: Some(TracedHeights { field, tracer }), bytes })
    }
}

/// A stored tile's decoded samples (voids as NaN), `side` to a row, with its record.
struct StoredSamples<'a> {
    samples: &'a [f32],
    side: usize,
    record: &'a TileRecord,
}

impl StoredSamples<'_> {
    /// The height field of the stored samples in `columns` x `rows` (`geometry` places the
    /// whole stored tile), standing on `floor`: voids are holes.
    fn field(
        &self,
        columns: Range<usize>,
        rows: Range<usize>,
        geometry: GridGeometry,
        floor: f32,
    ) -> Result<HeightField, relief_core::CoreError> {
        let (width, height) = (columns.len(), rows.len());
        let window = || {
            let rows = rows.clone();
            rows.flat_map(|r| {
                &self.samples[r * self.side + columns.start..r * self.side + columns.end]
            })
        };
        let geometry = GridGeometry {
            origin: geometry.origin
                + DVec2::new(columns.start as f64 * geometry.dx, rows.start as f64 * geometry.dy),
            ..geometry
        };
        let holes = self.record.has_voids.then(|| {
            let mut holes = Vec::with_capacity(width * height);
            holes.extend(window().map(|v| v.is_nan()));
            holes
        });
        let mut filled = Vec::with_capacity(width * height);
        filled.extend(window().map(|&v| if v.is_nan() { self.record.min } else { v }));
        let mut field = HeightField::new(width, height, filled, geometry)?;
        if let Some(holes) = holes {
            field = field.with_holes(holes)?;
        }
        field.with_floor(floor)
    }
}

/// A tile in memory, ready to trace.
#[derive(Debug)]
pub struct LoadedTile {
    /// Which tile.
    pub id: TileId,
    /// The world rectangle it answers for.
    pub rect: Rect,
    /// Its table record.
    pub record: TileRecord,
    /// Its heights and their tracer; `None` when every sample is a void.
    pub heights: Option<TracedHeights>,
    /// Bytes it holds: samples, holes and (for the default tracer) max mipmap.
    pub bytes: u64,
}

/// Reads the whole tile table, checking every record.
pub(crate) fn read_table(
    path: &Path,
    layout: &PyramidLayout,
) -> Result<Vec<Option<TileRecord>>, TileError> {
    read_record_table(path, layout, TileRecord::from_bytes)
}

/// Reads and decodes the slot of tile `id`, checked against its record's checksum.
pub(crate) fn read_slot(
    data: &File,
    path: &Path,
    layout: &PyramidLayout,
    precision: Precision,
    id: TileId,
    record: &TileRecord,
) -> Result<Vec<f32>, TileError> {
    let corrupt =
        |reason: String| TileError::Corrupt { path: path.to_path_buf(), tile: id, reason };
    let mut bytes = vec![0u8; layout.stored_samples() * sample_bytes(precision)];
    data.read_exact_at(&mut bytes, slot_offset(layout, precision, id)).map_err(|e| {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            corrupt(format!("{DATA_FILE} is truncated"))
        } else {
            TileError::io(path, e)
        }
    })?;
    if crate::format::slot_checksum(&bytes) != record.checksum {
        return Err(corrupt("its samples do not match their checksum".into()));
    }
    let mut samples = vec![0f32; layout.stored_samples()];
    decode_samples(precision, &bytes, &mut samples);
    Ok(samples)
}
