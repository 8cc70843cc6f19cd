//! GeoTIFF: single-band height rasters read whole ([`read_geotiff`]) or by rows, strips and
//! tiles checked against the file before they are decoded (ZSTD ones decoded here); height
//! fields written whole ([`write_geotiff`], [`write_geotiff_placed`]) or band by band
//! ([`GeoTiffStripWriter`]); layer files of named float32 bands ([`write_layers_geotiff`],
//! [`read_layers_geotiff`], with GDAL's band-naming metadata), written block by block in the
//! cloud-optimised layout with overviews, resumably ([`CogWriter`]), and 8-bit RGB ortho
//! photos ([`write_rgb_geotiff`]). Where a GeoTIFF lies (its GeoKeys) is in `georef/`.

pub(crate) mod chunks;
pub(crate) mod cog_journal;
pub(crate) mod cog_layout;
pub(crate) mod cog_overviews;
pub(crate) mod cog_progress;
pub(crate) mod cog_spill;
pub(crate) mod cog_tiles;
pub(crate) mod cog_writer;
pub(crate) mod float_strips;
pub(crate) mod gdal_metadata;
pub(crate) mod layers_read;
pub(crate) mod layers_write;
pub(crate) mod read;
pub(crate) mod rgb_write;
pub(crate) mod rows;
pub(crate) mod stored_chunk;
pub(crate) mod strip_writer;
pub(crate) mod tags;
pub(crate) mod tiff_directory;
pub(crate) mod write;
pub(crate) mod write_tags;

pub use cog_writer::CogWriter;
pub use layers_read::read_layers_geotiff;
pub use layers_write::write_layers_geotiff;
pub use read::read_geotiff;
pub use rgb_write::write_rgb_geotiff;
pub use strip_writer::GeoTiffStripWriter;
pub use write::{write_geotiff, write_geotiff_placed};
