//! A ray with a parameter interval: the unit of work of every tracer.

use glam::DVec3;

/// A ray `origin + t * dir` restricted to `t_min <= t <= t_max`.
///
/// Camera rays have a unit `dir`, so `t` is a distance in world units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Start point.
    pub origin: DVec3,
    /// Direction (not necessarily unit length).
    pub dir: DVec3,
    /// Smallest parameter considered.
    pub t_min: f64,
    /// Largest parameter considered (may be infinite).
    pub t_max: f64,
}

impl Ray {
    /// A ray over `[0, +inf)`.
    pub fn new(origin: DVec3, dir: DVec3) -> Self {
        Ray { origin, dir, t_min: 0.0, t_max: f64::INFINITY }
    }

    /// The same ray restricted to `[t_min, t_max]`.
    pub fn with_range(self, t_min: f64, t_max: f64) -> Self {
        Ray { t_min, t_max, ..self }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + t * self.dir
    }
}
