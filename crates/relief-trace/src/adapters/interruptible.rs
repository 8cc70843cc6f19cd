//! A tracer that stops when its frame is no longer needed: once its flag is set, every ray
//! misses at once, so that an outdated full-size frame ends in moments. Until then it is the
//! tracer it wraps, method for method, so the frames it finishes are exact.

use crate::{Hit, Medium, MlhmHit, MlhmMode, MlhmTracer, Tracer};
use relief_core::{DVec2, DVec3, Mlhm, Ray, Surface};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// `inner`, stopped once `stop` is set.
pub struct Interruptible<'a, T: ?Sized> {
    /// The tracer.
    pub inner: &'a T,
    /// Set when the frame is no longer wanted.
    pub stop: &'a AtomicBool,
}

impl<T: ?Sized> Interruptible<'_, T> {
    /// Whether the frame is no longer wanted.
    fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

impl<T: Tracer + ?Sized> Tracer for Interruptible<'_, T> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn surface(&self) -> Surface {
        self.inner.surface()
    }

    fn bounds(&self) -> relief_core::Aabb {
        self.inner.bounds()
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        if self.stopped() {
            return None;
        }
        self.inner.intersect_counted(ray, steps)
    }

    fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
        !self.stopped() && self.inner.occluded_counted(ray, steps)
    }

    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], steps: &mut [u32]) {
        if self.stopped() {
            return hits.fill(None);
        }
        self.inner.intersect_batch(rays, hits, steps)
    }

    fn occluded_batch(&self, rays: &[Ray], occluded: &mut [bool], steps: &mut [u32]) {
        if self.stopped() {
            return occluded.fill(false);
        }
        self.inner.occluded_batch(rays, occluded, steps)
    }
}

impl<T: MlhmTracer + ?Sized> MlhmTracer for Interruptible<'_, T> {
    fn map(&self) -> &Arc<Mlhm> {
        self.inner.map()
    }

    fn origin(&self) -> DVec2 {
        self.inner.origin()
    }

    fn intersect_mode_counted(
        &self,
        ray: &Ray,
        mode: MlhmMode,
        steps: &mut u32,
    ) -> Option<MlhmHit> {
        if self.stopped() {
            return None;
        }
        self.inner.intersect_mode_counted(ray, mode, steps)
    }

    fn occluded_mode(&self, ray: &Ray, mode: MlhmMode) -> bool {
        !self.stopped() && self.inner.occluded_mode(ray, mode)
    }

    fn medium(&self, p: DVec3) -> Medium {
        self.inner.medium(p)
    }

    fn surface_offset(&self) -> f64 {
        self.inner.surface_offset()
    }

    fn faceted(&self) -> bool {
        self.inner.faceted()
    }

    fn smoothing_radius(&self) -> Option<f64> {
        self.inner.smoothing_radius()
    }

    fn light_visibility(&self, ray: &Ray, steps: &mut u32) -> f64 {
        if self.stopped() {
            return 1.0;
        }
        self.inner.light_visibility(ray, steps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{build_tracer, TracerKind};
    use relief_core::{GridGeometry, HeightField};

    #[test]
    fn it_is_its_tracer_until_stopped_and_then_every_ray_misses() {
        let samples = (0..16 * 16).map(|k| (k % 7) as f32).collect();
        let field = Arc::new(HeightField::new(16, 16, samples, GridGeometry::unit()).unwrap());
        let inner = build_tracer(field, Surface::Triangles, TracerKind::Mipmap);
        let stop = AtomicBool::new(false);
        let tracer = Interruptible { inner: inner.as_ref(), stop: &stop };
        let rays: Vec<Ray> = (0..16)
            .map(|k| Ray::new(DVec3::new(k as f64, -5.0, 20.0), DVec3::new(0.1, 1.0, -1.0)))
            .collect();
        let (mut hits, mut steps) = (vec![None; 16], vec![0; 16]);
        tracer.intersect_batch(&rays, &mut hits, &mut steps);
        let expected: Vec<Option<Hit>> = rays.iter().map(|r| inner.intersect(r)).collect();
        assert_eq!(hits, expected);
        assert!(hits.iter().any(Option::is_some));
        stop.store(true, Ordering::Relaxed);
        tracer.intersect_batch(&rays, &mut hits, &mut steps);
        assert!(hits.iter().all(Option::is_none));
        assert!(rays.iter().all(|r| tracer.intersect(r).is_none() && !tracer.occluded(r)));
    }
}
