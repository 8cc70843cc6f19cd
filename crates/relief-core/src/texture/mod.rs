//! Textures draped over the terrain and filtered over a pixel's footprint on it (Dick et al.
//! 2009, section 3.3): the footprint of a pixel on the terrain's tangent plane
//! ([`GroundFootprint`], [`ground_footprint`], [`pixel_ground_footprint`] over any frame's
//! [`PixelHits`]), the filter over a mip-mapped texture ([`filter_texture`] of a
//! [`MipTexture`]) and the colour source that combines them ([`FootprintAlbedo`]).
//!
//! They live in relief-core, not in relief-shade, because two crates that stand side by side
//! need them: relief-shade filters textures in its deferred pass, and relief-tiles streams an
//! ortho photo's pyramid, choosing the tiles a frame's footprints touch and filtering them. A
//! footprint and a filter are geometry and sampling over data, which is what relief-core
//! holds; neither needs a material, a light or a renderer.

mod filter;
mod footprint;
mod footprint_albedo;

pub use filter::{
    filter_texture, FootprintAxes, MipTexture, TexelFootprint, TextureFilter,
    DEFAULT_MAX_ANISOTROPY,
};
pub use footprint::{
    ground_footprint, pixel_ground_footprint, slope_from_normal, GroundFootprint, PixelHits,
};
pub use footprint_albedo::FootprintAlbedo;
