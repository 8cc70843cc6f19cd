//! Frames over a tile store: choosing the tiles, loading them (a loader thread and a cache),
//! and the [`TiledTerrain`] a frame traces.
//!
//! A still render waits for every tile it needs. A fly-through never waits: tiles not in
//! memory are asked of the loader thread (nearest first, then the tiles the camera's motion
//! will need next), and until they arrive finer tiles in memory that cover them stand in (when
//! the error bound grew), or else their nearest ancestor in memory (the root tile is always in
//! memory). Later frames refine as tiles arrive.

use crate::cache::TileCache;
use crate::lod::{select_tiles, tile_bounds};
use crate::store::LoadedTile;
use crate::tiled_terrain::{TiledTerrain, TreeNode};
use crate::{TileError, TileId, TileStore};
use rayon::prelude::*;
use relief_core::{Camera, Surface};
use std::collections::{HashMap, HashSet, VecDeque};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

/// What a frame asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRequest {
    /// Screen-space error tolerance in pixels (0: level 0 everywhere).
    pub max_error_px: f64,
    /// Leave out tiles wholly outside the view (false when shadow rays may need them).
    pub cull: bool,
    /// Wait for every tile (a still render); otherwise coarser tiles stand in.
    pub wait: bool,
}

/// What a frame did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameStats {
    /// Tiles the error bound asked for.
    pub tiles_wanted: usize,
    /// Tiles traced (with samples).
    pub tiles_drawn: usize,
    /// Wanted tiles not yet in memory, stood in for by a coarser one.
    pub tiles_standing_in: usize,
    /// Milliseconds the frame waited for tiles to load.
    pub io_wait_ms: f64,
    /// Bytes of tiles in memory after the frame's selection.
    pub resident_bytes: u64,
    /// The error tolerance used: the one asked for, or larger when the tiles it needs would
    /// not fit the cache.
    pub max_error_px: f64,
}

/// A tile store with its cache and loader, drawing frames.
pub struct TileStreamer {
    store: Arc<TileStore>,
    surface: Surface,
    cache: Arc<TileCache>,
    root: Arc<LoadedTile>,
    loader: Loader,
    /// The last frame's camera, to predict the next one's.
    last_eye: Mutex<Option<relief_core::DVec3>>,
}

impl TileStreamer {
    /// Opens frames over `store` on `surface` with a cache of `cache_bytes`, loading the root.
    pub fn new(store: TileStore, surface: Surface, cache_bytes: u64) -> Result<Self, TileError> {
        let store = Arc::new(store);
        let root = Arc::new(store.load(store.layout().root(), surface)?);
        let cache = Arc::new(TileCache::new(cache_bytes));
        let loader = Loader::start(store.clone(), surface, cache.clone());
        Ok(TileStreamer { store, surface, cache, root, loader, last_eye: Mutex::new(None) })
    }

    /// The store.
    pub fn store(&self) -> &TileStore {
        &self.store
    }

    /// The cache.
    pub fn cache(&self) -> &TileCache {
        &self.cache
    }

    /// The terrain for `camera` (see [`FrameRequest`]). Fails when a tile cannot be read, or
    /// when the error tolerance is 0 and the level-0 tiles of the view do not fit the cache.
    pub fn frame(
        &self,
        camera: &Camera,
        request: FrameRequest,
    ) -> Result<(TiledTerrain, FrameStats), TileError> {
        if let Some(error) = self.loader.take_error() {
            return Err(error);
        }
        self.cache.begin_frame();
        let (wanted, max_error_px) = self.fitting_selection(camera, request)?;
        let mut stats =
            FrameStats { tiles_wanted: wanted.len(), max_error_px, ..FrameStats::default() };
        // The wanted tiles' ancestors are kept in memory too: they stand in for tiles that have
        // not arrived yet.
        let ancestors = self.ancestors(&wanted);
        for &id in &ancestors {
            self.tile(id);
        }
        let mut have: HashMap<TileId, Arc<LoadedTile>> = HashMap::new();
        let mut missing = Vec::new();
        for &id in &wanted {
            match self.tile(id) {
                Some(tile) => drop(have.insert(id, tile)),
                None => missing.push(id),
            }
        }
        if request.wait {
            let started = Instant::now();
            let loaded: Vec<Result<Arc<LoadedTile>, TileError>> = missing
                .par_iter()
                .map(|&id| self.store.load(id, self.surface).map(Arc::new))
                .collect();
            for tile in loaded {
                let tile = tile?;
                self.cache.insert(tile.clone());
                self.cache.get(tile.id);
                have.insert(tile.id, tile);
            }
            stats.io_wait_ms = started.elapsed().as_secs_f64() * 1e3;
        } else {
            stats.tiles_standing_in = missing.len();
            // Missing ancestors first, coarsest first (each covers many missing tiles), then the
            // missing tiles nearest first (they cover the most pixels), then the tiles the
            // camera's motion will need.
            let distance = |id: &TileId| {
                let b = tile_bounds(&self.store, *id, self.surface);
                camera.eye().clamp(b.min, b.max).distance(camera.eye())
            };
            let mut queue: Vec<TileId> =
                ancestors.iter().copied().filter(|&id| !self.cache.contains(id)).collect();
            queue.sort_by(|a, b| b.level.cmp(&a.level).then(distance(a).total_cmp(&distance(b))));
            missing.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
            queue.extend(&missing);
            queue.extend(self.predicted_tiles(camera, request, max_error_px));
            self.loader.request(queue);
            // Finer tiles in memory that cover a missing one stand in for it (the view's
            // error bound grew); otherwise its nearest coarser tile in memory does.
            let mut cover = Vec::new();
            for id in missing {
                cover.clear();
                if !self.resident_cover(id, COVER_LEVELS, &mut cover) {
                    cover.push(self.nearest_loaded_ancestor(id));
                }
                have.extend(cover.drain(..).map(|tile| (tile.id, tile)));
            }
        }
        let terrain = self.terrain(have);
        stats.tiles_drawn = terrain.tile_count();
        stats.resident_bytes = self.cache.bytes() + self.root.bytes;
        Ok((terrain, stats))
    }

