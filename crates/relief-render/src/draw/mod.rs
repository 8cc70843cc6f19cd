//! Drawing a scene's picture from a camera, one renderer a file.

pub mod clipmap;
pub(crate) mod field_picture;
pub mod hybrid;
pub mod mesh;
pub mod mlhm;
pub mod picture;
pub mod store;
pub mod strips;
