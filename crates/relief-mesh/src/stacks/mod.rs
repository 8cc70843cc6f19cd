//! Material stacks to meshes (Löffler et al. 2011, sections 3.2 to 3.4): the quadrangulation
//! pipeline (density by coverage, smoothing, classification, allocation, attributes, faces)
//! over an octree of nodes with crack-free stitching between levels of detail.
//!
//! - [`lattice`]: where a level's density points lie, boxes of points;
//! - [`column_field`]: one stack's density along its column (exact layer ends, thin layers kept);
//! - [`density`]: stacks to density and the [`Smoothing`] filter;
//! - [`cell_patches`]: one cell's surface patches (a vertex each, edge-manifold meshes);
//! - [`node_mesh`]: what meshing one node takes (its level's field, the job) and makes;
//! - [`fitted_field`]: a node's density fitted to its coarser neighbours;
//! - [`vertex_table`]: a node's vertices, made on first use and named by key;
//! - [`node_mesher`]: one node's mesh with topology fitting and T-junction removal;
//! - [`octree`]: the nodes, their selection by screen-space extent, balancing ([`NodeKey`]);
//! - [`node_columns`]: where the layers within each node's reach lie (empty nodes skipped);
//! - [`view_culling`]: the nodes a camera cannot see;
//! - [`node_cache`]: node meshes kept across frames, node meshing amortised over frames;
//! - [`node_joins`]: node meshes joined for export or appended for drawing;
//! - [`stacks_mesher`]: the whole terrain at one level or for a camera ([`StacksMesher`]).

mod cell_patches;
mod column_field;
mod density;
mod fitted_field;
mod lattice;
mod node_cache;
mod node_columns;
mod node_joins;
mod node_maker;
mod node_mesh;
mod node_mesher;
mod octree;
mod stacks_mesher;
mod vertex_table;
mod view_culling;

pub use density::Smoothing;
pub use octree::NodeKey;
pub use stacks_mesher::{MeshStats, StacksMeshParams, StacksMesher};
