//! The field a node contours: its level's density with the points next to a coarser
//! neighbour fitted to that neighbour's values (section 3.4.1's topology fitting).

use super::node_mesh::{LevelField, NodeJob};
use std::borrow::Cow;

/// The field a node contours: its level's density with the fitted points replaced.
pub(crate) struct Field<'a> {
    /// The node's own level.
    pub fine: &'a LevelField<'a>,
    /// The coarser neighbours' level, where the node has coarser neighbours.
    pub coarse: Option<&'a LevelField<'a>>,
    /// Whether each point of the fine block took the coarser level's value.
    fitted: Vec<bool>,
    /// Fitted values, channel-major, over the fine block.
    pub values: Cow<'a, [Vec<f32>]>,
}

impl<'a> Field<'a> {
    /// The field of `job`'s node: `fine`'s density, with the points within two points of a
    /// coarser neighbour taking `coarse`'s value at `floor(p / 2)` (topology fitting).
    pub(crate) fn fitted_to(
        job: &NodeJob,
        fine: &'a LevelField<'a>,
        coarse: Option<&'a LevelField<'a>>,
    ) -> Self {
        let block = fine.density.block;
        let mut fitted = Vec::new();
        let mut values = Cow::Borrowed(fine.density.channels.as_slice());
        if let Some(coarse) = coarse {
            fitted = vec![false; block.len()];
            let values = values.to_mut();
            for (i, flag) in fitted.iter_mut().enumerate() {
                let p = block.point(i);
                let in_band = job
                    .coarser
                    .iter()
                    .any(|(lo, hi)| (0..3).all(|a| p[a] >= lo[a] - 2 && p[a] <= hi[a] + 2));
                if in_band {
                    *flag = true;
                    let q = p.map(|c| c.div_euclid(2));
                    for (channel, v) in values.iter_mut().enumerate() {
                        v[i] = coarse.density.at(channel, q);
                    }
                }
            }
        }
        Field { fine, coarse, fitted, values }
    }

    /// Channel `channel` at lattice point `p`, fitted.
    #[inline]
    pub(crate) fn at(&self, channel: usize, p: [i32; 3]) -> f32 {
        self.values[channel][self.fine.density.block.index_of(p)]
    }

    /// Whether lattice point `p` took the coarser level's value.
    #[inline]
    pub(crate) fn fitted(&self, p: [i32; 3]) -> bool {
        self.fitted[self.fine.density.block.index_of(p)]
    }
}

/// Corner `c` of `cell`: `cell + bits(c)` (x in bit 0, y in bit 1, z in bit 2).
#[inline]
pub(crate) fn corner(cell: [i32; 3], c: usize) -> [i32; 3] {
    [cell[0] + (c & 1) as i32, cell[1] + ((c >> 1) & 1) as i32, cell[2] + ((c >> 2) & 1) as i32]
}
