//! relief-trace: exact intersection of rays with terrain, behind one trait.
//!
//! Every tracer implements [`Tracer`]: `intersect` finds the first point of a ray inside the
//! terrain's solid, `occluded` answers whether there is any (for shadow rays). Tracers of a
//! [`relief_core::HeightField`], all exact and agreeing with each other to rounding:
//!
//! - [`NaiveTracer`]: cell-by-cell traversal (Amanatides-Woo), the reference;
//! - [`MipmapTracer`]: max-mipmap quadtree traversal (Dick et al. 2009, section 3.2), and for
//!   batches of rays ([`Tracer::intersect_batch`]) coherent packets of up to 64 rays walking
//!   the pyramid together with SIMD node tests ([`Simd`]);
//! - [`SafetyTracer`]: marching with precomputed safety shapes, for static terrain and the
//!   `triangles` surface (Baboud et al. 2011; see [`safety`]).
//!
//! Shadow rays towards one sun can go through [`SunShadows`], which wraps any of them and
//! decides most of those rays without tracing, exactly, from a sweep along the sun's azimuth.
//!
//! The per-cell machinery of hybrid rendering (mesh near, ray cast far; Ammann et al. 2010)
//! is in [`hybrid`]; [`MipmapTracer::edit`] keeps the exact tracer up to date under edits.
//!
//! And of a multi-layered height map ([`relief_core::Mlhm`]):
//!
//! - [`MlhmNaiveTracer`]: box ray tracing by a 2D DDA over its cells, in the three
//!   [`MlhmMode`]s (Nilles & Müller 2025, 4.1);
//! - [`MlhmHierarchyTracer`]: the same hits through an [`MlhmHierarchy`] of conservative
//!   node bounds, a 2D DDA per level climbing back by an exit stack or a miss counter
//!   ([`MlhmBacktrack`]; Nilles & Müller 2025, 4.2);
//! - [`MlhmSmoothTracer`]: the smooth implicit surface of the boxes ([`MlhmImplicit`]), ray
//!   marched with adaptive steps inside the level-1 nodes of a padded hierarchy, with
//!   normals by finite differences and soft shadows (Nilles & Müller 2025, 3.3, 4.3-4.6).
//!
//! ```
//! use std::sync::Arc;
//! use relief_core::{GridGeometry, HeightField, Ray, Surface, DVec3};
//! use relief_trace::{build_tracer, TracerKind};
//! let field = Arc::new(HeightField::new(2, 2, vec![1.0; 4], GridGeometry::unit()).unwrap());
//! let tracer = build_tracer(field, Surface::Boxes, TracerKind::Mipmap);
//! let hit = tracer.intersect(&Ray::new(DVec3::new(1.0, 1.0, 5.0), -DVec3::Z)).unwrap();
//! assert_eq!(hit.t, 4.0);
//! ```
#![deny(missing_docs)]

pub mod adapters;
mod cell_grid;
#[cfg(feature = "conformance")]
pub mod conformance;
mod error;
mod hit;
pub mod hybrid;
mod max_mipmap;
mod mipmap_tracer;
mod mlhm;
mod naive_tracer;
mod packet;
pub mod safety;
mod shadow_sweep;
mod tracer;
mod tracer_kind;

pub use cell_grid::{CellGrid, CellRay, Entry, Segment};
pub use error::TraceError;
pub use hit::Hit;
pub use max_mipmap::MaxMipmap;
pub use mipmap_tracer::MipmapTracer;
pub use mlhm::{
    medium_at, Medium, MlhmBacktrack, MlhmField, MlhmFieldSample, MlhmHierarchy,
    MlhmHierarchyTracer, MlhmHit, MlhmImplicit, MlhmMaterial, MlhmMode, MlhmNaiveTracer,
    MlhmNodeLayer, MlhmNormalScheme, MlhmSmoothOptions, MlhmSmoothTracer, MlhmTracer, HIT_FRACTION,
    MAX_HIERARCHY_LEVELS,
};
pub use naive_tracer::NaiveTracer;
pub use packet::Simd;
pub use safety::{SafetyOptions, SafetyShapes, SafetyTracer};
pub use shadow_sweep::{SunShadows, DEFAULT_SHADOW_BLOCK, WALK_CELLS};
pub use tracer::Tracer;
pub use tracer_kind::{build_tracer, TracerKind};
