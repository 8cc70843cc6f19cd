//! relief-io: reading and writing the files relief consumes and produces.
//!
//! The crate is laid out by format, as image-rs lays out its codecs: each format's readers and
//! writers are a public module of their own,
//!
//! - [`geotiff`]: single-band GeoTIFFs read whole or by rows, written whole or band by band,
//!   layer files of named bands, cloud-optimised GeoTIFFs written block by block, RGB ortho
//!   photos;
//! - [`npy`]: NumPy `.npy` arrays and `.npz` archives;
//! - [`png`]: heights in PNG images (greyscale, terrain-RGB, Terrarium), shade layers with
//!   their world files, RGB and grey pictures;
//! - [`hgt`]: SRTM `.hgt` tiles; [`asc`]: ESRI ASCII grids; [`jpeg`]: JPEG pictures;
//! - [`mlhm`]: multi-layered height map scenes of the reference simulator and relief's own
//!   `.mlhm` files; [`stacks`]: relief's own `.stacks` files of material stacks;
//!
//! and what does not depend on a format stands at the root:
//!
//! - [`read_raster`]: any height file, by extension, as a [`Raster`] (row 0 south, voids as
//!   NaN, geometry in metres when the file is georeferenced, degrees converted at the raster's
//!   latitude); [`Raster::into_height_field`] fills the voids or keeps them as holes;
//!   [`ReadOptions`]: the memory budget (refused before allocating), the `.npz` array, the PNG
//!   encoding; [`default_memory_budget`]: half the smaller of the machine's memory and its
//!   cgroup's limit, with the words saying which applied;
//! - [`write_height_field`]: a height field by extension; [`write_height_field_georeferenced`]
//!   keeps an input's CRS and placement in every format that can hold them (GeoTIFF keys,
//!   `.asc` and `.png` with `.prj` and world file) and says what it could not keep;
//! - [`RowSource`]: a raster read in bands of rows, never whole: [`open_rows`] streams a
//!   GeoTIFF, an SRTM tile or a `.npy` file (and serves other formats from memory),
//!   [`open_mosaic`] joins SRTM tiles by their names or GeoTIFFs by their georeference into
//!   one raster; [`InMemoryRows`] serves one already read; [`open_ortho`] reads an ortho photo
//!   (8-bit RGB PNG or GeoTIFF) row by row as [`OrthoRows`], with its georeference;
//! - [`Georeference`]: a file's placement and CRS as stored (its GeoTIFF tags and GDAL
//!   geotransform), for outputs aligned with the input; [`HeightUnit`], [`LengthUnit`]: the
//!   unit of a raster's heights and why; [`LayerRaster`]: named float32 layers on one grid;
//! - [`IoError`]: why a file could not be read or written, by cause.
//!
//! Names that other crates took from the root before the formats had modules of their own
//! (`relief_io::write_geotiff`, `relief_io::read_mlhm_scene`, ...) are re-exported there too.
//!
//! Readers never trust a header: sizes are checked against the file before anything is
//! allocated. Writers write a temporary file beside the target and rename it into place, so a
//! failed write never leaves a partial file. Every error names the file and says what was wrong.
//!
//! ```
//! use relief_core::{GridGeometry, HeightField};
//! let path = std::env::temp_dir().join(format!("relief-io-doc-{}.npy", std::process::id()));
//! let field = HeightField::new(3, 2, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0], GridGeometry::unit())?;
//! relief_io::npy::write_height_field_npy(&path, &field)?;
//! let back = relief_io::npy::read_npy_height_field(&path)?;
//! assert_eq!(back.samples(), field.samples());
//! # std::fs::remove_file(&path)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod asc;
pub mod geotiff;
pub mod hgt;
pub mod jpeg;
pub mod mlhm;
pub mod npy;
pub mod png;
pub mod stacks;

mod atomic_write;
mod error;
mod format_error;
mod georef;
mod input_file;
mod layer_raster;
mod memory_budget;
mod raster;
mod read;
mod rows;
mod sample_type;
#[cfg(test)]
mod test_corruption;
#[cfg(test)]
mod test_dir;
mod void_fill;
mod write;

pub use atomic_write::write_bytes_atomically;
pub use error::IoError;
pub use georef::geodesy::metres_per_degree;
pub use georef::geographic_position::{utm_to_geographic, GeographicPosition, PositionError};
pub use georef::georeference::{GeoTiffTags, Georeference, EPSG_WGS84};
pub use georef::height_unit::{HeightUnit, LengthUnit};
pub use georef::sidecars::{aux_xml_path, prj_path, world_file_path};
pub use layer_raster::{Layer, LayerRaster};
pub use memory_budget::{default_memory_budget, default_memory_limit, MemoryBudget};
pub use raster::{
    height_field_of_samples, DegreeSpacing, Format, PngEncoding, Raster, RasterInfo, ReadOptions,
    VoidPolicy, BYTES_PER_SAMPLE,
};
pub use read::{format_of, read_raster, read_raster_from_bytes};
pub use rows::mosaic::open_mosaic;
pub use rows::open_rows::open_rows;
pub use rows::ortho::{open_ortho, OrthoInfo, OrthoRows};
pub use rows::row_source::{InMemoryRows, RowSource};
pub use void_fill::fill_voids;
pub use write::{write_height_field, write_height_field_georeferenced, WriteNotes};

// The formats' names that other crates (and the fuzz targets) take from the root.
pub use geotiff::{
    read_layers_geotiff, write_geotiff, write_geotiff_placed, write_layers_geotiff,
    write_rgb_geotiff, CogWriter, GeoTiffStripWriter,
};
pub use hgt::write_hgt;
pub use jpeg::{write_jpeg_rgb8, JPEG_QUALITY};
pub use mlhm::{
    read_mlhm_native, read_mlhm_native_from_bytes, read_mlhm_scene, read_mlhm_scene_from_bytes,
    write_mlhm_native, write_mlhm_scene, MlhmScene, SimulationState,
};
pub use npy::{read_npy_f32_array, read_npy_height_field, write_height_field_npy, write_npy_f32};
pub use png::{
    read_png_rgb, write_layer_png, write_png_rgb8, write_png_rgb8_compressed, PngCompression,
};
pub use stacks::{is_stacks_path, read_stacks, stacks_from_bytes, write_stacks, STACKS_EXTENSION};