    /// Tiles `id` in memory: the root, or a cached tile.
    fn tile(&self, id: TileId) -> Option<Arc<LoadedTile>> {
        if id == self.root.id {
            return Some(self.root.clone());
        }
        self.cache.get(id)
    }

    /// The ancestors of `tiles` but the root, each once.
    fn ancestors(&self, tiles: &[TileId]) -> Vec<TileId> {
        let layout = self.store.layout();
        let mut seen = HashSet::new();
        for &id in tiles {
            let mut at = id;
            while let Some(parent) = layout.parent(at) {
                if parent == self.root.id || !seen.insert(parent) {
                    break;
                }
                at = parent;
            }
        }
        seen.into_iter().collect()
    }

    /// Pushes onto `out` tiles in memory, at most `levels` levels below `id`, that together
    /// cover it; false (and `out` as it was) when there are none such.
    fn resident_cover(&self, id: TileId, levels: u32, out: &mut Vec<Arc<LoadedTile>>) -> bool {
        let start = out.len();
        if levels == 0 || id.level == 0 {
            return false;
        }
        for child in self.store.layout().children(id) {
            match self.tile(child) {
                Some(tile) => out.push(tile),
                None if self.resident_cover(child, levels - 1, out) => {}
                None => {
                    out.truncate(start);
                    return false;
                }
            }
        }
        true
    }

    /// The coarser tile in memory nearest above `id` (the root at worst).
    fn nearest_loaded_ancestor(&self, id: TileId) -> Arc<LoadedTile> {
        let layout = self.store.layout();
        let mut at = id;
        while let Some(parent) = layout.parent(at) {
            if let Some(tile) = self.tile(parent) {
                return tile;
            }
            at = parent;
        }
        self.root.clone()
    }

    /// The wanted tiles at the asked tolerance, or at a coarser one when they and their
    /// ancestors would not fit the cache (each step 1.5 times the last). A frame that does not
    /// wait leaves a quarter of the cache for the tiles loaded ahead of the camera.
    fn fitting_selection(
        &self,
        camera: &Camera,
        request: FrameRequest,
    ) -> Result<(Vec<TileId>, f64), TileError> {
        let per_tile = estimated_tile_bytes(&self.store);
        let room = match request.wait {
            true => self.cache.budget(),
            false => self.cache.budget() / 4 * 3,
        };
        let mut tolerance = request.max_error_px;
        loop {
            let wanted = select_tiles(&self.store, camera, self.surface, tolerance, request.cull);
            let bytes = (wanted.len() + self.ancestors(&wanted).len()) as u64 * per_tile;
            if bytes <= room {
                return Ok((wanted, tolerance));
            }
            if tolerance == 0.0 {
                return Err(TileError::Invalid(format!(
                    "the view needs {} level-0 tiles ({} MiB in memory with the coarser tiles \
                     over them) at --max-error-px 0, more than the {} MiB the cache has for a \
                     frame; raise --cache-mb or --max-error-px",
                    wanted.len(),
                    bytes >> 20,
                    room >> 20
                )));
            }
            tolerance *= 1.5;
        }
    }

    /// The tiles the next frame will need if the camera keeps moving as it did.
    fn predicted_tiles(
        &self,
        camera: &Camera,
        request: FrameRequest,
        tolerance: f64,
    ) -> Vec<TileId> {
        let mut last = self.last_eye.lock().unwrap_or_else(|p| p.into_inner());
        let previous = last.replace(camera.eye());
        let Some(previous) = previous else { return Vec::new() };
        let motion = camera.eye() - previous;
        if motion.length_squared() == 0.0 {
            return Vec::new();
        }
        let ahead = 4.0 * motion;
        let Ok(next) = Camera::new(
            camera.eye() + ahead,
            camera.target() + ahead,
            camera.up(),
            camera.projection(),
            camera.width(),
            camera.height(),
        ) else {
            return Vec::new();
        };
        select_tiles(&self.store, &next, self.surface, tolerance, request.cull)
            .into_iter()
            .filter(|&id| !self.cache.contains(id))
            .collect()
    }

