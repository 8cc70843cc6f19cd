//! The tiles in memory: a least-recently-used cache bounded by the bytes its tiles hold, for
//! height tiles ([`LoadedTile`]) and texture tiles ([`TextureTile`]) alike.

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

/// Loaded tiles, at most `budget` bytes of them; the least recently used go first.
#[derive(Debug)]
pub struct TileCache<T: CachedTile = LoadedTile> {
    budget: u64,
    state: Mutex<State<T>>,
}

#[derive(Debug)]
struct State<T> {
    tiles: HashMap<TileId, (Arc<T>, u64)>,
    bytes: u64,
    clock: u64,
}

impl<T: CachedTile> TileCache<T> {
    /// An empty cache of at most `budget` bytes.
    pub fn new(budget: u64) -> Self {
        TileCache { budget, state: Mutex::new(State { tiles: HashMap::new(), bytes: 0, clock: 0 }) }
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

    /// Tile `id` if it is in memory, marked as just used.
    pub fn get(&self, id: TileId) -> Option<Arc<T>> {
        let mut state = self.lock();
        state.clock += 1;
        let now = state.clock;
        state.tiles.get_mut(&id).map(|(tile, used)| {
            *used = now;
            tile.clone()
        })
    }

    /// Keeps `tile`, dropping the least recently used tiles until the bytes fit the budget; a
    /// tile larger than the whole budget is not kept.
    pub fn insert(&self, tile: Arc<T>) {
        let (id, bytes) = (tile.tile_id(), tile.tile_bytes());
        let mut state = self.lock();
        if bytes > self.budget || state.tiles.contains_key(&id) {
            return;
        }
        while state.bytes + bytes > self.budget {
            let oldest = state.tiles.iter().min_by_key(|(_, (_, used))| *used).map(|(id, _)| *id);
            let Some(oldest) = oldest else { break };
            let (gone, _) = state.tiles.remove(&oldest).expect("the oldest is there");
            state.bytes -= gone.tile_bytes();
        }
        state.clock += 1;
        let now = state.clock;
        state.bytes += bytes;
        state.tiles.insert(id, (tile, now));
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
            tracer: None,
            bytes,
        })
    }

    #[test]
    fn the_cache_never_holds_more_than_its_budget_and_drops_the_least_recently_used() {
        let cache = TileCache::new(1000);
        for k in 0..50u32 {
            cache.insert(tile(k, 100 + (k as u64 * 37) % 250));
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
        cache.insert(tile(4, 301));
        assert!(!cache.contains(TileId { level: 0, col: 4, row: 0 }));
    }
}
