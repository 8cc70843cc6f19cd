//! The raster a shade map is made from, block by block: a tile store read tile by tile through a
//! bounded cache, or a raster in memory. Either gives windows of samples, the bounds of every
//! block of [`BOUND_CELL`] x [`BOUND_CELL`] samples, and the georeference to write the layers with; and either is the
//! far field ([`FarTerrain`]) of the windows' horizons.

use crate::RenderError;
use relief_core::{GridGeometry, HeightField};
use relief_io::{Format, Georeference, HeightUnit, RasterInfo};
use relief_shade::horizon::{block_bounds, CoarseBounds, FarTerrain, SamplePatch, BOUND_CELL};
use relief_shade::ShadeError;
use relief_tiles::{CachedTile, TileCache, TileId, TileStore};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Bytes of decoded tiles a store's cache keeps at most, unless told otherwise.
pub const DEFAULT_TILE_CACHE: u64 = 256 << 20;

/// A raster to shade block by block, with where it lies.
pub struct ShadeSource {
    path: PathBuf,
    samples: Samples,
    width: usize,
    height: usize,
    geometry: GridGeometry,
    info: RasterInfo,
    bounds: CoarseBounds,
    /// Per sample, whether it was a void (filled for tracing, NaN in every layer): rasters in
    /// memory only.
    void: Option<Vec<bool>>,
}

/// Where a [`ShadeSource`]'s samples are.
enum Samples {
    Store(Box<StoreTiles>),
    Memory(Arc<Vec<f32>>),
}

impl ShadeSource {
    /// The tile store at `dir` (complete, its level-0 tiles without voids), its decoded tiles
    /// cached up to `cache_bytes`. Reads every level-0 tile once for the bounds (each checked
    /// against its checksum). Errors: a store that is not one, incomplete (with the tiles
    /// built and the first missing tile) or corrupt (naming the tile), or with voids.
    pub fn open_store(dir: &Path, cache_bytes: u64) -> Result<ShadeSource, RenderError> {
        let store = TileStore::open_any(dir)?;
        let layout = store.layout().clone();
        let (done, total) = store.progress();
        if !store.header().complete || done != total {
            let missing = (0..layout.tile_count())
                .map(|index| layout.id_at(index))
                .find(|&id| store.record(id).is_none())
                .map_or_else(String::new, |id| format!("; {id} is missing"));
            return Err(RenderError::ShadeSource {
                path: dir.to_path_buf(),
                reason: format!(
                    "the tile store is incomplete ({done} of {total} tiles built{missing}); run \
                     the same `relief tile` command again to resume it"
                ),
            });
        }
        let (tiles_x, tiles_y) = layout.tiles_of(0);
        for row in 0..tiles_y {
            for col in 0..tiles_x {
                let id = TileId { level: 0, col, row };
                if store.record(id).is_some_and(|r| r.has_voids) {
                    return Err(RenderError::ShadeSource {
                        path: dir.to_path_buf(),
                        reason: format!(
                            "{id} has voids; a store is shaded without voids only (fill \
                             them before `relief tile`, or shade the raster in memory, which \
                             fills them)"
                        ),
                    });
                }
            }
        }
        let header = store.header().clone();
        let (width, height) = (header.width as usize, header.height as usize);
        let tiles = StoreTiles::new(store, cache_bytes);
        let bounds = tiles.bounds(width, height)?;
        Ok(ShadeSource {
            path: dir.to_path_buf(),
            geometry: header.geometry.into(),
            info: store_info(&header),
            samples: Samples::Store(Box::new(tiles)),
            width,
            height,
            bounds,
            void: None,
        })
    }

    /// The height field `field` in memory, read from `path` as `info` says, with its voids
    /// (filled in `field`) marked in `void`.
    pub fn in_memory(
        path: &Path,
        field: HeightField,
        info: RasterInfo,
        void: Option<Vec<bool>>,
    ) -> ShadeSource {
        let (width, height, geometry) = (field.width(), field.height(), *field.geometry());
        let samples = field.samples().to_vec();
        let bounds = CoarseBounds::of_samples(&samples, width, height);
        ShadeSource {
            path: path.to_path_buf(),
            samples: Samples::Memory(Arc::new(samples)),
            width,
            height,
            geometry,
            info,
            bounds,
            void,
        }
    }

    /// The source placed with `spacing` (where given; else its own) and its z scale times
    /// `z_scale`, as [`crate::input::place`] places a height field. Errors: a placement that
    /// is not valid.
    pub fn placed(
        mut self,
        spacing: Option<(f64, f64)>,
        z_scale: f64,
    ) -> Result<ShadeSource, RenderError> {
        let g = self.geometry;
        let (dx, dy) = spacing.unwrap_or((g.dx, g.dy));
        let geometry = GridGeometry { dx, dy, z_scale: z_scale * g.z_scale, ..g };
        geometry.validate().map_err(RenderError::Placement)?;
        self.geometry = geometry;
        Ok(self)
    }

