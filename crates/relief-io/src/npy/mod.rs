//! NumPy: `.npy` arrays (the header and its dtypes, a streaming decoder, a 2D array as a
//! raster or as rows, f32 writers) and `.npz` archives of them.

pub(crate) mod header;
pub(crate) mod npz;
pub(crate) mod raster;
pub(crate) mod read;
pub(crate) mod rows;
pub(crate) mod write;

pub use npz::read_npz;
pub use raster::{read_npy, read_npy_height_field};
pub use read::read_npy_f32_array;
pub use write::{write_height_field_npy, write_npy_f32};
