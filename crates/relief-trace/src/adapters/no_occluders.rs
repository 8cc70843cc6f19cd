//! The shadow "tracer" of a picture drawn without shadows: it meets nothing.

use crate::{Hit, Tracer};
use relief_core::{Ray, Surface};

/// A tracer that meets nothing (every ray misses): the shadow tracer of a rasterized mesh,
/// which has no exact tracer for shadow rays.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoOccluders;

impl Tracer for NoOccluders {
    fn name(&self) -> &'static str {
        "none"
    }

    fn surface(&self) -> Surface {
        Surface::Triangles
    }

    /// An empty box: nothing to hit.
    fn bounds(&self) -> relief_core::Aabb {
        relief_core::Aabb::new(relief_core::DVec3::INFINITY, relief_core::DVec3::NEG_INFINITY)
    }

    fn intersect_counted(&self, _ray: &Ray, _steps: &mut u32) -> Option<Hit> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::DVec3;

    #[test]
    fn every_ray_misses() {
        let ray = Ray::new(DVec3::new(0.0, 0.0, 10.0), DVec3::new(0.0, 0.0, -1.0));
        assert!(NoOccluders.intersect(&ray).is_none());
        assert!(!NoOccluders.occluded(&ray));
    }
}
