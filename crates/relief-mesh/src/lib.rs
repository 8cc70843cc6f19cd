//! relief-mesh: triangle meshes and the CPU rasterizer every relief renderer shares.
//!
//! - [`IndexedMesh`]: world-space positions, triangles and optional per-vertex attributes,
//!   validated, with the exact ray-plane [`IndexedMesh::hit`] a G-buffer is filled from;
//! - [`Rasterizer`]: binned into screen tiles, tile-parallel (rayon) and deterministic,
//!   watertight (top-left rule on homogeneous edge functions), drawing both windings and
//!   triangles that reach behind the eye; each covered pixel gets the exact distance along its
//!   camera ray ([`relief_core::Camera::ray`]) to the triangle's plane, so rasterized and
//!   ray-cast pixels agree; it writes a [`RasterTarget`] of distances and triangle ids;
//! - [`height_field_mesh`]: the solid an exact tracer intersects (surface, walls, bottom) for
//!   a block of a height field, in either [`relief_core::Surface`], so cells can be meshed one
//!   by one and drawn without cracks;
//! - [`Clipmap`]: geometry clipmaps (Losasso & Hoppe 2004) over a [`HeightPyramid`], the
//!   comparison renderer of the hybrid paper, meshed per frame for a camera.
#![deny(missing_docs)]

mod box_mesh;
mod clipmap;
mod error;
mod height_field_mesh;
mod height_pyramid;
mod indexed_mesh;
mod raster_target;
mod rasterizer;
mod triangle_setup;

pub use clipmap::{Clipmap, ClipmapParams};
pub use error::MeshError;
pub use height_field_mesh::height_field_mesh;
pub use height_pyramid::HeightPyramid;
pub use indexed_mesh::{IndexedMesh, MeshHit};
pub use raster_target::RasterTarget;
pub use rasterizer::{Culling, DrawStats, Rasterizer};
