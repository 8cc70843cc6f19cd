//! What a horizon map is asked for: its directions, the observer's height, a radius, and the
//! earth's curvature.

use crate::ShadeError;

/// Directions of a horizon map unless asked otherwise.
pub const DEFAULT_AZIMUTHS: u32 = 32;

/// How far above its sample point the observer stands, in metres, unless asked otherwise.
pub const DEFAULT_OBSERVER_HEIGHT: f64 = 0.01;

/// The atmospheric refraction coefficient with `--earth-curvature` unless asked otherwise.
pub const REFRACTION_COEFFICIENT: f64 = 0.13;

/// Most directions a horizon map may have.
pub const MAX_AZIMUTHS: u32 = 4096;

/// The parameters of a horizon map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HorizonParams {
    /// Directions, evenly spaced clockwise from north (the first is north).
    pub azimuths: u32,
    /// Height of the observer above each sample point, in metres (>= 0).
    pub observer_height: f64,
    /// Horizontal search radius in metres; `None` searches to the edge of the data.
    pub radius: Option<f64>,
    /// With `Some(k)`, the terrain at horizontal distance `t` drops by `(1 - k) t^2 / (2 R)`
    /// (the earth's curvature, radius `R`, less refraction of coefficient `k`).
    pub refraction: Option<f64>,
}

impl Default for HorizonParams {
    fn default() -> Self {
        HorizonParams {
            azimuths: DEFAULT_AZIMUTHS,
            observer_height: DEFAULT_OBSERVER_HEIGHT,
            radius: None,
            refraction: None,
        }
    }
}

impl HorizonParams {
    /// Checks every parameter, naming the one that is wrong.
    pub fn validate(&self) -> Result<(), ShadeError> {
        if !(1..=MAX_AZIMUTHS).contains(&self.azimuths) {
            return Err(ShadeError::parameter(
                "azimuths",
                format!("{} is not between 1 and {MAX_AZIMUTHS}", self.azimuths),
            ));
        }
        if !(self.observer_height.is_finite() && self.observer_height >= 0.0) {
            return Err(ShadeError::parameter(
                "observer height",
                format!("{} is not a finite number >= 0", self.observer_height),
            ));
        }
        if let Some(radius) = self.radius {
            if !(radius.is_finite() && radius > 0.0) {
                return Err(ShadeError::parameter(
                    "radius",
                    format!("{radius} is not a finite number > 0"),
                ));
            }
        }
        if let Some(k) = self.refraction {
            if !(k.is_finite() && (0.0..1.0).contains(&k)) {
                return Err(ShadeError::parameter(
                    "refraction coefficient",
                    format!("{k} is not in [0, 1)"),
                ));
            }
        }
        Ok(())
    }

    /// At most how many bytes per sample of the height field one [`super::HorizonEngine`]
    /// with these parameters holds: two copies of the samples (columns one after the other
    /// and rows) with their footprints' maxima, the band windows while it starts, and a
    /// quarter of a byte per direction for the band pyramids.
    pub fn engine_bytes_per_sample(&self) -> u64 {
        24 + (self.azimuths as u64).div_ceil(4)
    }

    /// The direction of index `k` in degrees clockwise from north.
    pub fn azimuth_deg(&self, k: usize) -> f64 {
        k as f64 * 360.0 / self.azimuths as f64
    }
}
