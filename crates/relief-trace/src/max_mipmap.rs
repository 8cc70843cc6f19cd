//! The maximum mipmap: a pyramid where each node holds the highest point of the surface above
//! its footprint (Dick et al. 2009, section 3.2; Tevs et al. 2008).

use crate::cell_grid::CellGrid;

/// A pyramid of maxima over a [`CellGrid`], all levels in one flat allocation.
///
/// Level 0 holds one value per cell (the cell's highest surface point); a node of level `l + 1`
/// is the maximum of the (up to) 2x2 nodes below it. Any grid size works: a level has
/// `ceil(cells / 2^l)` nodes per axis, and the top level has one node.
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
    /// Builds the pyramid of `grid` over the height field's `samples`.
    pub fn build(grid: &CellGrid, samples: &[f32]) -> Self {
        let (mut nx, mut ny) = (grid.cells_x(), grid.cells_y());
        let mut levels = vec![Level { offset: 0, nodes_x: nx, nodes_y: ny }];
        let mut total = nx * ny;
        while nx > 1 || ny > 1 {
            nx = nx.div_ceil(2);
            ny = ny.div_ceil(2);
            levels.push(Level { offset: total, nodes_x: nx, nodes_y: ny });
            total += nx * ny;
        }
        let mut values = Vec::with_capacity(total);
        for cy in 0..grid.cells_y() {
            for cx in 0..grid.cells_x() {
                values.push(grid.cell_max(samples, cx, cy));
            }
        }
        for pair in levels.windows(2) {
            let (fine, coarse) = (pair[0], pair[1]);
            for y in 0..coarse.nodes_y {
                for x in 0..coarse.nodes_x {
                    let mut m = f32::NEG_INFINITY;
                    for (fx, fy) in [
                        (2 * x, 2 * y),
                        (2 * x + 1, 2 * y),
                        (2 * x, 2 * y + 1),
                        (2 * x + 1, 2 * y + 1),
                    ] {
                        if fx < fine.nodes_x && fy < fine.nodes_y {
                            m = m.max(values[fine.offset + fx + fy * fine.nodes_x]);
                        }
                    }
                    values.push(m);
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

    /// The maximum stored in node (x, y) of `level`; `None` outside the level.
    #[inline]
    pub fn get(&self, level: usize, x: usize, y: usize) -> Option<f32> {
        let l = self.levels.get(level)?;
        (x < l.nodes_x && y < l.nodes_y).then(|| self.values[l.offset + x + y * l.nodes_x])
    }

    /// Bytes used by all levels.
    pub fn memory_bytes(&self) -> usize {
        self.values.len() * std::mem::size_of::<f32>()
    }
}
