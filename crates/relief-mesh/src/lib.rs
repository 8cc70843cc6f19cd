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
//!   comparison renderer of the hybrid paper, meshed per frame for a camera;
//! - [`TerrainMesh`]: the material-stack pipeline's named parts of quads and triangles, and
//!   [`export`] to write one as glTF binary (`.glb`), OBJ or PLY.
//!
//! Filling a G-buffer: draw every mesh into one [`RasterTarget`] (each with its own
//! `id_offset`), then for each pixel whose id falls in a mesh's range, take
//! [`IndexedMesh::hit`] of that triangle with the pixel's [`relief_core::Camera::ray`]
//! (position, normal facing the eye, barycentrics) and
//! [`IndexedMesh::interpolate_attributes`].
//!
//! ```
//! use relief_core::{Camera, DVec3, GridGeometry, HeightField, SampleRegion, Surface};
//! use relief_mesh::{height_field_mesh, Culling, RasterTarget, Rasterizer};
//! let field = HeightField::new(4, 4, (0..16).map(|k| (k % 3) as f32).collect(),
//!     GridGeometry::unit()).unwrap();
//! // Two cells of the grid, overlapping by one sample, meshed apart and drawn together.
//! let west = height_field_mesh(&field, Surface::Triangles, SampleRegion::new(0, 0, 3, 4)).unwrap();
//! let east = height_field_mesh(&field, Surface::Triangles, SampleRegion::new(2, 0, 4, 4)).unwrap();
//! let camera = Camera::look_at(DVec3::new(-3.0, -4.0, 6.0), DVec3::new(2.0, 2.0, 1.0),
//!     DVec3::Z, 50.0, 32, 24).unwrap();
//! let rasterizer = Rasterizer::new().with_culling(Culling::BackFaces);
//! let mut target = RasterTarget::for_camera(&camera);
//! rasterizer.draw(&camera, &west, 0, &mut target).unwrap();
//! rasterizer.draw(&camera, &east, west.triangle_count() as u32, &mut target).unwrap();
//! let (distance, id) = target.get(16, 12).unwrap();
//! let hit = if (id as usize) < west.triangle_count() {
//!     west.hit(id, &camera.ray(16, 12))
//! } else {
//!     east.hit(id - west.triangle_count() as u32, &camera.ray(16, 12))
//! }
//! .unwrap();
//! assert!((hit.t - distance as f64).abs() < 1e-5 * hit.t);
//! ```
#![deny(missing_docs)]
#![deny(unsafe_code)]

#[cfg(target_arch = "x86_64")]
mod block_scan;
mod box_mesh;
mod clipmap;
mod error;
pub mod export;
mod height_field_mesh;
mod height_pyramid;
mod indexed_mesh;
mod mesh_builder;
mod part_measures;
mod raster_target;
mod rasterizer;
mod stacks;
mod terrain_mesh;
mod tile_scan;
mod tile_sinks;
mod triangle_setup;

pub use clipmap::{Clipmap, ClipmapParams};
pub use error::MeshError;
pub use height_field_mesh::height_field_mesh;
pub use height_pyramid::HeightPyramid;
pub use indexed_mesh::{IndexedMesh, MeshHit};
pub use part_measures::Component;
pub use raster_target::RasterTarget;
pub use rasterizer::{Culling, DrawStats, Rasterizer};
pub use stacks::{MeshStats, NodeKey, Smoothing, StacksMeshParams, StacksMesher};
pub use terrain_mesh::{MeshPart, TerrainMesh};
pub use tile_scan::ScanLanes;
