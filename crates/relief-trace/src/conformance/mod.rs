//! A conformance suite for every [`Tracer`](crate::Tracer): one set of checks run on any
//! tracer, as a BVH library's test base runs one suite on every hierarchy. Behind the cargo
//! feature `conformance`, so that the crates holding other tracers (a tiled terrain, the
//! hybrid's far field) enable it in their dev-dependencies and run the same suite.
//!
//! [`Suite::run`] builds the tracer under test on seeded random terrains (1x1, 2x2, odd and
//! non-square sizes, flat, noisy, spiky, cliffs, integer heights, holes, unit and non-unit
//! spacing and height scale) for both surfaces, casts rays of every kind ([`RayKind`]: from
//! above, grazing, vertical, axis-aligned, from inside, from outside, misses), over their
//! whole range and limited ranges, single and in batches, and holds every answer against a
//! brute force independent of every tracer ([`first_hit`]): hit `t`, position and normal,
//! occlusion, the batch methods against the single-ray ones, and `bounds()` holding every
//! hit. The tolerances are stated in [`T_RELATIVE`], [`NORMAL_TOLERANCE`] and
//! [`GRAZE_RELATIVE`].
//!
//! ```
//! use relief_trace::conformance::Suite;
//! use relief_trace::{NaiveTracer, Tracer};
//! Suite::new()
//!     .terrains(4)
//!     .run(|field, surface| Some(Box::new(NaiveTracer::new(field.clone(), surface)) as Box<dyn Tracer>))
//!     .assert_conforms();
//! ```

mod brute_force;
mod rays;
mod report;
mod seeded;
mod suite;
mod terrains;
mod verdict;

pub use brute_force::{first_hit, Expected, Floor};
pub use rays::{ray, RayKind, RAY_KINDS};
pub use report::{Check, Failure, Report};
pub use seeded::Seeded;
pub use suite::Suite;
pub use terrains::{terrain, Relief, RELIEFS};
pub use verdict::{same_hit, Reference, GRAZE_RELATIVE, NORMAL_TOLERANCE, T_RELATIVE};
