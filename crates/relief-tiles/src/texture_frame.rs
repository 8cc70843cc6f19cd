//! A store's texture over one frame: the tiles its pixels' footprints need, loaded into a
//! cache of their own, and the albedo the deferred pass filters from them.
//!
//! After the G-buffer is traced, every hit pixel's footprint is computed exactly as the
//! deferred pass will compute it ([`pixel_ground_footprint`], on the tangent
//! plane of [`TiledTerrain::surface_slope`]), and the filter is run once without colour to
//! record the texture tiles its samples touch. A still frame loads those tiles (in parallel,
//! checked against their checksums); a frame of a fly-through does not wait for them: they are
//! loaded in the background for later frames, and the coarser tiles in memory stand in. The
//! tiles are handed to the frame's [`TexturedFrame`], so that the shading pass reads them
//! without locks and never waits. When they would not fit the texture cache, the finest level
//! allowed is raised one level at a time until they do.

use crate::cache::TileCache;
use crate::texture_format::TEXEL_BYTES;
use crate::texture_store::{TextureStore, TextureTile};
use crate::{PyramidLayout, TileError, TileId, TiledTerrain};
use rayon::prelude::*;
use relief_core::colour::srgb8_to_linear_table;
use relief_core::texture::{
    filter_texture, pixel_ground_footprint, FootprintAlbedo, GroundFootprint, MipTexture,
    PixelHits, TexelFootprint, TextureFilter,
};
use relief_core::{Camera, DVec2, DVec3};
use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

/// What a textured frame did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TextureFrameStats {
    /// Texture tiles the frame's pixels sample.
    pub tiles: usize,
    /// Of those, tiles read from the store for this frame (the others were in the cache, or,
    /// in a frame that did not wait, are loading in the background).
    pub tiles_loaded: usize,
    /// Milliseconds spent choosing and loading them.
    pub io_ms: f64,
    /// Bytes of texture tiles in memory after the frame.
    pub resident_bytes: u64,
    /// The finest level sampled: 0, or higher when the tiles of finer ones would not fit the
    /// texture cache.
    pub min_level: u32,
}

/// A store's texture pyramid with its cache, making the albedo of frames.
pub struct TextureStreamer {
    store: Arc<TextureStore>,
    cache: Arc<TileCache<TextureTile>>,
    root: Arc<TextureTile>,
    /// The background load of the tiles a frame that did not wait missed, while it runs.
    background: Mutex<Option<JoinHandle<Result<(), TileError>>>>,
}

impl TextureStreamer {
    /// Frames over `store` with a cache of `cache_bytes` of texture tiles (the root tile,
    /// always in memory, aside).
    pub fn new(store: TextureStore, cache_bytes: u64) -> Result<Self, TileError> {
        let root = Arc::new(store.load(store.layout().root())?);
        let cache = Arc::new(TileCache::new(cache_bytes));
        let background = Mutex::new(None);
        Ok(TextureStreamer { store: Arc::new(store), cache, root, background })
    }

    /// The texture's pyramid.
    pub fn store(&self) -> &TextureStore {
        &self.store
    }

