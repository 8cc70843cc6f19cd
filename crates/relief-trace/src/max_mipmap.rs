//! The maximum mipmap: a pyramid where each node holds the highest point of the surface above
//! its footprint (Dick et al. 2009, section 3.2; Tevs et al. 2008).

use crate::cell_grid::CellGrid;
use rayon::prelude::*;

/// A pyramid of maxima over a [`CellGrid`], all stored levels in one flat allocation.
///
/// Level 0 stands for the cells themselves (a cell's maximum is the highest of its samples) and
/// is not stored: tracers test cells exactly instead. A node of level 1 holds the maximum over
/// its (up to) 2x2 cells, one of level `l + 1` the maximum of the (up to) 2x2 nodes below it.
/// Any grid size works: a level has `ceil(cells / 2^l)` nodes per axis, and the top level has
/// one node. The pyramid takes about a third of the memory of the samples.
///
/// Each level is stored in blocks of 2x2 nodes, one block per node of the level above, so the
/// four children of a node sit side by side in 16 bytes (`MaxMipmap::children`); blocks
/// follow the nodes above row by row, and entries outside the grid hold minus infinity.
#[derive(Debug, Clone)]
pub struct MaxMipmap {
    values: Vec<f32>,
    levels: Vec<Level>,
}

/// Where one level lives inside the flat allocation.
#[derive(Debug, Clone, Copy)]
struct Level {
    offset: usize,
    nodes_x: usize,
    nodes_y: usize,
    /// Blocks of 2x2 nodes per row: the level above's nodes along x.
    blocks_x: usize,
}

impl Level {
    /// Index of node (x, y) inside the level.
    #[inline(always)]
    fn index(&self, x: usize, y: usize) -> usize {
        4 * ((x >> 1) + (y >> 1) * self.blocks_x) + (x & 1) + 2 * (y & 1)
    }
}

impl MaxMipmap {
    /// Builds the pyramid of `grid` over the height field's `samples` (in parallel).
    pub fn build(grid: &CellGrid, samples: &[f32]) -> Self {
        let (mut nx, mut ny) = (grid.cells_x(), grid.cells_y());
        let mut levels = vec![Level { offset: 0, nodes_x: nx, nodes_y: ny, blocks_x: 0 }];
        let mut total = 0;
        while !grid.is_empty() && (nx > 1 || ny > 1) {
            nx = nx.div_ceil(2);
            ny = ny.div_ceil(2);
            let blocks_x = nx.div_ceil(2);
            levels.push(Level { offset: total, nodes_x: nx, nodes_y: ny, blocks_x });
            total += 4 * blocks_x * ny.div_ceil(2);
        }
        let mut values = vec![f32::NEG_INFINITY; total];
        for l in 1..levels.len() {
            let (below, level) = (levels[l - 1], levels[l]);
            let (done, rest) = values.split_at_mut(level.offset);
            let fine = &done[below.offset.min(done.len())..];
            let end = 4 * level.blocks_x * level.nodes_y.div_ceil(2);
            // One row of blocks (two rows of nodes) at a time, in parallel.
            rest[..end].par_chunks_mut(4 * level.blocks_x).enumerate().for_each(|(by, row)| {
                for (k, node) in row.iter_mut().enumerate() {
                    let (x, y) = (2 * (k / 4) + (k & 1), 2 * by + ((k >> 1) & 1));
                    if x >= level.nodes_x || y >= level.nodes_y {
                        continue;
                    }
                    for cy in (2 * y)..(2 * y + 2).min(below.nodes_y) {
                        for cx in (2 * x)..(2 * x + 2).min(below.nodes_x) {
                            let v = if l == 1 {
                                grid.cell_max(samples, cx, cy)
                            } else {
                                fine[below.index(cx, cy)]
                            };
                            *node = node.max(v);
                        }
                    }
                }
            });
        }
        MaxMipmap { values, levels }
    }

    /// Index of the coarsest level (a single node); 0 for a single cell.
    pub fn top_level(&self) -> usize {
        self.levels.len() - 1
    }

    /// Number of nodes of `level` along x and y.
    pub fn nodes(&self, level: usize) -> (usize, usize) {
        let l = self.levels[level];
        (l.nodes_x, l.nodes_y)
    }

    /// The maximum stored in node (x, y) of `level`; `None` outside the level and for level 0,
    /// which is not stored.
    #[inline]
    pub fn get(&self, level: usize, x: usize, y: usize) -> Option<f32> {
        if level == 0 {
            return None;
        }
        let l = self.levels.get(level)?;
        (x < l.nodes_x && y < l.nodes_y).then(|| self.values[l.offset + l.index(x, y)])
    }

    /// The maxima of the four children at stored `level` (1 or more) of node (x, y) one level
    /// up, which must exist: `[(2x, 2y), (2x+1, 2y), (2x, 2y+1), (2x+1, 2y+1)]`, minus
    /// infinity for children outside the grid.
    #[inline(always)]
    pub(crate) fn children(&self, level: usize, x: usize, y: usize) -> &[f32; 4] {
        let l = self.levels[level];
        let start = l.offset + 4 * (x + y * l.blocks_x);
        self.values[start..start + 4].try_into().expect("a block holds four nodes")
    }

    /// Bytes used by all levels.
    pub fn memory_bytes(&self) -> usize {
        self.values.len() * std::mem::size_of::<f32>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::{GridGeometry, HeightField, Surface};

    #[test]
    fn every_node_holds_the_maximum_of_its_cells() {
        for (w, h) in [(1, 1), (2, 1), (5, 3), (8, 8), (9, 17)] {
            let samples: Vec<f32> = (0..w * h).map(|k| ((k * 7919) % 23) as f32).collect();
            let field = HeightField::new(w, h, samples, GridGeometry::unit()).unwrap();
            let grid = CellGrid::new(&field, Surface::Boxes);
            let mipmap = MaxMipmap::build(&grid, field.samples());
            for level in 1..=mipmap.top_level() {
                let (nx, ny) = mipmap.nodes(level);
                for y in 0..ny {
                    for x in 0..nx {
                        let side = 1 << level;
                        let mut want = f32::NEG_INFINITY;
                        for cy in (y * side)..((y + 1) * side).min(h) {
                            for cx in (x * side)..((x + 1) * side).min(w) {
                                want = want.max(field.sample(cx, cy));
                            }
                        }
                        assert_eq!(mipmap.get(level, x, y), Some(want), "{w}x{h} level {level}");
                        let block = mipmap.children(level, x / 2, y / 2);
                        assert_eq!(block[(x & 1) + 2 * (y & 1)], want);
                    }
                }
                assert_eq!(mipmap.get(level, nx, 0), None);
            }
            assert_eq!(mipmap.nodes(mipmap.top_level()), (1, 1));
        }
    }
}
