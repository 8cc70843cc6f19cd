//! Precomputed safety shapes for exact, fast rendering of static height fields
//! (Baboud, Eisemann and Seidel 2011).
//!
//! - [`frame`]: the four ray classes and their local frames;
//! - [`dual`]: sets of lines as convex polygons in dual space;
//! - [`limiting`]: limiting triangles, for all rays or exterior rays, with `phi_max`;
//! - [`nbuffer`]: sliding-window maxima for the conservative cones;
//! - [`precompute`]: one class's radii and cones;
//! - [`shapes`]: the shapes of a field, built in parallel;
//! - [`cache`]: shapes on disk, keyed by the field's content and the options;
//! - [`tracer`]: the marching.

pub mod cache;
pub mod dual;
pub mod frame;
pub mod limiting;
pub mod nbuffer;
pub mod options;
pub mod precompute;
pub mod shapes;
pub mod tracer;

pub use cache::{CacheOutcome, ShapeCache};
pub use options::{ConeMode, RaySet, SafetyOptions, ShapeLayout};
pub use shapes::{Progress, SafetyShapes};
pub use tracer::{FinalTest, SafetyTracer};
