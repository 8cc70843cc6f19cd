//! What a tracer returns: the first point of a ray inside the terrain's solid.

use relief_core::DVec3;

/// The first point of a ray inside the terrain's solid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit: the distance from the origin when the direction is unit.
    pub t: f64,
    /// World position of the hit.
    pub position: DVec3,
    /// Unit geometric normal of the face hit, in world space, facing against the ray. A ray that
    /// starts inside the solid gets the reversed ray direction.
    pub normal: DVec3,
}
