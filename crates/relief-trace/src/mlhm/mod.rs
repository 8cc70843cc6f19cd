//! Ray tracing of multi-layered height maps ([`relief_core::Mlhm`]; Nilles & Müller 2025,
//! section 4): the exact box tracers, the hierarchy of conservative node bounds they share with
//! the smooth implicit surface, and that surface's ray marcher.
//!
//! - [`boxes`]: the boxes a cell stands for in each [`MlhmMode`] and the exact slab test;
//! - [`cells`]: cells placed in the world, a cell's part of a ray and its first hit;
//! - [`naive`]: the baseline 2D DDA over every cell ([`MlhmNaiveTracer`]);
//! - [`hierarchy`]: the 2D hierarchy of node bounds ([`MlhmHierarchy`]) and their access;
//! - [`build`]: the hierarchy's parallel bottom-up build;
//! - [`bounds`]: how the hierarchy stores its bounds, as f32 or as f16 rounded outward;
//! - [`walk`]: the walk through the hierarchy both hierarchical tracers share;
//! - [`hierarchy_tracer`]: the hierarchical box tracer ([`MlhmHierarchyTracer`]);
//! - [`implicit`]: the smooth implicit surface of the boxes ([`MlhmImplicit`]);
//! - [`smooth_tracer`]: that surface ray marched ([`MlhmSmoothTracer`]);
//! - [`smooth_shading`]: the smooth tracer's hits, normals, medium and soft shadows;
//! - [`medium`]: which medium a point lies in ([`Medium`]);
//! - [`tracer`]: what every MLHM box tracer offers ([`MlhmTracer`]).

mod backtrack;
mod bounds;
mod boxes;
mod build;
mod cells;
mod hierarchy;
mod hierarchy_tracer;
mod implicit;
mod medium;
mod naive;
mod node_layer;
mod single_layer_merge;
mod smooth_shading;
mod smooth_tracer;
mod tracer;
mod walk;

pub use backtrack::MlhmBacktrack;
pub use boxes::{MlhmMaterial, MlhmMode};
pub use hierarchy::{MlhmHierarchy, MAX_HIERARCHY_LEVELS};
pub use hierarchy_tracer::MlhmHierarchyTracer;
pub use implicit::{MlhmField, MlhmFieldSample, MlhmImplicit, MlhmNormalScheme, HIT_FRACTION};
pub use medium::{medium_at, Medium};
pub use naive::MlhmNaiveTracer;
pub use node_layer::MlhmNodeLayer;
pub use smooth_tracer::{MlhmSmoothOptions, MlhmSmoothTracer};
pub use tracer::{MlhmHit, MlhmTracer};
