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
/// one node. The pyramid takes a third of the memory of the samples.
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
}

impl MaxMipmap {
    /// Builds the pyramid of `grid` over the height field's `samples` (level 1 in parallel).
    pub fn build(grid: &CellGrid, samples: &[f32]) -> Self {
        let (mut nx, mut ny) = (grid.cells_x(), grid.cells_y());
        let mut levels = vec![Level { offset: 0, nodes_x: nx, nodes_y: ny }];
        let mut total = 0;
        while !grid.is_empty() && (nx > 1 || ny > 1) {
            nx = nx.div_ceil(2);
            ny = ny.div_ceil(2);
            levels.push(Level { offset: total, nodes_x: nx, nodes_y: ny });
            total += nx * ny;
        }
        let mut values = vec![f32::NEG_INFINITY; total];
        if let Some(first) = levels.get(1).copied() {
            let (cells_x, cells_y) = (grid.cells_x(), grid.cells_y());
            let level1 = &mut values[..first.nodes_x * first.nodes_y];
            level1.par_chunks_mut(first.nodes_x).enumerate().for_each(|(y, row)| {
                for (x, node) in row.iter_mut().enumerate() {
                    for cy in (2 * y)..(2 * y + 2).min(cells_y) {
                        for cx in (2 * x)..(2 * x + 2).min(cells_x) {
                            *node = node.max(grid.cell_max(samples, cx, cy));
                        }
                    }
                }
            });
        }
        for l in 2..levels.len() {
            let (fine, coarse) = (levels[l - 1], levels[l]);
            let (below, above) = values.split_at_mut(coarse.offset);
            let below = &below[fine.offset..];
            for y in 0..coarse.nodes_y {
                for x in 0..coarse.nodes_x {
                    let node = &mut above[x + y * coarse.nodes_x];
                    for fy in (2 * y)..(2 * y + 2).min(fine.nodes_y) {
                        for fx in (2 * x)..(2 * x + 2).min(fine.nodes_x) {
                            *node = node.max(below[fx + fy * fine.nodes_x]);
                        }
                    }
                }
            }
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
        (x < l.nodes_x && y < l.nodes_y).then(|| self.values[l.offset + x + y * l.nodes_x])
    }

    /// The maximum stored in node (x, y) of stored `level` (1 or more), which must exist.
    #[inline(always)]
    pub(crate) fn node_max(&self, level: usize, x: usize, y: usize) -> f32 {
        *self.node_ref(level, x, y)
    }

    /// Where the maximum of node (x, y) of stored `level` (1 or more) lives.
    #[inline(always)]
    pub(crate) fn node_ref(&self, level: usize, x: usize, y: usize) -> &f32 {
        let l = self.levels[level];
        &self.values[l.offset + x + y * l.nodes_x]
    }

    /// Bytes used by all levels.
    pub fn memory_bytes(&self) -> usize {
        self.values.len() * std::mem::size_of::<f32>()
    }
}
