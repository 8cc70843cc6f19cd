//! Where a surface point's colour comes from: a constant, the hypsometric ramp or a texture.

use relief_core::DVec3;

use crate::error::non_negative_colour;
use crate::{HypsometricRamp, RgbTexture, ShadeError};

/// The source of the diffuse albedo (linear RGB reflectance) of the terrain.
#[derive(Debug, Clone, PartialEq)]
pub enum Albedo {
    /// The same reflectance everywhere.
    Uniform([f32; 3]),
    /// A colour ramp over elevation (see [`HypsometricRamp`]).
    Hypsometric(HypsometricRamp),
    /// A texture draped over the terrain's footprint, sampled bilinearly at the G-buffer's
    /// texture coordinates.
    Texture(RgbTexture),
}

impl Albedo {
    /// Checks the source's parameters (textures are checked when they are built).
    pub fn validate(&self) -> Result<(), ShadeError> {
        match self {
            Albedo::Uniform(c) => non_negative_colour("uniform albedo", *c),
            Albedo::Hypsometric(ramp) => ramp.validate(),
            Albedo::Texture(_) => Ok(()),
        }
    }

    /// The albedo at world `position` with unit `normal` and texture coordinates `uv`.
    pub fn at(&self, position: DVec3, normal: DVec3, uv: [f32; 2]) -> DVec3 {
        match self {
            Albedo::Uniform(c) => DVec3::from(c.map(f64::from)),
            Albedo::Hypsometric(ramp) => ramp.albedo(position.z, normal.z),
            Albedo::Texture(texture) => texture.sample_bilinear(uv[0] as f64, uv[1] as f64),
        }
    }
}
