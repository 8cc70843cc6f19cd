//! Where a viewshed's observer stands: a point of the DEM's plane and a height above the
//! ground there, turned into the eye every line of sight ends at.

use crate::shade_map::surface_origin;
use crate::ShadeError;
use relief_core::{DVec3, HeightField, Ray};
use relief_trace::Tracer;

/// Height of an observer's eye above the ground, in metres, unless asked otherwise: a
/// standing person's.
pub const DEFAULT_OBSERVER_HEIGHT: f64 = 1.7;

/// One observer of a viewshed: a point in the height field's world coordinates and the
/// height of the eye above the ground there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observer {
    /// World x (east) of the observer, in the field's coordinates.
    pub x: f64,
    /// World y (north) of the observer, in the field's coordinates.
    pub y: f64,
    /// Height of the eye above the ground, in metres (finite, >= 0).
    pub height: f64,
}

impl Observer {
    /// The observer standing at world (`x`, `y`) with the eye `height` above the ground.
    pub fn new(x: f64, y: f64, height: f64) -> Self {
        Observer { x, y, height }
    }

    /// The eye of this observer over `field`: the world point every line of sight ends at.
    ///
    /// The observer must stand on the field's footprint (the texels' extent, closed) and
    /// not on a void (a hole of `field` or a flag of `void`). Its ground is the surface
    /// `tracer` intersects, met by a vertical ray; an observer in the outer half texel, where
    /// the `triangles` surface (spanned by the sample points) does not reach, stands on the
    /// nearest point of the sample points' rectangle. The eye is `height` above that ground,
    /// plus the lift every shade-map ray starts with ([`crate::shade_map::SURFACE_LIFT`]),
    /// so that an observer of height 0 is not inside the solid.
    pub fn eye(
        &self,
        field: &HeightField,
        tracer: &dyn Tracer,
        void: Option<&[bool]>,
    ) -> Result<DVec3, ShadeError> {
        let g = field.geometry();
        let (w, h) = (field.width(), field.height());
        if !(self.height.is_finite() && self.height >= 0.0) {
            return Err(ShadeError::parameter(
                "observer height",
                format!("{} is not a finite number >= 0", self.height),
            ));
        }
        let col_f = (self.x - g.origin.x) / g.dx;
        let row_f = (self.y - g.origin.y) / g.dy;
        let inside = |v: f64, n: usize| v.is_finite() && (0.0..=n as f64).contains(&v);
        if !inside(col_f, w) || !inside(row_f, h) {
            let (x1, y1) = (g.origin.x + w as f64 * g.dx, g.origin.y + h as f64 * g.dy);
            return Err(ShadeError::parameter(
                "observer",
                format!(
                    "({}, {}) lies outside the DEM, which spans x {} to {x1} and y {} to {y1}",
                    self.x, self.y, g.origin.x, g.origin.y
                ),
            ));
        }
        let col = (col_f as usize).min(w - 1);
        let row = (row_f as usize).min(h - 1);
        if field.is_hole(col, row) || void.is_some_and(|v| v.get(col + row * w) == Some(&true)) {
            return Err(ShadeError::parameter(
                "observer",
                format!("({}, {}) stands on a void of the DEM", self.x, self.y),
            ));
        }
        // The sample points' rectangle, in grid units.
        let hull = |v: f64, n: usize| v.clamp(0.5, n as f64 - 0.5);
        let grid = DVec3::new(hull(col_f, w), hull(row_f, h), 0.0);
        let ground = g.point_to_world(grid);
        let top = f64::from(field.max_sample()) * g.z_scale;
        let bottom = f64::from(field.min_sample()) * g.z_scale;
        let span = (top - bottom).max(1.0);
        let above = DVec3::new(ground.x, ground.y, top + span);
        let down = Ray::new(above, DVec3::new(0.0, 0.0, -1.0));
        // A vertical ray inside the footprint always meets the solid; its bottom otherwise.
        let ground_z = tracer.intersect(&down).map_or(bottom, |hit| above.z - hit.t);
        // The lift of the nearest sample's rays, which grows with the coordinates' size.
        let lift =
            surface_origin(field, col, row).z - f64::from(field.sample(col, row)) * g.z_scale;
        Ok(DVec3::new(ground.x, ground.y, ground_z + self.height + lift))
    }
}
