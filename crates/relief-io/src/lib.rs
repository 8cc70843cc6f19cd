//! relief-io: reading and writing the files relief consumes and produces.
//!
//! - [`read_npy_height_field`]: a 2D NumPy `.npy` grid (integer or float dtypes, either byte
//!   order, C or Fortran order) as a [`HeightField`](relief_core::HeightField);
//! - [`write_npy_f32`], [`write_height_field_npy`]: little-endian f32 `.npy` arrays (depth
//!   images, normals, height fields);
//! - [`write_png_rgb8`], [`write_png_gray16`], [`read_png_rgb`]: PNG images.
//!
//! Readers never trust a header: sizes are checked against the file before anything is
//! allocated. Writers write a temporary file beside the target and rename it into place, so a
//! failed write never leaves a partial file. Every error names the file and says what was wrong.
//!
//! ```
//! use relief_core::{GridGeometry, HeightField};
//! let path = std::env::temp_dir().join(format!("relief-io-doc-{}.npy", std::process::id()));
//! let field = HeightField::new(3, 2, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0], GridGeometry::unit())?;
//! relief_io::write_height_field_npy(&path, &field)?;
//! let back = relief_io::read_npy_height_field(&path)?;
//! assert_eq!(back.samples(), field.samples());
//! # std::fs::remove_file(&path)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

mod atomic_write;
mod error;
mod geodesy;
mod input_file;
mod npy_header;
mod npy_read;
mod npy_write;
mod png_read;
mod png_write;
mod raster;
#[cfg(test)]
mod test_dir;
mod void_fill;

pub use error::IoError;
pub use geodesy::metres_per_degree;
pub use npy_read::read_npy_height_field;
pub use npy_write::{write_height_field_npy, write_npy_f32};
pub use png_read::{read_png_rgb, RgbImage};
pub use png_write::{write_png_gray16, write_png_rgb8};
pub use raster::{
    default_memory_limit, DegreeSpacing, Format, PngEncoding, Raster, RasterInfo, ReadOptions,
    VoidPolicy, BYTES_PER_SAMPLE,
};
pub use void_fill::fill_voids;
