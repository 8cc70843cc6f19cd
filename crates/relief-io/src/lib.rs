//! relief-io: reading and writing the files relief consumes and produces.
//!
//! - [`read_raster`]: any height file, by extension, as a [`Raster`] (row 0 south, voids as
//!   NaN, geometry in metres when the file is georeferenced, degrees converted at the raster's
//!   latitude); [`Raster::into_height_field`] fills the voids or keeps them as holes. Readers:
//!   [`read_geotiff`], [`read_hgt`] (SRTM tiles), [`read_asc`] (ESRI ASCII grids),
//!   [`read_png_height`] (greyscale, terrain-RGB and Terrarium PNGs), [`read_npy`],
//!   [`read_npz`] (NumPy), and [`read_npy_height_field`] for a plain `.npy` grid;
//! - [`RowSource`]: a raster read in bands of rows, never whole: [`open_rows`] streams a
//!   GeoTIFF, an SRTM tile or a `.npy` file (and serves other formats from memory),
//!   [`open_mosaic`] joins SRTM tiles by their names or GeoTIFFs by their georeference into
//!   one raster; [`InMemoryRows`] serves one already read; [`GeoTiffStripWriter`] writes a
//!   float32 GeoTIFF row band by row band;
//! - [`RasterInfo::georeference`]: the file's placement and CRS as stored ([`Georeference`]:
//!   its GeoTIFF tags and GDAL geotransform), for outputs aligned with the input;
//!   [`write_layers_geotiff`] writes named float32 layers ([`LayerRaster`]) with it, one band
//!   each, and [`read_layers_geotiff`] reads them back; [`write_layer_png`] writes one layer
//!   as a 16-bit PNG with a world file;
//! - [`write_height_field`]: a height field by extension, through [`write_geotiff`],
//!   [`write_hgt`], [`write_asc`], [`write_png16_height`] (16 bits over the heights' range,
//!   [`PngHeightScale`] in tEXt chunks) or [`write_height_field_npy`];
//!   [`write_height_field_georeferenced`] keeps an input's CRS and placement in every format
//!   that can hold them (GeoTIFF keys, `.asc` and `.png` with `.prj` and world file) and says
//!   what it could not keep;
//! - [`HeightUnit`], [`LengthUnit`]: the unit of a raster's heights (VerticalUnitsGeoKey, the
//!   CRS's linear unit, [`ReadOptions::z_unit`]) and why; readers give the raster's geometry
//!   the z scale to metres; [`Georeference::epsg`], [`Georeference::esri_wkt`] and
//!   [`Georeference::height_unit`] describe a georeference's CRS;
//! - [`read_mlhm_scene`], [`write_mlhm_scene`]: multi-layered height map scenes of the
//!   reference simulator (JSON settings and a zlib `.dat`, f32 or f16) as an [`MlhmScene`];
//!   [`read_mlhm_scene_header`] for the JSON alone (a procedural scene has no `.dat`);
//! - [`read_mlhm_native`], [`write_mlhm_native`]: relief's own `.mlhm` files, a NumPy `.npz`
//!   archive of the layer counts, the columns (f32 or f16) and the cell size;
//! - [`read_stacks`], [`write_stacks`]: relief's own `.stacks` files of material stacks
//!   ([`relief_core::MaterialStacks`]), a little-endian binary ([`is_stacks_path`] and
//!   [`has_stacks_magic`] recognise one);
//! - [`ReadOptions`]: the memory budget (refused before allocating), the `.npz` array, the PNG
//!   encoding; [`default_memory_budget`]: the default budget, half the smaller of the
//!   machine's memory and its cgroup's limit, with the words saying which applied;
//! - [`write_npy_f32`], [`write_height_field_npy`]: little-endian f32 `.npy` arrays (depth
//!   images, normals, height fields);
//! - [`write_png_rgb8`], [`write_png_gray16`], [`read_png_rgb`]: PNG images;
//!   [`write_jpeg_rgb8`]: JPEG pictures;
//! - [`open_ortho`]: an ortho photo (8-bit RGB PNG or GeoTIFF) read row by row as
//!   [`OrthoRows`], with its georeference; [`write_rgb_geotiff`] writes one.
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

