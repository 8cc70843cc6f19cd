//! What the meshing of one octree node takes and makes: its level's lattice and density, the
//! job's origin, coarser neighbours and colours, and the node's mesh of vertices named by key.

use super::density::Density;
use super::lattice::{Block, Lattice};
use relief_core::DVec3;

/// The iso-value of the density: half covered.
pub(crate) const ISO: f32 = 0.5;

/// One part's mesh made by one node: vertices named by key, faces in local indices.
#[derive(Debug, Clone, Default)]
pub(crate) struct NodePart {
    /// The key of each vertex (see [`vertex_key`]).
    pub keys: Vec<u128>,
    /// Whether another node may make the same vertex: a cell on the node's border (its ring
    /// of overlap, or its last cell, which is the next node's ring) or of a coarser level.
    pub shared: Vec<bool>,
    /// Positions, world.
    pub positions: Vec<DVec3>,
    /// Unit normals pointing out of the volume.
    pub normals: Vec<[f32; 3]>,
    /// Linear RGB colours.
    pub colors: Vec<[f32; 3]>,
    /// Quads, counter-clockwise from outside.
    pub quads: Vec<[u32; 4]>,
    /// Triangles where stitching collapsed a corner.
    pub triangles: Vec<[u32; 3]>,
}

/// The meshes of one node: the solid, then the liquid.
#[derive(Debug, Clone, Default)]
pub(crate) struct NodeMesh {
    /// Solid then water.
    pub parts: [NodePart; 2],
}

/// The name of the vertex of patch `patch` of cell `cell` at `level`.
#[inline]
pub(crate) fn vertex_key(level: usize, cell: [i32; 3], patch: u8) -> u128 {
    ((level as u128) << 112)
        | ((patch as u128) << 96)
        | ((cell[0] as u32 as u128) << 64)
        | ((cell[1] as u32 as u128) << 32)
        | (cell[2] as u32 as u128)
}

/// One level's data a node reads: its lattice and density.
pub(crate) struct LevelField<'a> {
    /// The level's index, 0 finest.
    pub level: usize,
    /// Where its points lie.
    pub lattice: &'a Lattice,
    /// Its density over the block the node needs.
    pub density: Density,
    /// Whether its liquid channel was smoothed.
    pub smoothed: bool,
}

/// What the meshing of a node needs besides the densities.
pub(crate) struct NodeJob<'a> {
    /// The node's first own lattice point.
    pub origin: [i32; 3],
    /// Cells per axis.
    pub n: i32,
    /// Lattice boxes (closed, in this node's level's points) of the coarser neighbours.
    pub coarser: &'a [([i32; 3], [i32; 3])],
    /// Linear colour of each per-material channel's material.
    pub colors: &'a [[f32; 3]],
    /// Linear colour of the liquid.
    pub liquid_color: [f32; 3],
    /// The terrain's footprint, world x and y: its lowest corner, then its highest.
    pub domain: [[f64; 2]; 2],
}

/// The lattice points a node's own level must cover: its cells' corners and their Sobel
/// neighbours.
pub(crate) fn fine_block(origin: [i32; 3], n: i32) -> Block {
    Block::between(origin.map(|o| o - 2), origin.map(|o| o + n + 2))
}

/// The coarser level's points a node with coarser neighbours needs.
pub(crate) fn coarse_block(origin: [i32; 3], n: i32) -> Block {
    Block::between(
        origin.map(|o| (o - 2).div_euclid(2) - 1),
        origin.map(|o| (o + n + 1).div_euclid(2) + 3),
    )
}
