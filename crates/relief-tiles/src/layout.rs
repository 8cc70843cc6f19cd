//! The shape of a tile pyramid: its levels, the tiles of each level, which samples a tile
//! holds and where it lies in the world.
//!
//! Level 0 is the raster itself (`width x height` samples); level `l + 1` averages blocks of
//! 2x2 samples of level `l`, so it has `ceil(width / 2^(l+1))` samples per row. Every level is
//! cut into tiles of `tile x tile` samples; tile `(col, row)` of level `l` covers the level's
//! samples `[col * tile, (col + 1) * tile)` along x (likewise along y) and exactly the four
//! tiles `(2 col .. 2 col + 1, 2 row .. 2 row + 1)` of level `l - 1`, so the tiles form a
//! quadtree. The top level has one tile. A tile stores a ring of one more sample on every side
//! (`(tile + 2)^2` samples; beyond the raster's edge the edge sample repeats), which the
//! `triangles` surface needs to reach across the tile's edges.

use relief_core::{GridGeometry, Surface};
use std::ops::Range;

/// One tile of the pyramid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TileId {
    /// Pyramid level, 0 the finest.
    pub level: u32,
    /// Column of tiles within the level, 0 westmost.
    pub col: u32,
    /// Row of tiles within the level, 0 southmost.
    pub row: u32,
}

impl std::fmt::Display for TileId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "tile (level {}, column {}, row {})", self.level, self.col, self.row)
    }
}

/// A rectangle of the world's xy plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// South-west corner.
    pub min: [f64; 2],
    /// North-east corner.
    pub max: [f64; 2],
}

/// The levels and tiles of a pyramid over a `width x height` raster.
#[derive(Debug, Clone, PartialEq)]
pub struct PyramidLayout {
    width: u64,
    height: u64,
    tile: u32,
    /// Per level: tiles along x and y, and the index of the level's first tile.
    levels: Vec<LevelShape>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct LevelShape {
    tiles_x: u32,
    tiles_y: u32,
    first: u64,
}

/// The smallest tile size a pyramid accepts.
pub const MIN_TILE: u32 = 4;

impl PyramidLayout {
    /// The layout of a `width x height` raster cut into tiles of `tile` samples a side.
    /// Panics when the raster is empty or `tile` is below [`MIN_TILE`] (callers check both).
    pub fn new(width: u64, height: u64, tile: u32) -> Self {
        assert!(width > 0 && height > 0 && tile >= MIN_TILE, "empty raster or tiny tile");
        let mut levels = Vec::new();
        let (mut w, mut h, mut first) = (width, height, 0u64);
        loop {
            let tiles_x = w.div_ceil(tile as u64) as u32;
            let tiles_y = h.div_ceil(tile as u64) as u32;
            levels.push(LevelShape { tiles_x, tiles_y, first });
            first += tiles_x as u64 * tiles_y as u64;
            if tiles_x == 1 && tiles_y == 1 {
                break;
            }
            (w, h) = (w.div_ceil(2), h.div_ceil(2));
        }
        PyramidLayout { width, height, tile, levels }
    }

    /// Samples per row of level 0.
    pub fn width(&self) -> u64 {
        self.width
    }

    /// Rows of level 0.
    pub fn height(&self) -> u64 {
        self.height
    }

    /// Samples along a tile's side, its ring not counted.
    pub fn tile(&self) -> u32 {
        self.tile
    }

    /// Samples along a stored tile's side: the tile and its ring.
    pub fn stored_side(&self) -> usize {
        self.tile as usize + 2
    }

    /// Samples a stored tile holds.
    pub fn stored_samples(&self) -> usize {
        self.stored_side() * self.stored_side()
    }

    /// Number of levels; the last has one tile.
    pub fn level_count(&self) -> u32 {
        self.levels.len() as u32
    }

    /// The coarsest level's one tile.
    pub fn root(&self) -> TileId {
        TileId { level: self.level_count() - 1, col: 0, row: 0 }
    }

    /// Samples per row and rows of `level`.
    pub fn level_size(&self, level: u32) -> (u64, u64) {
        let scale = 1u64 << level;
        (self.width.div_ceil(scale), self.height.div_ceil(scale))
    }