    /// The albedo of the frame `camera` saw into `hits` (a G-buffer) over `terrain`, filtered
    /// with `filter`. With `wait`, loads the texture tiles the frame's footprints need; without,
    /// starts loading them in the background (unless an earlier load still runs) and lets
    /// coarser tiles in memory stand in. Fails when a tile cannot be read or is damaged (a
    /// background load's failure is reported by the next frame).
    pub fn frame<H: PixelHits + Sync + ?Sized>(
        &self,
        hits: &H,
        camera: &Camera,
        terrain: Arc<TiledTerrain>,
        filter: TextureFilter,
        wait: bool,
    ) -> Result<(TexturedFrame, TextureFrameStats), TileError> {
        let started = Instant::now();
        self.cache.begin_frame();
        let pyramid = TexturePyramid::new(&self.store);
        let layout = self.store.layout();
        let per_tile = self.store.tile_bytes();
        let mut min_level = 0;
        let needed = loop {
            let needed = needed_tiles(&pyramid, hits, camera, &terrain, filter, min_level);
            let fits = needed.len() as u64 * per_tile <= self.cache.budget();
            if fits || min_level + 1 >= layout.level_count() {
                break needed;
            }
            min_level += 1;
        };
        let mut tiles: HashMap<TileId, Arc<TextureTile>> = HashMap::new();
        tiles.insert(self.root.id, self.root.clone());
        let mut missing = Vec::new();
        for &id in &needed {
            match self.cache.get(id).or_else(|| (id == self.root.id).then(|| self.root.clone())) {
                Some(tile) => drop(tiles.insert(id, tile)),
                None => missing.push(id),
            }
        }
        let mut background = self.background.lock().unwrap_or_else(|p| p.into_inner());
        if background.as_ref().is_some_and(|load| load.is_finished()) {
            let load = background.take().expect("a finished load");
            load.join()
                .unwrap_or_else(|_| Err(TileError::Invalid("texture loader panicked".into())))?;
        }
        let tiles_loaded = match (wait, background.is_some()) {
            (true, _) => {
                let loaded: Vec<Result<TextureTile, TileError>> =
                    missing.par_iter().map(|&id| self.store.load(id)).collect();
                for tile in loaded {
                    let tile = Arc::new(tile?);
                    self.cache.insert(tile.clone());
                    self.cache.get(tile.id);
                    tiles.insert(tile.id, tile);
                }
                missing.len()
            }
            (false, true) => 0,
            (false, false) => {
                let (store, cache) = (self.store.clone(), self.cache.clone());
                *background = Some(std::thread::spawn(move || {
                    for id in missing {
                        cache.insert(Arc::new(store.load(id)?));
                    }
                    Ok(())
                }));
                0
            }
        };
        let stats = TextureFrameStats {
            tiles: needed.len(),
            tiles_loaded,
            io_ms: started.elapsed().as_secs_f64() * 1e3,
            resident_bytes: self.cache.bytes() + self.root.bytes,
            min_level,
        };
        let frame = TexturedFrame { pyramid, tiles, terrain, filter, min_level };
        Ok((frame, stats))
    }
}

/// The tiles the filter samples for every hit pixel of `hits`.
fn needed_tiles<H: PixelHits + Sync + ?Sized>(
    pyramid: &TexturePyramid,
    hits: &H,
    camera: &Camera,
    terrain: &TiledTerrain,
    filter: TextureFilter,
    min_level: u32,
) -> HashSet<TileId> {
    let slope = |p: DVec3| terrain.surface_slope(p.x, p.y);
    let (width, height) = hits.size();
    (0..height)
        .into_par_iter()
        .fold(HashSet::new, |mut set, j| {
            let recorder = TileRecorder { pyramid, tiles: RefCell::new(std::mem::take(&mut set)) };
            for i in 0..width {
                let footprint = pixel_ground_footprint(hits, camera, i as u32, j as u32, &slope);
                if let Some(footprint) = footprint {
                    let texels = pyramid.texel_footprint(&footprint);
                    filter_texture(&recorder, &texels, filter, min_level);
                }
            }
            recorder.tiles.into_inner()
        })
        .reduce(HashSet::new, |mut a, b| {
            a.extend(b);
            a
        })
}

/// The geometry of a texture pyramid: its layout and where level 0 lies in the world.
#[derive(Debug, Clone)]
struct TexturePyramid {
    layout: PyramidLayout,
    origin: DVec2,
    texel: DVec2,
}

/// The four texels a bilinear sample reads: their tile, their stored indices in it and the
/// weights of the second column and row.
struct Taps {
    tile: TileId,
    cols: [usize; 2],
    rows: [usize; 2],
    weights: [f64; 2],
}

impl TexturePyramid {
    fn new(store: &TextureStore) -> Self {
        let header = store.header();
        TexturePyramid {
            layout: store.layout().clone(),
            origin: DVec2::from(header.origin),
            texel: DVec2::from(header.texel),
        }
    }

    /// `footprint` in texels of level 0.
    fn texel_footprint(&self, footprint: &GroundFootprint) -> TexelFootprint {
        TexelFootprint {
            centre: (footprint.centre.truncate() - self.origin) / self.texel,
            along_x: footprint.along_x / self.texel,
            along_y: footprint.along_y / self.texel,
        }
    }

