//! How a tracer's answer is held against the reference, and the tolerances that allows.
//!
//! Tracers are exact to rounding, and compute in their own spaces (cell space, scaled heights)
//! where the reference computes in world space; so `t` agrees to [`T_RELATIVE`] of the
//! parameter span of the scene, normals to [`NORMAL_TOLERANCE`]. A ray that grazes an edge or
//! a face within [`GRAZE_RELATIVE`] of the scene's size may go either way: the answer is then
//! also held against the reference with every face grown, and shrunk, by that much.

use super::brute_force::{first_hit, Expected, Floor};
use super::report::Check;
use crate::Hit;
use relief_core::{Aabb, DVec3, HeightField, Ray, Surface};

/// Relative tolerance on `t`, of the larger of `t` and the parameter span that crosses the
/// scene's box.
pub const T_RELATIVE: f64 = 1e-7;

/// Largest distance between a hit's unit normal and the reference's.
pub const NORMAL_TOLERANCE: f64 = 1e-6;

/// How close to an edge, relative to the scene's size, a ray may graze and go either way.
pub const GRAZE_RELATIVE: f64 = 1e-9;

/// The solid a tracer is held against, with the scale its tolerances are taken from.
#[derive(Debug, Clone, Copy)]
pub struct Reference<'a> {
    /// The terrain.
    pub field: &'a HeightField,
    /// Its surface.
    pub surface: Surface,
    /// How far down its solid reaches.
    pub floor: Floor,
    /// The length of the terrain box's diagonal (at least 1).
    pub extent: f64,
}

impl<'a> Reference<'a> {
    /// The reference for `surface` of `field` reaching down to `floor`.
    pub fn new(field: &'a HeightField, surface: Surface, floor: Floor) -> Self {
        let extent = field.world_bounds(Surface::Boxes).diagonal().max(1.0);
        Reference { field, surface, floor, extent }
    }

    /// The reference's first hit of `ray`, with faces grown by `margin` world units.
    pub fn first_hit(&self, ray: &Ray, margin: f64) -> Option<Expected> {
        first_hit(self.field, self.surface, self.floor, ray, margin)
    }

    /// The margin by which a grazing ray may go either way.
    fn graze(&self, ray: &Ray) -> f64 {
        GRAZE_RELATIVE * (self.extent + ray.origin.length())
    }

    /// `None` when `hit` is the reference's answer for `ray` (exact, or a graze going the
    /// other way), else the promise broken and how.
    pub fn judge(&self, ray: &Ray, hit: Option<Hit>) -> Option<(Check, String)> {
        let exact = self.first_hit(ray, 0.0);
        let m = self.graze(ray);
        let grown = || self.compare(ray, hit, self.first_hit(ray, m).as_ref());
        let shrunk = || self.compare(ray, hit, self.first_hit(ray, -m).as_ref());
        // The exact verdict stands unless a graze within the margin explains it.
        let exact = self.compare(ray, hit, exact.as_ref())?;
        grown()?;
        shrunk()?;
        Some(exact)
    }

    /// `None` when `occluded` is whether the reference meets `ray` (or a graze going either
    /// way), else what differs.
    pub fn judge_occluded(&self, ray: &Ray, occluded: bool) -> Option<(Check, String)> {
        let m = self.graze(ray);
        let agrees = |margin: f64| self.first_hit(ray, margin).is_some() == occluded;
        if agrees(0.0) || agrees(m) || agrees(-m) {
            return None;
        }
        Some((Check::Occluded, format!("occluded {occluded}, the reference says otherwise")))
    }

    /// `hit` against `expected`.
    fn compare(
        &self,
        ray: &Ray,
        hit: Option<Hit>,
        expected: Option<&Expected>,
    ) -> Option<(Check, String)> {
        let (hit, expected) = match (hit, expected) {
            (None, None) => return None,
            (Some(h), Some(e)) => (h, e),
            (h, e) => return Some((Check::Intersect, format!("hit {h:?}, expected {e:?}"))),
        };
        let span = self.extent / ray.dir.length();
        if (hit.t - expected.t).abs() > T_RELATIVE * (expected.t.abs() + span) {
            return Some((Check::Intersect, format!("hit {hit:?}, expected t {}", expected.t)));
        }
        let at = ray.at(expected.t);
        if (hit.position - at).length() > T_RELATIVE * (self.extent + at.length()) {
            return Some((Check::Position, format!("hit {hit:?}, expected position {at}")));
        }
        if !expected.normals.iter().any(|n| (hit.normal - *n).length() <= NORMAL_TOLERANCE) {
            let normals = &expected.normals;
            return Some((Check::Normal, format!("hit {hit:?}, expected a normal of {normals:?}")));
        }
        None
    }

    /// Whether `hit` lies in `bounds`, grown by the position tolerance.
    pub fn within(&self, bounds: &Aabb, hit: &Hit) -> bool {
        let slack = DVec3::splat(T_RELATIVE * (self.extent + hit.position.length()));
        let (lo, hi) = (bounds.min - slack, bounds.max + slack);
        hit.position.cmpge(lo).all() && hit.position.cmple(hi).all()
    }
}

/// Whether two answers of one tracer for one ray agree (a batch against single rays): both
/// miss, or both hit at the same `t` (to [`T_RELATIVE`]) with the same normal.
pub fn same_hit(a: Option<Hit>, b: Option<Hit>, span: f64) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            (a.t - b.t).abs() <= T_RELATIVE * (a.t.abs() + span)
                && (a.normal - b.normal).length() <= NORMAL_TOLERANCE
        }
        _ => false,
    }
}