    /// Tiles along x and y of `level`.
    pub fn tiles_of(&self, level: u32) -> (u32, u32) {
        let shape = self.levels[level as usize];
        (shape.tiles_x, shape.tiles_y)
    }

    /// Tiles of every level together.
    pub fn tile_count(&self) -> u64 {
        let last = self.levels.last().expect("a pyramid has a level");
        last.first + last.tiles_x as u64 * last.tiles_y as u64
    }

    /// The position of `id` in the store's table and data: levels from the finest, each row
    /// by row.
    pub fn index_of(&self, id: TileId) -> u64 {
        let shape = self.levels[id.level as usize];
        debug_assert!(id.col < shape.tiles_x && id.row < shape.tiles_y, "{id} outside");
        shape.first + id.col as u64 + id.row as u64 * shape.tiles_x as u64
    }

    /// The tile at position `index` of the store (the inverse of [`PyramidLayout::index_of`]).
    pub fn id_at(&self, index: u64) -> TileId {
        let level = self.levels.iter().rposition(|l| l.first <= index).expect("index in range");
        let shape = self.levels[level];
        let k = index - shape.first;
        TileId {
            level: level as u32,
            col: (k % shape.tiles_x as u64) as u32,
            row: (k / shape.tiles_x as u64) as u32,
        }
    }

    /// Whether `id` names a tile of this pyramid.
    pub fn contains(&self, id: TileId) -> bool {
        self.levels.get(id.level as usize).is_some_and(|s| id.col < s.tiles_x && id.row < s.tiles_y)
    }

    /// The tiles of the level below that `id` covers (up to four; fewer at the raster's
    /// north and east edges), none for level 0.
    pub fn children(&self, id: TileId) -> impl Iterator<Item = TileId> + '_ {
        let below = id.level.checked_sub(1);
        (0..4u32).filter_map(move |k| {
            let child =
                TileId { level: below?, col: 2 * id.col + (k & 1), row: 2 * id.row + k / 2 };
            self.contains(child).then_some(child)
        })
    }

    /// The tile of the level above that covers `id`; `None` for the root.
    pub fn parent(&self, id: TileId) -> Option<TileId> {
        (id.level + 1 < self.level_count()).then_some(TileId {
            level: id.level + 1,
            col: id.col / 2,
            row: id.row / 2,
        })
    }

    /// The first level sample (column, row) a stored tile holds: one before the tile, its
    /// ring. The stored samples are this one plus `0..stored_side()` along each axis, clamped
    /// to the level's samples.
    pub fn stored_origin(&self, id: TileId) -> (i64, i64) {
        let t = self.tile as i64;
        (id.col as i64 * t - 1, id.row as i64 * t - 1)
    }

    /// The stored samples of tile `id` that are samples of its level, as ranges of the stored
    /// tile's columns and rows: every stored sample but the ring's repeats of the edge sample
    /// beyond the level's edges.
    pub fn stored_within_level(&self, id: TileId) -> (Range<usize>, Range<usize>) {
        let (width, height) = self.level_size(id.level);
        let (c0, r0) = self.stored_origin(id);
        let side = self.stored_side() as i64;
        let axis = |first: i64, size: u64| {
            let lo = (-first).clamp(0, side);
            let hi = (size as i64 - first).clamp(lo, side);
            lo as usize..hi as usize
        };
        (axis(c0, width), axis(r0, height))
    }

    /// The world rectangle tile `id` answers for: its footprint on level 0's texels, clipped to
    /// the raster, and for the `triangles` surface to the sample centres (from half a texel in
    /// from the raster's edges).
    pub fn rect(&self, id: TileId, geometry: &GridGeometry, surface: Surface) -> Rect {
        let span = self.tile as u64 * (1u64 << id.level);
        let inset = match surface {
            Surface::Boxes => 0.0,
            Surface::Triangles => 0.5,
        };
        let axis = |i: u32, size: u64, spacing: f64, origin: f64| {
            let lo = ((i as u64 * span) as f64).max(inset);
            let hi = (((i as u64 + 1) * span).min(size) as f64).min(size as f64 - inset);
            (origin + lo * spacing, origin + hi * spacing)
        };
        let (x0, x1) = axis(id.col, self.width, geometry.dx, geometry.origin.x);
        let (y0, y1) = axis(id.row, self.height, geometry.dy, geometry.origin.y);
        Rect { min: [x0, y0], max: [x1, y1] }
    }