    /// The texels of a bilinear sample of `level` at `(s, t)` (level-0 texels); all four lie
    /// in one stored tile, thanks to its ring.
    fn taps(&self, level: u32, s: f64, t: f64) -> Taps {
        let scale = (1u64 << level) as f64;
        let (width, height) = self.layout.level_size(level);
        let tile = self.layout.tile() as u64;
        let axis = |x: f64, size: u64| {
            let x = if x.is_nan() { 0.5 * size as f64 } else { x };
            let x = (x / scale - 0.5).clamp(0.0, (size - 1) as f64);
            let i0 = x.floor() as u64;
            let i1 = (i0 + 1).min(size - 1);
            let index = i0 / tile;
            // Stored indices: the tile's first stored texel is one before it (its ring).
            let first = index * tile;
            (index as u32, [(i0 + 1 - first) as usize, (i1 + 1 - first) as usize], x - i0 as f64)
        };
        let (col, cols, wx) = axis(s, width);
        let (row, rows, wy) = axis(t, height);
        Taps { tile: TileId { level, col, row }, cols, rows, weights: [wx, wy] }
    }
}

/// Records the tiles a filter samples (the colour it returns is black).
struct TileRecorder<'a> {
    pyramid: &'a TexturePyramid,
    tiles: RefCell<HashSet<TileId>>,
}

impl MipTexture for TileRecorder<'_> {
    fn level_count(&self) -> u32 {
        self.pyramid.layout.level_count()
    }

    fn bilinear(&self, level: u32, s: f64, t: f64) -> DVec3 {
        self.tiles.borrow_mut().insert(self.pyramid.taps(level, s, t).tile);
        DVec3::ZERO
    }
}

/// One frame's albedo from a store's texture: the tiles its pixels need, in memory, filtered
/// over each pixel's footprint on the frame's terrain.
#[derive(Debug)]
pub struct TexturedFrame {
    pyramid: TexturePyramid,
    tiles: HashMap<TileId, Arc<TextureTile>>,
    terrain: Arc<TiledTerrain>,
    filter: TextureFilter,
    min_level: u32,
}

impl TexturedFrame {
    /// The linear colour of texel `(c, r)` (stored indices) of `tile`.
    #[inline]
    fn texel(tile: &TextureTile, side: usize, c: usize, r: usize) -> DVec3 {
        let linear = srgb8_to_linear_table();
        let k = (c + r * side) * TEXEL_BYTES;
        let b = &tile.texels[k..k + TEXEL_BYTES];
        DVec3::new(
            linear[b[0] as usize] as f64,
            linear[b[1] as usize] as f64,
            linear[b[2] as usize] as f64,
        )
    }
}

impl MipTexture for TexturedFrame {
    fn level_count(&self) -> u32 {
        self.pyramid.layout.level_count()
    }

    fn bilinear(&self, level: u32, s: f64, t: f64) -> DVec3 {
        let taps = self.pyramid.taps(level, s, t);
        let Some(tile) = self.tiles.get(&taps.tile) else {
            // Every tile the frame samples was loaded; a coarser one stands in otherwise.
            return self.bilinear(level + 1, s, t);
        };
        let side = self.pyramid.layout.stored_side();
        let [c0, c1] = taps.cols;
        let [r0, r1] = taps.rows;
        let [wx, wy] = taps.weights;
        let south = Self::texel(tile, side, c0, r0).lerp(Self::texel(tile, side, c1, r0), wx);
        let north = Self::texel(tile, side, c0, r1).lerp(Self::texel(tile, side, c1, r1), wx);
        south.lerp(north, wy)
    }
}

impl FootprintAlbedo for TexturedFrame {
    fn tangent_slope(&self, position: DVec3) -> Option<DVec2> {
        self.terrain.surface_slope(position.x, position.y)
    }

    fn albedo(&self, footprint: &GroundFootprint) -> DVec3 {
        let texels = self.pyramid.texel_footprint(footprint);
        filter_texture(self, &texels, self.filter, self.min_level)
    }
}
