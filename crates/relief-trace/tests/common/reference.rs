//! The tests' independent brute force: the conformance suite's reference
//! ([`relief_trace::conformance::first_hit`]: every face of the solid in world space, nothing
//! shared with the tracers' traversal), as the parameter of the first hit. The tests of other
//! crates include this file by path and enable relief-trace's `conformance` feature.

use relief_core::{HeightField, Ray, Surface};
use relief_trace::conformance::{self, Floor};

/// First parameter in the ray's range at which it is inside the solid of `surface`, the solid
/// reaching down to the field's lowest sample as the tracers clip it.
pub fn first_hit(field: &HeightField, surface: Surface, ray: &Ray) -> Option<f64> {
    conformance::first_hit(field, surface, Floor::LowestSample, ray, 0.0).map(|hit| hit.t)
}
