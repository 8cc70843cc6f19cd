//! `relief shade`.

use crate::args::values::*;
use crate::args::*;
use crate::parse;
use clap::Args;
use relief_core::Surface;
use relief_shade::ShadeLayer;
use std::path::PathBuf;

/// `relief shade`.
#[derive(Debug, Args)]
pub struct ShadeArgs {
    /// The DEM: .tif/.tiff (GeoTIFF), .hgt, .asc, .png, .npy or .npz.
    pub input: PathBuf,
    /// How to read it (voids are filled for tracing, and are nodata in every layer).
    #[command(flatten)]
    pub read: ReadArgs,
    /// The file to write: .tif (a float32 GeoTIFF, one band per layer, each described by its
    /// layer's name) or .png (one layer, 16-bit grey, with a .pgw world file).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The layers, comma-separated, in the order of the bands: shadow, sky, hillshade,
    /// combined. Each is 0 (dark, or closed to the sky) to 1 (lit, or open).
    #[arg(long, value_delimiter = ',', default_values = ["combined"])]
    pub layers: Vec<ShadeLayer>,
    /// A sun, AZIMUTH,ELEVATION in degrees (azimuth clockwise from north, elevation above the
    /// horizon, above 0); give it again for more suns (`--sun 315,45 --sun 45,30`), which are
    /// averaged [default: 315,45].
    #[arg(long, value_parser = parse::sun, allow_hyphen_values = true,
          action = clap::ArgAction::Append, value_name = "AZ,EL")]
    pub sun: Vec<(f64, f64)>,
    /// Angular radius of each sun's disc in degrees, for soft shadows (the real sun's is 0.27)
    /// [default: 0, a point].
    #[arg(long, value_name = "DEG", value_parser = sun_radius, allow_hyphen_values = true)]
    pub sun_radius: Option<f64>,
    /// Rays over each sun's disc, with --sun-radius (1 to 4096) [default: 16].
    #[arg(long, value_name = "N", value_parser = shade_rays, allow_hyphen_values = true)]
    pub sun_rays: Option<u32>,
    /// Directions over the sky for the sky-view factor, for the sky and combined layers (1 to
    /// 4096) [default: 64].
    #[arg(long, value_name = "N", value_parser = shade_rays, allow_hyphen_values = true)]
    pub sky_rays: Option<u32>,
    /// The surface the rays meet: triangles (through the samples) or boxes (a flat-topped
    /// column per sample).
    #[arg(long, default_value = "triangles")]
    pub surface: Surface,
    /// Texel spacing `DX[,DY]` in metres (default: from the file's georeference, else 1).
    #[arg(long, value_parser = parse::spacing, allow_hyphen_values = true)]
    pub spacing: Option<(f64, f64)>,
    /// Multiply heights by this (1e-6 to 1e7), after their unit is turned into metres (see
    /// --z-unit).
    #[arg(long, default_value = "1", value_parser = parse::z_scale, allow_hyphen_values = true)]
    pub z_scale: f64,
    /// Write the stage timings and ray counts to this .json file.
    #[arg(long, value_name = "F.json")]
    pub stats: Option<PathBuf>,
}
