//! Where a surface point's colour comes from: a constant, the hypsometric ramp, a named colour
//! map over heights, a texture, or a texture filtered over each pixel's footprint.

use std::sync::Arc;

use relief_core::DVec3;

use crate::error::non_negative_colour;
use crate::{
    FootprintAlbedo, GroundFootprint, HeightColourMap, HypsometricRamp, RgbTexture, ShadeError,
};

/// The source of the diffuse albedo (linear RGB reflectance) of the terrain.
#[derive(Debug, Clone, PartialEq)]
pub enum Albedo {
    /// The same reflectance everywhere.
    Uniform([f32; 3]),
    /// A colour ramp over elevation (see [`HypsometricRamp`]).
    Hypsometric(HypsometricRamp),
    /// A named colour map over a range of heights (see [`HeightColourMap`]), without the
    /// ramp's rock on steep slopes.
    Mapped(HeightColourMap),
    /// A texture draped over the terrain's footprint, sampled bilinearly at the G-buffer's
    /// texture coordinates.
    Texture(RgbTexture),
    /// A texture filtered over each pixel's footprint on the terrain (see
    /// [`FootprintAlbedo`]): the deferred pass computes the footprint.
    Filtered(FilteredAlbedo),
    /// The colour each pixel's renderer stored: the first three G-buffer material weights are
    /// the linear RGB albedo (renderers of meshes with per-vertex colours, such as the stacks
    /// meshes); `fallback` where the pass has no G-buffer pixel at hand.
    GBufferColour {
        /// The albedo used without a G-buffer pixel.
        fallback: [f32; 3],
    },
}

/// A shared [`FootprintAlbedo`]; two are equal when they are the same source.
#[derive(Debug, Clone)]
pub struct FilteredAlbedo(pub Arc<dyn FootprintAlbedo>);

impl PartialEq for FilteredAlbedo {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::addr_eq(Arc::as_ptr(&self.0), Arc::as_ptr(&other.0))
    }
}

impl Albedo {
    /// Checks the source's parameters (textures are checked when they are built).
    pub fn validate(&self) -> Result<(), ShadeError> {
        match self {
            Albedo::Uniform(c) => non_negative_colour("uniform albedo", *c),
            Albedo::Hypsometric(ramp) => ramp.validate(),
            Albedo::Mapped(map) => map.validate(),
            Albedo::Texture(_) | Albedo::Filtered(_) => Ok(()),
            Albedo::GBufferColour { fallback } => non_negative_colour("fallback albedo", *fallback),
        }
    }

    /// The albedo at world `position` with unit `normal` and texture coordinates `uv`; a
    /// filtered texture is sampled at the point, without a footprint (the deferred pass gives
    /// it each pixel's).
    pub fn at(&self, position: DVec3, normal: DVec3, uv: [f32; 2]) -> DVec3 {
        match self {
            Albedo::Uniform(c) => DVec3::from(c.map(f64::from)),
            Albedo::Hypsometric(ramp) => ramp.albedo(position.z, normal.z),
            Albedo::Mapped(map) => map.albedo(position.z),
            Albedo::Texture(texture) => texture.sample_bilinear(uv[0] as f64, uv[1] as f64),
            Albedo::Filtered(source) => source.0.albedo(&GroundFootprint::point(position)),
            Albedo::GBufferColour { fallback } => DVec3::from(fallback.map(f64::from)),
        }
    }
}
