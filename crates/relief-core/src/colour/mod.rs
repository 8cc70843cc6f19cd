//! Colour encodings every crate that reads or writes pixels shares: the sRGB transfer function
//! ([`linear_to_srgb`], [`srgb_to_linear`]), its 8-bit forms ([`linear_to_srgb8`],
//! [`srgb8_to_linear_table`]) and [`ByteSteps`], the table that turns a non-decreasing curve
//! into bytes without evaluating it.
//!
//! They live in relief-core, not in relief-shade, because both relief-shade (which tone-maps
//! radiance to sRGB bytes and decodes sRGB textures) and relief-tiles (which stores ortho
//! photos as sRGB bytes and averages them in linear light when it builds their mip pyramid)
//! need them, and relief-tiles stands beside relief-shade, not above it: the encoding is data,
//! not shading.

mod byte_steps;
mod srgb;

pub use byte_steps::ByteSteps;
pub use srgb::{linear_to_srgb, linear_to_srgb8, srgb8_to_linear_table, srgb_to_linear};
