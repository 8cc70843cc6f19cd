//! The tiles in memory: a least-recently-used cache bounded by the bytes its tiles hold, for
//! height tiles ([`LoadedTile`]) and texture tiles ([`TextureTile`]) alike.
//!
//! The cache counts frames: a tile used by the frame being drawn is never dropped to make room
//! for another, so tiles loaded ahead of the camera cannot push out the ones on screen.

use crate::store::LoadedTile;
use crate::texture_store::TextureTile;
use crate::TileId;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// A tile a [`TileCache`] can hold: it knows which tile it is and the bytes it takes.
pub trait CachedTile: Send + Sync {
    /// Which tile.
    fn tile_id(&self) -> TileId;
    /// Bytes it holds in memory.
    fn tile_bytes(&self) -> u64;
}

impl CachedTile for LoadedTile {
    fn tile_id(&self) -> TileId {
        self.id
    }
    fn tile_bytes(&self) -> u64 {
        self.bytes
    }
}

impl CachedTile for TextureTile {
    fn tile_id(&self) -> TileId {
        self.id
    }
    fn tile_bytes(&self) -> u64 {
        self.bytes
    }
}

/// Loaded tiles, at most `budget` bytes of them; the least recently used go first, never one
/// the current frame uses.
#[derive(Debug)]
pub struct TileCache<T: CachedTile = LoadedTile> {
    budget: u64,
    state: Mutex<State<T>>,
}

#[derive(Debug)]
struct State<T> {
    tiles: HashMap<TileId, Entry<T>>,
    bytes: u64,
    clock: u64,
    frame: u64,
}

#[derive(Debug)]
struct Entry<T> {
    tile: Arc<T>,
    /// When it was last used, on the cache's clock.
    used: u64,
    /// The last frame that used it.
    frame: u64,
}

impl<T: CachedTile> TileCache<T> {
    /// An empty cache of at most `budget` bytes.
    pub fn new(budget: u64) -> Self {
        // Frame 0 is no frame: tiles inserted but not used yet carry it.
        let state = State { tiles: HashMap::new(), bytes: 0, clock: 0, frame: 1 };
        TileCache { budget, state: Mutex::new(state) }
    }

    /// The most bytes it holds.
    pub fn budget(&self) -> u64 {
        self.budget
    }

    /// The bytes its tiles hold now.
    pub fn bytes(&self) -> u64 {
        self.lock().bytes
    }

    /// How many tiles it holds.
    pub fn len(&self) -> usize {
        self.lock().tiles.len()
    }

    /// Whether it holds no tile.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether tile `id` is in memory (without marking it used).
    pub fn contains(&self, id: TileId) -> bool {
        self.lock().tiles.contains_key(&id)
    }

    /// Starts a new frame: the tiles the last frame used may be dropped again.
    pub fn begin_frame(&self) {
        self.lock().frame += 1;
    }

    /// Tile `id` if it is in memory, marked as just used, by the current frame.
    pub fn get(&self, id: TileId) -> Option<Arc<T>> {
        let mut state = self.lock();
        state.clock += 1;
        let (now, frame) = (state.clock, state.frame);
        state.tiles.get_mut(&id).map(|entry| {
            (entry.used, entry.frame) = (now, frame);
            entry.tile.clone()
        })
    }

    /// Keeps `tile`, dropping the least recently used tiles that the current frame does not
    /// use until the bytes fit the budget. Returns whether it kept the tile: not when that
    /// would drop a tile of the current frame, or when the tile is larger than the budget.
    pub fn insert(&self, tile: Arc<T>) -> bool {
        let (id, bytes) = (tile.tile_id(), tile.tile_bytes());
        let mut state = self.lock();
        if state.tiles.contains_key(&id) {
            return true;
        }
        let frame = state.frame;
        let droppable: u64 =
            state.tiles.values().filter(|e| e.frame < frame).map(|e| e.tile.tile_bytes()).sum();
        if state.bytes - droppable + bytes > self.budget {
            return false;
        }
        while state.bytes + bytes > self.budget {
            let oldest = state.tiles.iter().filter(|(_, e)| e.frame < frame);
            let oldest = oldest.min_by_key(|(_, e)| e.used).map(|(id, _)| *id);
            let gone = state.tiles.remove(&oldest.expect("droppable tiles")).expect("present");
            state.bytes -= gone.tile.tile_bytes();
        }
        state.clock += 1;
        let used = state.clock;
        state.bytes += bytes;
        state.tiles.insert(id, Entry { tile, used, frame: 0 });
        true
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State<T>> {
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::TileRecord;
    use crate::layout::Rect;

    fn tile(col: u32, bytes: u64) -> Arc<LoadedTile> {
        Arc::new(LoadedTile {
            id: TileId { level: 0, col, row: 0 },
            rect: Rect { min: [0.0; 2], max: [1.0; 2] },
            record: TileRecord { min: 0.0, max: 1.0, error: 0.0, has_voids: false, checksum: 0 },
            heights: None,
            bytes,
        })
    }

    #[test]
    fn the_cache_never_holds_more_than_its_budget_and_drops_the_least_recently_used() {
        let cache = TileCache::new(1000);
        for k in 0..50u32 {
            cache.begin_frame();
            assert!(cache.insert(tile(k, 100 + (k as u64 * 37) % 250)));
            // Counted independently of the cache's own counter.
            let held: u64 = (0..50)
                .filter_map(|c| cache.get(TileId { level: 0, col: c, row: 0 }))
                .map(|t| t.bytes)
                .sum();
            assert!(held <= 1000, "{held} bytes held");
            assert_eq!(held, cache.bytes());
        }
        let cache = TileCache::new(300);
        cache.insert(tile(0, 100));
        cache.insert(tile(1, 100));
        cache.insert(tile(2, 100));
        cache.get(TileId { level: 0, col: 0, row: 0 });
        cache.insert(tile(3, 100));
        assert!(cache.contains(TileId { level: 0, col: 0, row: 0 }));
        assert!(!cache.contains(TileId { level: 0, col: 1, row: 0 }));
        assert!(!cache.insert(tile(4, 301)));
        assert!(!cache.contains(TileId { level: 0, col: 4, row: 0 }));
    }

    #[test]
    fn tiles_of_the_current_frame_are_never_dropped() {
        let cache = TileCache::new(300);
        for col in 0..3 {
            assert!(cache.insert(tile(col, 100)));
        }
        cache.begin_frame();
        let id = |col| TileId { level: 0, col, row: 0 };
        cache.get(id(0));
        cache.get(id(2));
        // Room only by dropping tile 1, which this frame does not use.
        assert!(cache.insert(tile(3, 100)));
        assert!(!cache.contains(id(1)));
        // No room without dropping a tile of this frame.
        cache.get(id(3));
        assert!(!cache.insert(tile(4, 100)));
        assert!([0, 2, 3].iter().all(|&c| cache.contains(id(c))));
        cache.begin_frame();
        assert!(cache.insert(tile(4, 100)));
        assert!(cache.bytes() <= 300);
    }
}