    /// The quadtree over the chosen tiles (a tile under another chosen one is dropped: the
    /// coarser one covers it).
    fn terrain(&self, chosen: HashMap<TileId, Arc<LoadedTile>>) -> TiledTerrain {
        let layout = self.store.layout();
        let covered_by_ancestor = |id: TileId| {
            let mut at = id;
            while let Some(parent) = layout.parent(at) {
                if chosen.contains_key(&parent) {
                    return true;
                }
                at = parent;
            }
            false
        };
        let kept: HashMap<TileId, Arc<LoadedTile>> = chosen
            .iter()
            .filter(|(id, _)| !covered_by_ancestor(**id))
            .map(|(id, t)| (*id, t.clone()))
            .collect();
        let mut inner: HashSet<TileId> = HashSet::new();
        for id in kept.keys() {
            let mut at = *id;
            while let Some(parent) = layout.parent(at) {
                if !inner.insert(parent) {
                    break;
                }
                at = parent;
            }
        }
        fn build(
            id: TileId,
            layout: &crate::PyramidLayout,
            kept: &HashMap<TileId, Arc<LoadedTile>>,
            inner: &HashSet<TileId>,
        ) -> Option<TreeNode> {
            if let Some(tile) = kept.get(&id) {
                return Some(TreeNode::Tile(tile.clone()));
            }
            inner.contains(&id).then(|| {
                TreeNode::Inner(
                    layout.children(id).filter_map(|c| build(c, layout, kept, inner)).collect(),
                )
            })
        }
        let g = self.store.geometry();
        let floor = self.store.floor() as f64 * g.z_scale;
        let root =
            build(layout.root(), layout, &kept, &inner).unwrap_or(TreeNode::Inner(Vec::new()));
        TiledTerrain::new(root, self.surface, floor, g.z_scale)
    }
}

/// How many levels finer the tiles standing in for a missing tile may be.
const COVER_LEVELS: u32 = 2;

/// Bytes a loaded tile of `store` takes at most (samples, hole flags, max mipmap).
pub fn estimated_tile_bytes(store: &TileStore) -> u64 {
    let n = store.layout().stored_samples() as u64;
    n * (4 + 2 + 1)
}

/// The loader thread: loads the tiles asked for, most urgent first, into the cache.
struct Loader {
    shared: Arc<LoaderShared>,
    thread: Option<JoinHandle<()>>,
}

struct LoaderShared {
    queue: Mutex<LoaderQueue>,
    wake: Condvar,
}

#[derive(Default)]
struct LoaderQueue {
    pending: VecDeque<TileId>,
    stop: bool,
    error: Option<TileError>,
}

impl Loader {
    fn start(store: Arc<TileStore>, surface: Surface, cache: Arc<TileCache>) -> Self {
        let shared = Arc::new(LoaderShared {
            queue: Mutex::new(LoaderQueue::default()),
            wake: Condvar::new(),
        });
        let worker = shared.clone();
        let thread = std::thread::Builder::new()
            .name("relief-tile-loader".into())
            .spawn(move || loop {
                let id = {
                    let mut queue = worker.queue.lock().unwrap_or_else(|p| p.into_inner());
                    loop {
                        if queue.stop {
                            return;
                        }
                        if let Some(id) = queue.pending.pop_front() {
                            break id;
                        }
                        queue = worker.wake.wait(queue).unwrap_or_else(|p| p.into_inner());
                    }
                };
                if cache.contains(id) {
                    continue;
                }
                match store.load(id, surface) {
                    Ok(tile) => drop(cache.insert(Arc::new(tile))),
                    Err(error) => {
                        let mut queue = worker.queue.lock().unwrap_or_else(|p| p.into_inner());
                        queue.error.get_or_insert(error);
                    }
                }
            })
            .expect("the loader thread starts");
        Loader { shared, thread: Some(thread) }
    }

    /// Replaces the queue with `ids`, in that order.
    fn request(&self, ids: Vec<TileId>) {
        let mut queue = self.shared.queue.lock().unwrap_or_else(|p| p.into_inner());
        queue.pending = ids.into_iter().collect();
        self.shared.wake.notify_one();
    }

    /// The first error the loader met, if any.
    fn take_error(&self) -> Option<TileError> {
        self.shared.queue.lock().unwrap_or_else(|p| p.into_inner()).error.take()
    }
}

impl Drop for Loader {
    fn drop(&mut self) {
        self.shared.queue.lock().unwrap_or_else(|p| p.into_inner()).stop = true;
        self.shared.wake.notify_one();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