    /// The geometry of a stored tile's samples as a height field of its own: the level's
    /// spacing, origin at the stored tile's first sample.
    pub fn tile_geometry(&self, id: TileId, geometry: &GridGeometry) -> GridGeometry {
        let scale = (1u64 << id.level) as f64;
        let (c0, r0) = self.stored_origin(id);
        GridGeometry {
            dx: geometry.dx * scale,
            dy: geometry.dy * scale,
            z_scale: geometry.z_scale,
            origin: relief_core::DVec2::new(
                geometry.origin.x + c0 as f64 * geometry.dx * scale,
                geometry.origin.y + r0 as f64 * geometry.dy * scale,
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_halve_until_one_tile_and_indices_round_trip() {
        let layout = PyramidLayout::new(1000, 300, 128);
        assert_eq!(layout.level_count(), 4);
        assert_eq!(layout.tiles_of(0), (8, 3));
        assert_eq!(layout.tiles_of(1), (4, 2));
        assert_eq!(layout.tiles_of(2), (2, 1));
        assert_eq!(layout.tiles_of(3), (1, 1));
        assert_eq!(layout.level_size(3), (125, 38));
        assert_eq!(layout.tile_count(), 24 + 8 + 2 + 1);
        for index in 0..layout.tile_count() {
            assert_eq!(layout.index_of(layout.id_at(index)), index);
        }
    }

    #[test]
    fn children_cover_the_parent_and_stop_at_the_edges() {
        let layout = PyramidLayout::new(1000, 300, 128);
        let kids: Vec<_> = layout.children(TileId { level: 1, col: 3, row: 1 }).collect();
        assert_eq!(
            kids,
            vec![TileId { level: 0, col: 6, row: 2 }, TileId { level: 0, col: 7, row: 2 }]
        );
        for kid in kids {
            assert_eq!(layout.parent(kid), Some(TileId { level: 1, col: 3, row: 1 }));
        }
        assert_eq!(layout.children(TileId { level: 0, col: 0, row: 0 }).count(), 0);
        assert_eq!(layout.parent(layout.root()), None);
    }

    #[test]
    fn rectangles_tile_the_raster_on_every_level() {
        let layout = PyramidLayout::new(1000, 300, 128);
        let g = GridGeometry {
            dx: 2.0,
            dy: 3.0,
            z_scale: 1.0,
            origin: relief_core::DVec2::new(10.0, 20.0),
        };
        let root = layout.rect(layout.root(), &g, Surface::Triangles);
        assert_eq!(root, Rect { min: [11.0, 21.5], max: [10.0 + 999.5 * 2.0, 20.0 + 299.5 * 3.0] });
        let a = layout.rect(TileId { level: 1, col: 0, row: 0 }, &g, Surface::Boxes);
        let b = layout.rect(TileId { level: 1, col: 1, row: 0 }, &g, Surface::Boxes);
        assert_eq!((a.min, a.max[0]), ([10.0, 20.0], 10.0 + 256.0 * 2.0));
        assert_eq!(a.max[0], b.min[0]);
    }

    #[test]
    fn the_ring_beyond_the_level_is_left_out_of_the_samples_within_it() {
        let layout = PyramidLayout::new(20, 9, 8);
        // Tile (0, 0) of level 0: its ring's first column and row lie before the raster.
        assert_eq!(layout.stored_within_level(TileId { level: 0, col: 0, row: 0 }), (1..10, 1..10));
        // Tile (2, 1): columns 15..=19 and rows 7..=8 of the raster.
        assert_eq!(layout.stored_within_level(TileId { level: 0, col: 2, row: 1 }), (0..5, 0..2));
        // Level 1 is 10 x 5 samples: tile (1, 0) holds its columns 7..=9 and rows 0..=4.
        assert_eq!(layout.stored_within_level(TileId { level: 1, col: 1, row: 0 }), (0..3, 1..6));
    }
}