    /// The raster's file or store.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Samples a row.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Where the raster lies in relief's world.
    pub fn geometry(&self) -> GridGeometry {
        self.geometry
    }

    /// Where it lies on the earth, if it is georeferenced.
    pub fn georeference(&self) -> Option<&Georeference> {
        self.info.georeference.as_ref()
    }

    /// Its declared nodata value.
    pub fn nodata(&self) -> Option<f64> {
        self.info.nodata
    }

    /// What its file said of it (for a store: what the store kept of its source).
    pub fn info(&self) -> &RasterInfo {
        &self.info
    }

    /// The side of the store's tiles (`None` for a raster in memory).
    pub fn tile(&self) -> Option<usize> {
        match &self.samples {
            Samples::Store(tiles) => Some(tiles.side),
            Samples::Memory(_) => None,
        }
    }

    /// The lowest and highest sample.
    pub fn span(&self) -> [f32; 2] {
        self.bounds.span(0..self.width, 0..self.height)
    }

    /// The samples of columns `cols` and rows `rows`, row-major, and which were voids.
    pub fn window(
        &self,
        cols: Range<usize>,
        rows: Range<usize>,
    ) -> Result<(Vec<f32>, Option<Vec<bool>>), RenderError> {
        let mut out = Vec::new();
        self.read(cols.clone(), rows.clone(), &mut out)?;
        let void = self.void.as_ref().map(|v| {
            rows.flat_map(|r| v[r * self.width + cols.start..r * self.width + cols.end].to_vec())
                .collect()
        });
        Ok((out, void))
    }

    /// Bytes the source holds besides its tile cache: the bounds, and a raster in memory.
    pub fn bytes(&self) -> u64 {
        let memory = match &self.samples {
            Samples::Memory(samples) => samples.len() as u64 * 4,
            Samples::Store(_) => 0,
        };
        memory + self.bounds.bytes() + self.void.as_ref().map_or(0, |v| v.len() as u64)
    }
}

impl ShadeSource {
    /// Reads columns `cols` and rows `rows` into `out`, row-major.
    fn read(
        &self,
        cols: Range<usize>,
        rows: Range<usize>,
        out: &mut Vec<f32>,
    ) -> Result<(), RenderError> {
        out.clear();
        match &self.samples {
            Samples::Memory(samples) => {
                for r in rows {
                    out.extend_from_slice(&samples[r * self.width + cols.start..][..cols.len()]);
                }
                Ok(())
            }
            Samples::Store(tiles) => Ok(tiles.read(cols, rows, out)?),
        }
    }
}

impl FarTerrain for ShadeSource {
    fn bounds(&self) -> &CoarseBounds {
        &self.bounds
    }

    fn patch(&self, col: usize, row: usize) -> Result<SamplePatch, ShadeError> {
        match &self.samples {
            Samples::Memory(samples) => Ok(SamplePatch {
                samples: samples.clone(),
                x0: 0,
                y0: 0,
                width: self.width,
                height: self.height,
            }),
            Samples::Store(tiles) => {
                let n = tiles.side;
                let (tc, tr) = (col / n, row / n);
                let samples = tiles
                    .tile(tc as u32, tr as u32)
                    .map_err(|e| ShadeError::Limits(format!("reading the far field: {e}")))?;
                // The stored tile starts one sample before the tile: its ring.
                Ok(SamplePatch {
                    samples,
                    x0: (tc * n) as isize - 1,
                    y0: (tr * n) as isize - 1,
                    width: n + 2,
                    height: n + 2,
                })
            }
        }
    }
}

/// A store's level-0 tiles, decoded, in the store's bounded cache (least recently used out).
struct StoreTiles {
    store: TileStore,
    /// Samples along a tile's side (without its ring).
    side: usize,
    cache: TileCache<SampleTile>,
}

/// A level-0 tile's stored samples, as the cache holds them.
struct SampleTile {
    id: TileId,
    samples: Arc<Vec<f32>>,
}

impl CachedTile for SampleTile {
    fn tile_id(&self) -> TileId {
        self.id
    }
    fn tile_bytes(&self) -> u64 {
        self.samples.len() as u64 * 4
    }
}

impl StoreTiles {
    fn new(store: TileStore, budget: u64) -> StoreTiles {
        let side = store.layout().tile() as usize;
        StoreTiles { store, side, cache: TileCache::new(budget) }
    }

