//! `relief tile`.

use crate::args::values::*;
use crate::args::*;
use crate::parse;
use clap::Args;
use relief_core::Precision;
use std::path::PathBuf;

/// `relief tile`.
#[derive(Debug, Args)]
pub struct TileArgs {
    /// The raster, or the rasters of a mosaic (.hgt tiles, or GeoTIFFs on one grid).
    #[arg(required = true, num_args = 1..)]
    pub inputs: Vec<PathBuf>,
    /// The store to write (a folder; resumed when it holds an interrupted build of the same
    /// inputs and options).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Samples along a tile's side (16 to 4096).
    #[arg(long, default_value_t = 512, value_parser = tile_samples)]
    pub tile: u32,
    /// Store samples as f32, or as f16 (half the disk, rounded to the nearest half) [default:
    /// f32].
    #[arg(long, value_parser = parse::precision)]
    pub precision: Option<Precision>,
    /// Memory the build's buffers may take, e.g. 512M, 2G (default: 1G).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// An ortho photo to drape over the DEM, stored as its own pyramid: an 8-bit RGB(A) PNG
    /// (taken to span the DEM's extent exactly, top row north) or GeoTIFF (placed by its
    /// georeference, which must be in the DEM's CRS and cover the DEM).
    #[arg(long, value_name = "ORTHO")]
    pub texture: Option<PathBuf>,
    /// The unit of the inputs' heights: m, ft (international foot) or us-ft (US survey foot)
    /// [default: the file's VerticalUnitsGeoKey, else its projected CRS's linear unit, else
    /// metres]. The store records it; renders take its heights in metres.
    #[arg(long, value_name = "UNIT", value_parser = z_unit)]
    pub z_unit: Option<relief_io::LengthUnit>,
}
