//! A colour source that filters its texture over each pixel's footprint.

use crate::{DVec2, DVec3};

use super::GroundFootprint;

/// A colour source that filters its texture over each pixel's footprint: an ortho photo's mip
/// pyramid, filtered anisotropically (Dick et al. 2009, section 3.3).
pub trait FootprintAlbedo: Send + Sync + std::fmt::Debug {
    /// The slope (`dz/dx`, `dz/dy`) of the terrain's tangent plane at world `position`, from
    /// the heights around it; `None` to take the plane of the hit's normal instead.
    fn tangent_slope(&self, position: DVec3) -> Option<DVec2>;

    /// The linear RGB albedo averaged over `footprint`.
    fn albedo(&self, footprint: &GroundFootprint) -> DVec3;
}
