//! The sky: its colour seen in a direction, the ambient light it gives, and aerial
//! perspective (exponential fog towards the sky colour).

use relief_core::DVec3;

use crate::error::{non_negative, non_negative_colour};
use crate::ShadeError;

/// A clear sky: a gradient from a light horizon to a deeper blue zenith, and a uniform
/// radiance for the ambient light it casts on the terrain. All colours are linear radiance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sky {
    /// Radiance straight up.
    pub zenith: [f32; 3],
    /// Radiance at (and below) the horizon.
    pub horizon: [f32; 3],
    /// Uniform sky radiance lighting the terrain (see [`crate::ambient_lighting`]); set it to
    /// zero to light with the sun alone.
    pub ambient: [f32; 3],
}

impl Default for Sky {
    /// A clear day: pale horizon, blue zenith, and sky light about a sixth of the default sun's.
    fn default() -> Self {
        Sky { zenith: [0.16, 0.30, 0.62], horizon: [0.58, 0.68, 0.82], ambient: [0.10, 0.13, 0.19] }
    }
}

impl Sky {
    /// Checks that every channel is finite and non-negative.
    pub fn validate(&self) -> Result<(), ShadeError> {
        non_negative_colour("sky zenith colour", self.zenith)?;
        non_negative_colour("sky horizon colour", self.horizon)?;
        non_negative_colour("sky ambient radiance", self.ambient)
    }

    /// Radiance of the sky seen along the unit direction `dir`: the horizon colour at and below
    /// the horizon, blending to the zenith colour as `sqrt(dir.z)` (a light band near the
    /// horizon that deepens quickly upwards).
    pub fn radiance(&self, dir: DVec3) -> DVec3 {
        let up = if dir.z > 0.0 { dir.z.min(1.0).sqrt() } else { 0.0 };
        colour(self.horizon).lerp(colour(self.zenith), up)
    }

    /// The ambient sky radiance as a vector.
    pub fn ambient(&self) -> DVec3 {
        colour(self.ambient)
    }
}

fn colour(c: [f32; 3]) -> DVec3 {
    DVec3::from(c.map(f64::from))
}

/// How much fog lies between the eye and a point twice the terrain's diagonal away, in the
/// default density of [`fog_density_for_scene`].
pub const FOG_AT_TWICE_DIAGONAL: f64 = 0.3;

/// A fog density (per world unit) scaled to a scene of diagonal `diagonal`: fog reaches
/// [`FOG_AT_TWICE_DIAGONAL`] (30%) at twice the diagonal, i.e. `ln(1 / 0.7) / (2 diagonal)`.
/// Returns 0 (no fog) for a diagonal that is not finite and positive.
pub fn fog_density_for_scene(diagonal: f64) -> f64 {
    if diagonal.is_finite() && diagonal > 0.0 {
        -(1.0 - FOG_AT_TWICE_DIAGONAL).ln() / (2.0 * diagonal)
    } else {
        0.0
    }
}

/// Checks a fog density: finite and non-negative.
pub(crate) fn validate_fog_density(density: f64) -> Result<(), ShadeError> {
    non_negative("fog density", density)
}

/// Aerial perspective: the radiance of a surface `distance` away through exponential fog of
/// `density` per world unit that scatters `fog` radiance (the sky colour in that direction):
/// `surface · T + fog · (1 - T)` with transmittance `T = exp(-density · distance)`.
pub fn aerial_perspective(surface: DVec3, fog: DVec3, distance: f64, density: f64) -> DVec3 {
    let transmittance = (-density * distance).exp();
    if transmittance.is_nan() {
        return surface;
    }
    surface * transmittance + fog * (1.0 - transmittance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sky_is_lighter_at_the_horizon_and_bluer_at_the_zenith() {
        let sky = Sky::default();
        let (horizon, zenith) = (sky.radiance(DVec3::X), sky.radiance(DVec3::Z));
        assert_eq!(horizon, colour(sky.horizon));
        assert_eq!(zenith, colour(sky.zenith));
        assert!(horizon.element_sum() > zenith.element_sum());
        assert!(zenith.z > zenith.x && zenith.z > zenith.y);
        assert_eq!(sky.radiance(-DVec3::Z), horizon);
        let mid = sky.radiance(DVec3::new(1.0, 0.0, 1.0).normalize());
        assert!(
            mid.element_sum() < horizon.element_sum() && mid.element_sum() > zenith.element_sum()
        );
        assert!(Sky { ambient: [0.0, -1.0, 0.0], ..sky }.validate().is_err());
    }

    #[test]
    fn fog_reaches_thirty_percent_at_twice_the_diagonal() {
        let diagonal = 1234.5;
        let density = fog_density_for_scene(diagonal);
        let surface = DVec3::ZERO;
        let fog = DVec3::ONE;
        let seen = aerial_perspective(surface, fog, 2.0 * diagonal, density);
        assert!((seen - DVec3::splat(0.3)).abs().max_element() < 1e-12);
        assert_eq!(aerial_perspective(DVec3::ONE, DVec3::ZERO, 0.0, density), DVec3::ONE);
        assert_eq!(aerial_perspective(DVec3::ONE, DVec3::ZERO, 1e9, 0.0), DVec3::ONE);
        assert_eq!(fog_density_for_scene(0.0), 0.0);
        assert_eq!(fog_density_for_scene(f64::NAN), 0.0);
        // Farther is foggier.
        let near = aerial_perspective(surface, fog, 100.0, density);
        let far = aerial_perspective(surface, fog, 1000.0, density);
        assert!(far.x > near.x);
    }
}
