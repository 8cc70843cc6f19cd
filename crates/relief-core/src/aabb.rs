//! Axis-aligned boxes and the slab test that clips a ray to one.

use crate::Ray;
use glam::DVec3;

/// An axis-aligned box `[min, max]` (closed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: DVec3,
    /// Upper corner.
    pub max: DVec3,
}

/// The face of a box through which a ray enters it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoxFace {
    /// The ray starts inside the box (or on its boundary at `t_min`).
    Inside,
    /// A face perpendicular to x.
    X,
    /// A face perpendicular to y.
    Y,
    /// A face perpendicular to z.
    Z,
}

/// The part of a ray inside a box: `t_enter <= t <= t_exit`, entering through `face`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clip {
    /// Parameter where the ray enters (at least the ray's `t_min`).
    pub t_enter: f64,
    /// Parameter where the ray leaves (at most the ray's `t_max`).
    pub t_exit: f64,
    /// The face crossed at `t_enter`.
    pub face: BoxFace,
}

impl Aabb {
    /// The box spanning two corners.
    pub fn new(min: DVec3, max: DVec3) -> Self {
        Aabb { min, max }
    }

    /// Centre of the box.
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Length of the box's diagonal.
    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).length()
    }

    /// Clips `ray` to the box (slab test). `None` when the ray misses the box within its range.
    ///
    /// A ray parallel to a slab is inside it only if its origin is (boundaries included).
    pub fn clip(&self, ray: &Ray) -> Option<Clip> {
        self.clip_with_inverse(ray, DVec3::ONE / ray.dir)
    }

    /// [`Aabb::clip`] for a ray whose reciprocal direction `inv_dir` (`1 / dir` component by
    /// component) is already known: the same numbers without dividing again.
    #[inline]
    pub fn clip_with_inverse(&self, ray: &Ray, inv_dir: DVec3) -> Option<Clip> {
        let mut clip = Clip { t_enter: ray.t_min, t_exit: ray.t_max, face: BoxFace::Inside };
        let (o, d, lo, hi) = (ray.origin, ray.dir, self.min, self.max);
        clip_slab(&mut clip, o.x, d.x, inv_dir.x, lo.x, hi.x, BoxFace::X)?;
        clip_slab(&mut clip, o.y, d.y, inv_dir.y, lo.y, hi.y, BoxFace::Y)?;
        clip_slab(&mut clip, o.z, d.z, inv_dir.z, lo.z, hi.z, BoxFace::Z)?;
        (clip.t_enter <= clip.t_exit).then_some(clip)
    }
}

/// Narrows `clip` to the slab `[lo, hi]` along one axis of a ray with origin `o`, direction
/// `d` and reciprocal `inv` there, entering through `face`; `None` when a ray parallel to the
/// slab lies outside it. Multiplying by the reciprocal, as the tracers do, keeps crossings
/// bit-identical.
#[inline(always)]
fn clip_slab(
    clip: &mut Clip,
    o: f64,
    d: f64,
    inv: f64,
    lo: f64,
    hi: f64,
    face: BoxFace,
) -> Option<()> {
    if d == 0.0 {
        return (!(o < lo || o > hi)).then_some(());
    }
    let (a, b) = ((lo - o) * inv, (hi - o) * inv);
    let (near, far) = if a > b { (b, a) } else { (a, b) };
    if near > clip.t_enter {
        clip.t_enter = near;
        clip.face = face;
    }
    clip.t_exit = clip.t_exit.min(far);
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clip_reports_entry_face_and_range() {
        let b = Aabb::new(DVec3::ZERO, DVec3::ONE);
        let r = Ray::new(DVec3::new(-1.0, 0.5, 0.5), DVec3::X);
        let c = b.clip(&r).unwrap();
        assert_eq!((c.t_enter, c.t_exit, c.face), (1.0, 2.0, BoxFace::X));
        let inside = Ray::new(DVec3::splat(0.5), DVec3::Z);
        assert_eq!(b.clip(&inside).unwrap().face, BoxFace::Inside);
        let parallel_outside = Ray::new(DVec3::new(2.0, 0.5, 0.5), DVec3::Y);
        assert!(b.clip(&parallel_outside).is_none());
    }

    #[test]
    fn flat_box_is_hit_from_above() {
        let b = Aabb::new(DVec3::new(0.0, 0.0, 1.0), DVec3::new(1.0, 1.0, 1.0));
        let r = Ray::new(DVec3::new(0.5, 0.5, 3.0), -DVec3::Z);
        let c = b.clip(&r).unwrap();
        assert_eq!((c.t_enter, c.t_exit), (2.0, 2.0));
    }
}
