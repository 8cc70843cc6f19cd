//! The lights, preset and exposure of an MLHM rendering.

use super::environment::reference_sky;
use super::preset::{MlhmPreset, MlhmQuality};
use crate::error::non_negative;
use crate::{ShadeError, Sky, Sun};

/// The default strength of the sky's light: with the default sun 35 degrees up, flat open
/// ground gets about a third of its light from the sky, as on a clear day.
pub const SKY_LIGHT: f64 = 0.4;

/// Lights, preset and exposure of an MLHM rendering.
#[derive(Debug, Clone, PartialEq)]
pub struct MlhmShading {
    /// What the rendering computes (see [`MlhmPreset::quality`]).
    pub quality: MlhmQuality,
    /// The sun: direction and irradiance.
    pub sun: Sun,
    /// The sky seen behind the terrain and lighting it.
    pub sky: Sky,
    /// How brightly the sky lights the terrain relative to how bright it looks (the reference
    /// renderer's ambient light intensity against its sun).
    pub sky_light: f64,
    /// Exposure before tone mapping (see [`crate::tonemap_reinhard_to_rgb8`]).
    pub exposure: f64,
}

impl MlhmShading {
    /// The reference look at `preset`: the default sun, the reference sky lighting with
    /// [`SKY_LIGHT`], exposure 1.
    pub fn new(preset: MlhmPreset) -> Self {
        MlhmShading {
            quality: preset.quality(),
            sun: Sun::default(),
            sky: reference_sky(),
            sky_light: SKY_LIGHT,
            exposure: 1.0,
        }
    }

    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), ShadeError> {
        self.sun.validate()?;
        self.sky.validate()?;
        if let Some(a) = self.quality.ao_radius {
            if !(a.is_finite() && a > 0.0) {
                return Err(ShadeError::parameter(
                    "AO radius",
                    format!("{a} is not a positive length"),
                ));
            }
        }
        non_negative("sky light", self.sky_light)?;
        non_negative("exposure", self.exposure)
    }
}
