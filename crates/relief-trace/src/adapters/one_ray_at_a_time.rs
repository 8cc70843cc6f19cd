//! A tracer seen one ray at a time, for measuring what batches gain.

use crate::{Hit, Tracer};
use relief_core::{Ray, Surface};

/// The tracer it wraps, seen one ray at a time: its batch methods are the trait's loops over
/// single rays (what `relief bench --single-rays` measures).
pub struct OneRayAtATime<'a>(pub &'a dyn Tracer);

impl Tracer for OneRayAtATime<'_> {
    fn name(&self) -> &'static str {
        self.0.name()
    }

    fn surface(&self) -> Surface {
        self.0.surface()
    }

    fn bounds(&self) -> relief_core::Aabb {
        self.0.bounds()
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        self.0.intersect_counted(ray, steps)
    }

    fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
        self.0.occluded_counted(ray, steps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{build_tracer, TracerKind};
    use relief_core::{DVec3, GridGeometry, HeightField};
    use std::sync::Arc;

    #[test]
    fn its_batches_give_the_hits_of_single_rays() {
        let samples = (0..16 * 16).map(|k| (k % 5) as f32).collect();
        let field = Arc::new(HeightField::new(16, 16, samples, GridGeometry::unit()).unwrap());
        let inner = build_tracer(field, Surface::Triangles, TracerKind::Mipmap);
        let single = OneRayAtATime(inner.as_ref());
        let rays: Vec<Ray> = (0..16)
            .map(|k| Ray::new(DVec3::new(k as f64, -5.0, 20.0), DVec3::new(0.1, 1.0, -1.0)))
            .collect();
        let (mut hits, mut steps) = (vec![None; 16], vec![0; 16]);
        single.intersect_batch(&rays, &mut hits, &mut steps);
        let expected: Vec<Option<Hit>> = rays.iter().map(|r| inner.intersect(r)).collect();
        assert_eq!(hits, expected);
        assert!(hits.iter().any(Option::is_some));
    }
}