    /// The stored samples of level-0 tile (`col`, `row`), from the cache or the store.
    fn tile(&self, col: u32, row: u32) -> Result<Arc<Vec<f32>>, relief_tiles::TileError> {
        let id = TileId { level: 0, col, row };
        if let Some(tile) = self.cache.get(id) {
            return Ok(tile.samples.clone());
        }
        let samples = Arc::new(self.store.stored_samples(id)?);
        // Every tile read so far may make room: the cache's frames are not a renderer's here.
        self.cache.begin_frame();
        self.cache.insert(Arc::new(SampleTile { id, samples: samples.clone() }));
        Ok(samples)
    }

    /// Reads columns `cols` and rows `rows` of level 0 into `out`, row-major.
    fn read(
        &self,
        cols: Range<usize>,
        rows: Range<usize>,
        out: &mut Vec<f32>,
    ) -> Result<(), relief_tiles::TileError> {
        let (n, side) = (self.side, self.side + 2);
        out.resize(cols.len() * rows.len(), 0.0);
        for tr in rows.start / n..=(rows.end - 1) / n {
            for tc in cols.start / n..=(cols.end - 1) / n {
                let tile = self.tile(tc as u32, tr as u32)?;
                let (c0, c1) = (cols.start.max(tc * n), cols.end.min((tc + 1) * n));
                let (r0, r1) = (rows.start.max(tr * n), rows.end.min((tr + 1) * n));
                for r in r0..r1 {
                    // Stored samples start one before the tile: its ring.
                    let from = (c0 + 1 - tc * n) + (r + 1 - tr * n) * side;
                    let to = (c0 - cols.start) + (r - rows.start) * cols.len();
                    out[to..to + (c1 - c0)].copy_from_slice(&tile[from..from + (c1 - c0)]);
                }
            }
        }
        Ok(())
    }

    /// The bounds of every block of [`BOUND_CELL`] samples, reading each tile once.
    fn bounds(&self, width: usize, height: usize) -> Result<CoarseBounds, RenderError> {
        use rayon::prelude::*;
        let n = self.side;
        let (tiles_x, tiles_y) = self.store.layout().tiles_of(0);
        let cells_x = width.div_ceil(BOUND_CELL);
        let cells_y = height.div_ceil(BOUND_CELL);
        // Per tile row, its blocks' bounds (a block may straddle tiles: merged below).
        let mut cells = vec![[f32::INFINITY, f32::NEG_INFINITY]; cells_x * cells_y];
        let per_tile: Vec<Vec<(usize, [f32; 2])>> = (0..tiles_x * tiles_y)
            .into_par_iter()
            .map(|k| {
                let (tc, tr) = ((k % tiles_x) as usize, (k / tiles_x) as usize);
                let id = TileId { level: 0, col: tc as u32, row: tr as u32 };
                let tile = self.store.stored_samples(id)?;
                let (c0, c1) = (tc * n, ((tc + 1) * n).min(width));
                let (r0, r1) = (tr * n, ((tr + 1) * n).min(height));
                let mut found = Vec::new();
                for by in r0 / BOUND_CELL..=(r1 - 1) / BOUND_CELL {
                    for bx in c0 / BOUND_CELL..=(c1 - 1) / BOUND_CELL {
                        let (xa, xb) = ((bx * BOUND_CELL).max(c0), ((bx + 1) * BOUND_CELL).min(c1));
                        let (ya, yb) = ((by * BOUND_CELL).max(r0), ((by + 1) * BOUND_CELL).min(r1));
                        let side = n + 2;
                        let span = block_bounds((ya..yb).flat_map(|r| {
                            let at = (xa + 1 - c0) + (r + 1 - r0) * side;
                            &tile[at..at + (xb - xa)]
                        }));
                        found.push((bx + by * cells_x, span));
                    }
                }
                Ok(found)
            })
            .collect::<Result<_, relief_tiles::TileError>>()?;
        for (cell, [low, high]) in per_tile.into_iter().flatten() {
            cells[cell][0] = cells[cell][0].min(low);
            cells[cell][1] = cells[cell][1].max(high);
        }
        Ok(CoarseBounds::new(width, height, |bx, by| cells[bx + by * cells_x]))
    }
}

/// What a store kept of its source, as a reader would have said it.
fn store_info(header: &relief_tiles::StoreHeader) -> RasterInfo {
    RasterInfo {
        format: Format::GeoTiff,
        sample_type: relief_tiles::precision_name(header.precision).to_string(),
        georeferenced: header.georeference.is_some(),
        from_degrees: None,
        nodata: header.nodata,
        georeference: header.georeference.as_ref().map(Into::into),
        height_unit: HeightUnit::default(),
    }
}
