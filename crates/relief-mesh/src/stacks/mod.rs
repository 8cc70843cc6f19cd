//! Material stacks to meshes (Löffler et al. 2011, sections 3.2 to 3.4): the quadrangulation
//! pipeline (density by coverage, smoothing, classification, allocation, attributes, faces)
//! over an octree of nodes with crack-free stitching between levels of detail.
//!
//! - [`lattice`]: where a level's density points lie, boxes of points;
//! - [`density`]: stacks to density and the [`Smoothing`] filter;
//! - [`cell_patches`]: one cell's surface patches (a vertex each, edge-manifold meshes);
//! - [`node_mesher`]: one node's mesh with topology fitting and T-junction removal;
//! - [`octree`]: the nodes, their selection by screen-space extent, balancing ([`NodeKey`]);
//! - [`stacks_mesher`]: the whole terrain at one level or for a camera ([`StacksMesher`]).

mod cell_patches;
mod density;
mod lattice;
mod node_mesher;
mod octree;
mod stacks_mesher;

pub use density::Smoothing;
pub use octree::NodeKey;
pub use stacks_mesher::{MeshStats, StacksMeshParams, StacksMesher};