mod asc;
mod atomic_write;
mod crs;
mod epsg_feet;
mod error;
mod gdal_metadata;
mod geodesy;
mod geokeys;
mod georeference;
mod geotiff_chunks;
mod geotiff_read;
mod geotiff_rows;
mod geotiff_strip_writer;
mod geotiff_write;
mod height_unit;
mod hgt;
mod hgt_rows;
mod input_file;
mod jpeg_write;
mod layer_png_write;
mod layer_raster;
mod layers_geotiff_read;
mod layers_geotiff_write;
mod memory_budget;
mod mlhm_native;
mod mlhm_scene;
mod mosaic;
mod npy_header;
mod npy_raster;
mod npy_read;
mod npy_rows;
mod npy_write;
mod npz;
mod open_rows;
mod ortho_read;
mod png_height;
mod png_read;
mod png_write;
mod raster;
mod read;
mod rgb_geotiff_write;
mod row_source;
mod sample_type;
mod sidecars;
mod stacks_native;
mod stored_chunk;
#[cfg(test)]
mod test_corruption;
#[cfg(test)]
mod test_dir;
mod void_fill;
mod write;

pub use asc::{read_asc, write_asc};
pub use atomic_write::write_bytes_atomically;
pub use error::IoError;
pub use geodesy::metres_per_degree;
pub use georeference::{GeoTiffTags, Georeference, EPSG_WGS84};
pub use geotiff_read::read_geotiff;
pub use geotiff_strip_writer::GeoTiffStripWriter;
pub use geotiff_write::{write_geotiff, write_geotiff_placed};
pub use height_unit::{HeightUnit, LengthUnit};
pub use hgt::{hgt_tile_corner, read_hgt, write_hgt, HGT_VOID};
pub use jpeg_write::{write_jpeg_rgb8, JPEG_QUALITY};
pub use layer_png_write::{world_file_path, write_layer_png};
pub use layer_raster::{Layer, LayerRaster};
pub use layers_geotiff_read::read_layers_geotiff;
pub use layers_geotiff_write::write_layers_geotiff;
pub use memory_budget::{default_memory_budget, default_memory_limit, MemoryBudget};
pub use mlhm_native::{
    read_mlhm_native, read_mlhm_native_from_bytes, write_mlhm_native, MLHM_NATIVE_VERSION,
};
pub use mlhm_scene::{
    parse_mlhm_scene_header, read_mlhm_scene, read_mlhm_scene_from_bytes, read_mlhm_scene_header,
    write_mlhm_scene, MlhmScene, MlhmSceneHeader, SimulationState, F16_SLACK, F32_SLACK,
};
pub use mosaic::open_mosaic;
pub use npy_raster::read_npy;
pub use npy_read::{read_npy_f32_array, read_npy_height_field};
pub use npy_write::{write_height_field_npy, write_npy_f32};
pub use npz::read_npz;
pub use open_rows::open_rows;
pub use ortho_read::{open_ortho, OrthoInfo, OrthoRows};
pub use png_height::{
    read_png_height, write_png16_height, write_png16_height_in, PngHeightScale, PNG_HEIGHT_OFFSET,
    PNG_HEIGHT_SCALE, PNG_HEIGHT_UNIT,
};
pub use png_read::{read_png_rgb, RgbImage};
pub use png_write::{write_png_gray16, write_png_rgb8, write_png_rgb8_compressed, PngCompression};
pub use raster::{
    DegreeSpacing, Format, PngEncoding, Raster, RasterInfo, ReadOptions, VoidPolicy,
    BYTES_PER_SAMPLE,
};
pub use read::{format_of, read_raster, read_raster_from_bytes};
pub use rgb_geotiff_write::write_rgb_geotiff;
pub use row_source::{InMemoryRows, RowSource};
pub use stacks_native::{
    has_stacks_magic, is_stacks_path, read_stacks, stacks_from_bytes, stacks_to_bytes,
    write_stacks, STACKS_EXTENSION, STACKS_MAGIC, STACKS_VERSION,
};
pub use void_fill::fill_voids;
pub use write::{
    aux_xml_path, prj_path, write_height_field, write_height_field_georeferenced, WriteNotes,
};
