//! The maximum mipmap: a pyramid where each node holds the highest point of the surface above
//! its footprint (Dick et al. 2009, section 3.2; Tevs et al. 2008).

use crate::cell_grid::CellGrid;
use rayon::prelude::*;
use relief_core::{SampleRegion, Surface};

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
#[derive(Debug, Clone, PartialEq)]
pub struct MaxMipmap {
    values: Vec<f32>,
    levels: Vec<Level>,
}

/// Where one level lives inside the flat allocation.
#[derive(Debug, Clone, Copy, PartialEq)]
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
    /// Builds the pyramid of `grid` over the height field's `samples` (in parallel): every node
    /// computed as [`MaxMipmap::update`] computes the nodes above a region, here the whole field.
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
        let mut pyramid = MaxMipmap { values: vec![f32::NEG_INFINITY; total], levels };
        let width = grid.samples_width();
        let height = samples.len().checked_div(width).unwrap_or(0);
        pyramid.update(grid, samples, SampleRegion::whole(width, height));
        pyramid
    }

    /// Recomputes the nodes above the samples of `region` after they changed, and only those:
    /// afterwards the pyramid equals [`MaxMipmap::build`] over the new samples, bit for bit.
    ///
    /// `grid` must be the grid the pyramid was built for (same size and holes; its height
    /// bounds do not matter here) and `region` must hold every changed sample. A `triangles`
    /// cell has four samples, so the cells updated reach one column and row below the region.
    /// Costs a few nodes per level for a small region.
    pub fn update(&mut self, grid: &CellGrid, samples: &[f32], region: SampleRegion) {
        let (cells_x, cells_y) = (grid.cells_x(), grid.cells_y());
        if self.levels.len() < 2
            || (self.levels[0].nodes_x, self.levels[0].nodes_y) != (cells_x, cells_y)
        {
            return;
        }
        // The cells whose test reads a sample of the region.
        let reach = match grid.surface() {
            Surface::Boxes => 0,
            Surface::Triangles => 1,
        };
        let cells = SampleRegion::new(
            region.col0.saturating_sub(reach),
            region.row0.saturating_sub(reach),
            region.col1,
            region.row1,
        )
        .clamped(cells_x, cells_y);
        if cells.is_empty() {
            return;
        }
        // Inclusive node ranges of the level below, starting with the cells.
        let (mut x0, mut y0, mut x1, mut y1) =
            (cells.col0, cells.row0, cells.col1 - 1, cells.row1 - 1);
        for l in 1..self.levels.len() {
            (x0, y0, x1, y1) = (x0 >> 1, y0 >> 1, x1 >> 1, y1 >> 1);
            let (below, level) = (self.levels[l - 1], self.levels[l]);
            let (done, rest) = self.values.split_at_mut(level.offset);
            let fine = &done[below.offset.min(done.len())..];
            let (y1, x1) = (y1.min(level.nodes_y - 1), x1.min(level.nodes_x - 1));
            // Rows of 2 x 2 blocks in parallel (a simulation rewrites the whole field).
            let block_row = 4 * level.blocks_x;
            let rows = &mut rest[..block_row * level.nodes_y.div_ceil(2)];
            rows.par_chunks_mut(block_row)
                .enumerate()
                .skip(y0 >> 1)
                .take((y1 >> 1) + 1 - (y0 >> 1))
                .for_each(|(by, blocks)| {
                    for y in (2 * by).max(y0)..=(2 * by + 1).min(y1) {
                        for x in x0..=x1 {
                            let node = node_max(grid, samples, fine, l, below, x, y);
                            blocks[level.index(x, y) - by * block_row] = node;
                        }
                    }
                });
        }
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

    /// The maximum stored in node (x, y) of stored `level` (1 or more), which must exist.
    #[inline]
    pub(crate) fn node(&self, level: usize, x: usize, y: usize) -> f32 {
        let l = self.levels[level];
        self.values[l.offset + l.index(x, y)]
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

/// The maximum of node (x, y) of level `l` over its (up to) 2x2 children in the level
/// `below`: cells of the grid for level 1, else the stored values `fine` of that level.
#[inline]
fn node_max(
    grid: &CellGrid,
    samples: &[f32],
    fine: &[f32],
    l: usize,
    below: Level,
    x: usize,
    y: usize,
) -> f32 {
    if l == 1 && !grid.has_empty_cells() {
        return level_one_max(grid, samples, below, x, y);
    }
    let mut node = f32::NEG_INFINITY;
    for cy in (2 * y)..(2 * y + 2).min(below.nodes_y) {
        for cx in (2 * x)..(2 * x + 2).min(below.nodes_x) {
            let v = if l == 1 { grid.cell_max(samples, cx, cy) } else { fine[below.index(cx, cy)] };
            node = node.max(v);
        }
    }
    node
}

/// Node (x, y) of level 1 of a grid without holes straight from the samples its (up to) 2 x 2
/// cells reach, each read once: 3 x 3 samples for `triangles` (a cell's four corners), 2 x 2
/// texels for `boxes`, clipped to the grid. Equals the maximum of the cells' maxima.
#[inline(always)]
fn level_one_max(grid: &CellGrid, samples: &[f32], cells: Level, x: usize, y: usize) -> f32 {
    let reach = match grid.surface() {
        Surface::Boxes => 0,
        Surface::Triangles => 1,
    };
    let w = grid.samples_width();
    let (c0, r0) = (2 * x, 2 * y);
    let c1 = (2 * x + 1).min(cells.nodes_x - 1) + reach;
    let r1 = (2 * y + 1).min(cells.nodes_y - 1) + reach;
    let mut node = f32::NEG_INFINITY;
    for row in samples[r0 * w..(r1 + 1) * w].chunks_exact(w) {
        for &v in &row[c0..=c1] {
            node = node.max(v);
        }
    }
    node
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
