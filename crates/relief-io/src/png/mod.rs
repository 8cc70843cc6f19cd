//! PNG: heights in PNG images (16-bit greyscale, terrain-RGB, Terrarium; [`read_png_height`],
//! [`write_png16_height`]), one shade layer as a 16-bit PNG with its world file
//! ([`write_layer_png`]), and 8-bit RGB and 16-bit grey pictures ([`read_png_rgb`],
//! [`write_png_rgb8`], [`write_png_gray16`]).

pub(crate) mod decoding_error;
pub(crate) mod height;
pub(crate) mod layer_write;
pub(crate) mod read;
pub(crate) mod write;

pub use height::{
    read_png_height, write_png16_height, write_png16_height_in, PngHeightScale, PNG_HEIGHT_OFFSET,
    PNG_HEIGHT_SCALE, PNG_HEIGHT_UNIT,
};
pub use layer_write::write_layer_png;
pub use read::{read_png_rgb, RgbImage};
pub use write::{write_png_gray16, write_png_rgb8, write_png_rgb8_compressed, PngCompression};
