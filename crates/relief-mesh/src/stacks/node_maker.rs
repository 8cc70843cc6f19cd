//! What meshing one octree node reads, gathered in one value that the frame's meshing and the
//! meshing done ahead in the background (`node_cache.rs`) share: the mipmap, each level's
//! lattice and filters, the materials' colours and the terrain's footprint.

use super::density::{Channels, Density};
use super::lattice::{Block, Lattice};
use super::node_mesh::{coarse_block, fine_block, LevelField, NodeJob, NodeMesh};
use super::node_mesher::mesh_node;
use super::octree::NodeKey;
use relief_core::StacksMipmap;

/// Everything [`NodeMaker::make`] reads, made once by the mesher.
#[derive(Debug)]
pub(crate) struct NodeMaker {
    pub(crate) mipmap: StacksMipmap,
    pub(crate) lattices: Vec<Lattice>,
    pub(crate) channels: Channels,
    /// The smoothing filter's kernel per level: the same width in metres at every level (a
    /// coarser level's stacks are already averaged over its cells).
    pub(crate) kernels: Vec<Vec<f32>>,
    /// The liquid's kernel per level: the same where it is at least 3/4 of a cell wide, none
    /// where it is narrower. Water is flat already; a narrow filter only thickens its thin
    /// sheets (measured: +33 % of a shallow pond's water at level 1).
    pub(crate) liquid_kernels: Vec<Vec<f32>>,
    pub(crate) colors: Vec<[f32; 3]>,
    pub(crate) liquid_color: [f32; 3],
    /// The terrain's footprint, world x and y: lowest corner, highest corner.
    pub(crate) domain: [[f64; 2]; 2],
    /// Cells a node along each axis.
    pub(crate) n: i32,
}

impl NodeMaker {
    /// The kernels of level `level`'s solids and liquids.
    pub(crate) fn kernels(&self, level: usize) -> [&[f32]; 2] {
        [&self.kernels[level], &self.liquid_kernels[level]]
    }

    /// Meshes one node of `key`'s level next to the coarser leaves `coarser`.
    pub(crate) fn make(&self, key: &NodeKey, coarser: &[NodeKey]) -> NodeMesh {
        let level = key.level as usize;
        let n = self.n;
        let o = key.origin(n);
        let levels = self.mipmap.levels();
        let density = |l: usize, block: Block| {
            Density::new(&levels[l], &self.lattices[l], &self.channels, block, self.kernels(l))
        };
        let fine = LevelField {
            level,
            lattice: &self.lattices[level],
            density: density(level, fine_block(o, n)),
            liquid_smoothed: self.liquid_kernels[level].len() > 1,
        };
        let boxes: Vec<([i32; 3], [i32; 3])> = coarser
            .iter()
            .map(|c| {
                let origin = c.origin(n);
                (origin.map(|v| 2 * v), origin.map(|v| 2 * (v + n)))
            })
            .collect();
        let coarse = (!coarser.is_empty() && level + 1 < levels.len()).then(|| LevelField {
            level: level + 1,
            lattice: &self.lattices[level + 1],
            density: density(level + 1, coarse_block(o, n)),
            liquid_smoothed: self.liquid_kernels[level + 1].len() > 1,
        });
        let job = NodeJob {
            origin: o,
            n,
            coarser: &boxes,
            colors: &self.colors,
            liquid_color: self.liquid_color,
            domain: self.domain,
        };
        mesh_node(&job, &fine, coarse.as_ref())
    }
}
