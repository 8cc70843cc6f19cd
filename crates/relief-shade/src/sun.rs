//! The sun: its direction from compass angles, its irradiance, and shadow rays towards it.

use std::sync::Arc;

use relief_core::{DVec3, HeightField, Ray, Surface};
use relief_trace::{SunShadows, Tracer};

use crate::error::non_negative;
use crate::{ShadeError, ShadingParams, TraceStats};

/// A distant directional light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sun {
    /// Compass direction of the sun in degrees, clockwise from north (+y): 90 is east (+x).
    pub azimuth_deg: f64,
    /// Angle of the sun above the horizon in degrees, in `[-90, 90]`. Below the horizon
    /// (negative) the sun gives no direct light.
    pub elevation_deg: f64,
    /// Irradiance `E` on a surface facing the sun, in linear radiometric units.
    pub irradiance: f64,
}

impl Default for Sun {
    /// The cartographers' light: from the north-west, 45 degrees up, `E = 3`.
    fn default() -> Self {
        Sun { azimuth_deg: 315.0, elevation_deg: 45.0, irradiance: 3.0 }
    }
}

impl Sun {
    /// Checks that the angles are finite, the elevation within `[-90, 90]` and the irradiance
    /// finite and non-negative.
    pub fn validate(&self) -> Result<(), ShadeError> {
        if !self.azimuth_deg.is_finite() {
            return Err(ShadeError::parameter(
                "sun azimuth",
                format!("{} is not finite", self.azimuth_deg),
            ));
        }
        if !(self.elevation_deg.is_finite() && (-90.0..=90.0).contains(&self.elevation_deg)) {
            return Err(ShadeError::parameter(
                "sun elevation",
                format!("{} is not between -90 and 90 degrees", self.elevation_deg),
            ));
        }
        non_negative("sun irradiance", self.irradiance)
    }

    /// Unit vector from the ground towards the sun.
    pub fn direction(&self) -> DVec3 {
        sun_direction(self.azimuth_deg, self.elevation_deg)
    }

    /// Whether the sun lights the terrain at all (it is not below the horizon).
    pub fn is_up(&self) -> bool {
        self.elevation_deg >= 0.0
    }
}

/// The sun's shadow sweep for the shadow rays of a picture of `pixels` pixels of `surface` of
/// `field`, shaded with `params`: [`SunShadows`] around `tracer` (which must trace that
/// surface), exact and faster; `None` where no shadow ray goes to the sun or the sweep would not
/// pay ([`SunShadows::pays_for`]).
pub fn sun_shadow_sweep<T: Tracer>(
    tracer: T,
    field: &Arc<HeightField>,
    surface: Surface,
    params: &ShadingParams,
    pixels: usize,
) -> Option<SunShadows<T>> {
    if !params.traces_shadow_rays() || !SunShadows::<T>::pays_for(field, surface, pixels) {
        return None;
    }
    // A sun on the horizon lights nothing and is refused here.
    SunShadows::new(tracer, field.clone(), params.sun.direction()).ok()
}

/// Unit vector towards a light at compass `azimuth_deg` (clockwise from north = +y, so 90 is
/// east = +x) and `elevation_deg` above the horizon (90 is the zenith, +z).
pub fn sun_direction(azimuth_deg: f64, elevation_deg: f64) -> DVec3 {
    let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
    DVec3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin())
}

/// Offset of a shadow ray's origin along the surface normal, per unit of hit distance.
///
/// Deferred shading rebuilds a hit point from the eye and the G-buffer's `f32` distance, which
/// is rounded to 2^-24 (6e-8) of the distance; the tracers themselves work in `f64`. An offset
/// of 1e-5 of the distance clears that rounding more than 100 times over, whatever the angle
/// of the surface, yet stays below a hundredth of a pixel at common fields of view (a pixel
/// is 2 tan(fov/2)/H ≈ 8e-4 of the distance at 45° and 1080 rows), so contact shadows do not
/// visibly detach.
pub const SHADOW_BIAS: f64 = 1e-5;

/// Offset relative to the largest coordinate of the hit, covering `f64` rounding of far-from-
/// origin (e.g. georeferenced) coordinates when the hit distance is tiny.
const COORDINATE_BIAS: f64 = 1e-12;

/// The shadow ray from a surface point at `position` (unit `normal`, seen from
/// `distance` away) towards the light direction `towards_light` (unit).
///
/// The origin is lifted off the surface along the normal by
/// `SHADOW_BIAS * distance + 1e-12 * max |coordinate|` (see [`SHADOW_BIAS`]), so the ray does
/// not find the surface it starts on; it then runs to infinity.
pub fn shadow_ray(position: DVec3, normal: DVec3, distance: f64, towards_light: DVec3) -> Ray {
    let eps = shadow_ray_offset(position, distance);
    Ray::new(position + normal * eps, towards_light)
}

/// How far along its normal a secondary ray leaves a surface point at `position`, seen from
/// `distance` away: `SHADOW_BIAS * distance + 1e-12 * max |coordinate|` (see [`SHADOW_BIAS`]).
pub fn shadow_ray_offset(position: DVec3, distance: f64) -> f64 {
    SHADOW_BIAS * distance.abs() + COORDINATE_BIAS * position.abs().max_element()
}

/// Visibility of a light from a surface point: 1 when the shadow ray (see [`shadow_ray`])
/// escapes the terrain, 0 when `tracer` finds it occluded. Counts the ray into `stats`.
pub fn light_visibility(
    tracer: &dyn Tracer,
    position: DVec3,
    normal: DVec3,
    distance: f64,
    towards_light: DVec3,
    stats: &mut TraceStats,
) -> f64 {
    let ray = shadow_ray(position, normal, distance, towards_light);
    let mut steps = 0;
    let occluded = tracer.occluded_counted(&ray, &mut steps);
    stats.record(steps, occluded);
    if occluded {
        0.0
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compass_angles_map_to_world_axes() {
        let close = |a: DVec3, b: DVec3| (a - b).length() < 1e-12;
        assert!(close(sun_direction(90.0, 0.0), DVec3::X));
        assert!(close(sun_direction(0.0, 0.0), DVec3::Y));
        assert!(close(sun_direction(180.0, 0.0), -DVec3::Y));
        assert!(close(sun_direction(0.0, 90.0), DVec3::Z));
        assert!(close(sun_direction(123.0, 90.0), DVec3::Z));
        let d = sun_direction(315.0, 45.0);
        assert!((d.length() - 1.0).abs() < 1e-12 && d.x < 0.0 && d.y > 0.0 && d.z > 0.0);
    }

    #[test]
    fn refuses_impossible_suns() {
        assert!(Sun::default().validate().is_ok());
        assert!(Sun { elevation_deg: 91.0, ..Sun::default() }.validate().is_err());
        assert!(Sun { azimuth_deg: f64::NAN, ..Sun::default() }.validate().is_err());
        assert!(Sun { irradiance: -1.0, ..Sun::default() }.validate().is_err());
        assert!(!Sun { elevation_deg: -5.0, ..Sun::default() }.is_up());
    }

    #[test]
    fn shadow_ray_starts_just_off_the_surface() {
        let r = shadow_ray(DVec3::new(0.0, 0.0, 2.0), DVec3::Z, 1000.0, DVec3::X);
        assert!((r.origin.z - 2.0 - 1000.0 * SHADOW_BIAS).abs() < 1e-9);
        assert_eq!((r.dir, r.t_min, r.t_max), (DVec3::X, 0.0, f64::INFINITY));
    }
}
