//! JPEG: 8-bit RGB pictures written as baseline JPEGs ([`write_jpeg_rgb8`]).

pub(crate) mod write;

pub use write::{write_jpeg_rgb8, JPEG_QUALITY};
