//! The brute-force reference the tests hold tracers against: relief-trace's conformance
//! suite's ([`relief_trace::conformance::first_hit`]), which intersects the ray with every
//! face of the solid in world space and shares no code with the tracers' traversal.

use relief_core::{HeightField, Ray, Surface};
use relief_trace::conformance::{self, Floor};

/// First parameter in the ray's range at which it is inside the solid of `surface`.
pub fn first_hit(field: &HeightField, surface: Surface, ray: &Ray) -> Option<f64> {
    conformance::first_hit(field, surface, Floor::LowestSample, ray, 0.0).map(|hit| hit.t)
}
