//! The tracer trait every acceleration scheme implements.

use crate::{Hit, MaxMipmap};
use relief_core::{Aabb, Ray, Surface};
use std::sync::Arc;

/// Exact ray intersection with one surface of a terrain.
///
/// The terrain stands for a solid (see [`Surface`]); `intersect` returns the smallest `t` in the
/// ray's `[t_min, t_max]` at which the ray is inside it. A ray that starts inside hits at `t_min`.
pub trait Tracer: Send + Sync {
    /// Short name for reports (e.g. `mipmap`).
    fn name(&self) -> &'static str;

    /// The surface this tracer intersects.
    fn surface(&self) -> Surface;

    /// The world-space box holding the solid this tracer intersects: every hit lies in it (to
    /// the rounding of `origin + t dir`), so a caller can clip rays to it or frame a camera
    /// on it. A side the solid is unbounded on (the columns of an MLHM reach down forever) is
    /// infinite.
    fn bounds(&self) -> Aabb;

    /// The first hit, counting traversal steps (visited cells or nodes) into `steps`.
    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit>;

    /// Whether any point of the ray within its range is inside the solid, counting steps.
    fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
        self.intersect_counted(ray, steps).is_some()
    }

    /// The first hit.
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.intersect_counted(ray, &mut 0)
    }

    /// Whether the ray is blocked within its range (for shadow rays).
    fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_counted(ray, &mut 0)
    }

    /// The first hits of many rays at once: `hits[k]` is `intersect(&rays[k])`, and the ray's
    /// traversal steps are added to `steps[k]`.
    ///
    /// Callers pass neighbouring rays together (a tile of camera pixels, the shadow rays of a
    /// tile): tracers that gain from coherence, such as [`crate::MipmapTracer`]'s ray
    /// packets, override this. Panics when the three slices differ in length.
    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], steps: &mut [u32]) {
        assert!(rays.len() == hits.len() && rays.len() == steps.len(), "batch slices differ");
        for ((ray, hit), steps) in rays.iter().zip(hits).zip(steps) {
            *hit = self.intersect_counted(ray, steps);
        }
    }

    /// Occlusion of many rays at once: `occluded[k]` is `occluded(&rays[k])`, with the ray's
    /// steps added to `steps[k]` (see [`Tracer::intersect_batch`]). Panics when the three
    /// slices differ in length.
    fn occluded_batch(&self, rays: &[Ray], occluded: &mut [bool], steps: &mut [u32]) {
        assert!(rays.len() == occluded.len() && rays.len() == steps.len(), "batch slices differ");
        for ((ray, blocked), steps) in rays.iter().zip(occluded).zip(steps) {
            *blocked = self.occluded_counted(ray, steps);
        }
    }

    /// The max mipmap this tracer traverses, if it keeps one: what is built over the same
    /// field and surface later (the sun's shadow sweep) reads its maxima instead of the
    /// samples.
    fn max_mipmap(&self) -> Option<&MaxMipmap> {
        None
    }
}

/// A reference to a tracer, or a shared one, is the tracer (so wrappers such as
/// [`crate::SunShadows`] can hold a `&dyn Tracer` or an `Arc<dyn Tracer>`); every method
/// forwards, batches included.
macro_rules! forward_tracer {
    ($($pointer:ty),*) => {$(
        impl<T: Tracer + ?Sized> Tracer for $pointer {
            fn name(&self) -> &'static str {
                (**self).name()
            }

            fn surface(&self) -> Surface {
                (**self).surface()
            }

            fn bounds(&self) -> Aabb {
                (**self).bounds()
            }

            fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
                (**self).intersect_counted(ray, steps)
            }

            fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
                (**self).occluded_counted(ray, steps)
            }

            fn intersect(&self, ray: &Ray) -> Option<Hit> {
                (**self).intersect(ray)
            }

            fn occluded(&self, ray: &Ray) -> bool {
                (**self).occluded(ray)
            }

            fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], steps: &mut [u32]) {
                (**self).intersect_batch(rays, hits, steps)
            }

            fn occluded_batch(&self, rays: &[Ray], occluded: &mut [bool], steps: &mut [u32]) {
                (**self).occluded_batch(rays, occluded, steps)
            }

            fn max_mipmap(&self) -> Option<&MaxMipmap> {
                (**self).max_mipmap()
            }
        }
    )*};
}

forward_tracer!(&T, Arc<T>);
