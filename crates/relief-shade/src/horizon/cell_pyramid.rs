//! A pyramid of maxima over the cells of a height field's `triangles` surface, for skipping
//! the stretches of a horizon's line that cannot raise it.

/// Maxima of the `triangles` surface over blocks of cells: level 0 holds a bound on each cell's
/// surface (its highest corner: the surface over a cell never rises above its corners), level
/// `l + 1` the highest of the (up to) 2x2 nodes of level `l` below each node.
#[derive(Debug, Clone)]
pub(crate) struct CellPyramid {
    /// Every level's maxima row by row, level 0 first.
    values: Vec<f32>,
    /// Per level: where it starts in `values`, and its nodes along x.
    levels: Vec<(usize, usize)>,
}

impl CellPyramid {
    /// The pyramid of `cells_x` x `cells_y` cells whose maxima are `cell_max(c, r)`.
    pub(crate) fn build(
        cells_x: usize,
        cells_y: usize,
        cell_max: &dyn Fn(usize, usize) -> f32,
    ) -> CellPyramid {
        let mut base = vec![f32::NEG_INFINITY; cells_x * cells_y];
        for r in 0..cells_y {
            for c in 0..cells_x {
                base[c + r * cells_x] = cell_max(c, r);
            }
        }
        let mut levels = vec![(cells_x, cells_y, base)];
        while let Some((nx, ny, below)) = levels.last().filter(|(nx, ny, _)| *nx > 1 || *ny > 1) {
            let (ux, uy) = (nx.div_ceil(2), ny.div_ceil(2));
            let mut above = vec![f32::NEG_INFINITY; ux * uy];
            for y in 0..*ny {
                for x in 0..*nx {
                    let node = &mut above[x / 2 + (y / 2) * ux];
                    *node = node.max(below[x + y * nx]);
                }
            }
            levels.push((ux, uy, above));
        }
        let mut values = Vec::with_capacity(levels.iter().map(|(_, _, v)| v.len()).sum());
        let mut starts = Vec::with_capacity(levels.len());
        for (nx, _, level) in levels {
            starts.push((values.len(), nx));
            values.extend_from_slice(&level);
        }
        CellPyramid { values, levels: starts }
    }

    /// The highest level (one node over every cell).
    pub(crate) fn top(&self) -> usize {
        self.levels.len() - 1
    }

    /// The maximum of node (`x`, `y`) of `level`.
    #[inline(always)]
    pub(crate) fn get(&self, level: usize, x: usize, y: usize) -> f32 {
        let (start, nx) = self.levels[level];
        self.values[start + x + y * nx]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_hold_the_highest_cell_below_them() {
        let cells = [9.0, 2.0, 7.0, 4.0, 11.0, 5.0];
        let pyramid = CellPyramid::build(3, 2, &|c, r| cells[c + 3 * r]);
        assert_eq!(pyramid.get(0, 0, 0), 9.0);
        assert_eq!(pyramid.get(0, 2, 1), 5.0);
        assert_eq!(pyramid.get(1, 0, 0), 11.0);
        assert_eq!(pyramid.get(1, 1, 0), 7.0);
        assert_eq!(pyramid.top(), 2);
        assert_eq!(pyramid.get(2, 0, 0), 11.0);
    }
}
