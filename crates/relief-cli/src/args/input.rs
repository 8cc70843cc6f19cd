//! Where a height field comes from and how it is read and placed: the arguments every command
//! reading a height file shares.

use super::values::*;
use crate::parse;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// How height files are read.
#[derive(Debug, Default, Args)]
pub struct ReadArgs {
    /// Voids (nodata): fill them from their surroundings, or keep them as holes [default: fill;
    /// for convert, hole, so that they stay the output's nodata].
    #[arg(long, value_enum)]
    pub voids: Option<Voids>,
    /// Memory a raster may take, e.g. 512M, 8G (default: half the machine's or cgroup's memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// How a PNG encodes heights (PNG input only) [default: grey].
    #[arg(long, value_enum)]
    pub png_encoding: Option<PngHeights>,
    /// The array to read from an .npz archive (.npz input only) [default: the first].
    #[arg(long)]
    pub array: Option<String>,
    /// The unit of the file's heights: m, ft (international foot) or us-ft (US survey foot)
    /// [default: the file's VerticalUnitsGeoKey, else its projected CRS's linear unit, else
    /// metres; `relief info` says which and why]. Heights are converted to metres.
    #[arg(long, value_name = "UNIT", value_parser = z_unit)]
    pub z_unit: Option<relief_io::LengthUnit>,
}

/// `--z-unit`: m, ft or us-ft.
pub(crate) fn z_unit(s: &str) -> Result<relief_io::LengthUnit, String> {
    s.parse()
}

/// `--voids`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Voids {
    /// Nearest valid sample, then smoothed.
    Fill,
    /// Empty texels the rays pass through.
    Hole,
}

/// `--png-encoding`.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PngHeights {
    /// 16- or 8-bit grey values.
    Grey,
    /// Mapbox terrain-RGB tiles.
    TerrainRgb,
    /// Terrarium tiles.
    Terrarium,
}

/// Where the height field comes from and how it is placed in the world.
#[derive(Debug, Args)]
pub struct InputArgs {
    /// Height file: .tif/.tiff (GeoTIFF), .hgt (SRTM), .asc (ESRI ASCII grid), .png (16-bit grey,
    /// terrain-RGB, Terrarium), .npy or .npz; or a multi-layered height map scene (.json, the
    /// reference simulator's format, or .mlhm, relief's own). Without one, the seeded fBm
    /// terrain is used.
    pub input: Option<PathBuf>,
    /// How to read it.
    #[command(flatten)]
    pub read: ReadArgs,
    /// Texel spacing `DX[,DY]` in world units (default: from the file's georeference, else 1).
    #[arg(long, value_parser = parse::spacing, allow_hyphen_values = true)]
    pub spacing: Option<(f64, f64)>,
    /// The array's row 0 is its north edge (as in most north-up rasters): flip the rows.
    #[arg(long)]
    pub north_up: bool,
    /// Multiply heights by this (1e-6 to 1e7), after their unit is turned into metres (see
    /// --z-unit).
    #[arg(long, default_value = "1", value_parser = parse::z_scale, allow_hyphen_values = true)]
    pub z_scale: f64,
    /// Terrain samples per side of the default fBm terrain, when no INPUT is given (1 to
    /// 65536) [default: 1024].
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub fbm_size: Option<usize>,
    /// Seed of the default fBm terrain, when no INPUT is given [default: 1].
    #[arg(long, value_parser = seed, allow_hyphen_values = true)]
    pub seed: Option<u64>,
}
