//! `relief shade`.

use crate::args::values::*;
use crate::args::*;
use crate::parse;
use clap::Args;
use relief_core::Surface;
use relief_shade::shade_map::SkyModel;
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
    /// The layers, comma-separated, in the order of the bands: shadow (cast shadows of the
    /// suns), sky (sky-view factor), hillshade, combined (the map layer), horizon (one band
    /// per direction, degrees), sky-aniso (RVT's anisotropic sky-view factor), openness-pos,
    /// openness-neg (degrees), sky-illumination, hillshade-multi (gdaldem's
    /// -multidirectional), insolation (Wh/m2), sun-hours. Those not in degrees, hours or Wh/m2
    /// are 0 (dark, or closed to the sky) to 1 (lit, or open).
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
    /// Compass directions of the horizons, evenly spaced from north, for the layers built on
    /// them (sky, combined, horizon, sky-aniso, openness, sky-illumination, insolation,
    /// sun-hours; 1 to 4096) [default: 32].
    #[arg(long, value_name = "N", value_parser = azimuths, allow_hyphen_values = true)]
    pub azimuths: Option<u32>,
    /// How far above each sample the horizons are seen from, in metres [default: 0.01].
    #[arg(long, value_name = "M", value_parser = observer_height, allow_hyphen_values = true)]
    pub observer_height: Option<f64>,
    /// Search the horizons this far only, in metres [default: to the edge of the data].
    #[arg(long, value_name = "M", value_parser = radius, allow_hyphen_values = true)]
    pub radius: Option<f64>,
    /// Let the earth's curvature lower distant terrain, less atmospheric refraction of
    /// coefficient K (0 to below 1) [default when given alone: 0.13].
    #[arg(long, value_name = "K", num_args = 0..=1, default_missing_value = "0.13",
          value_parser = refraction)]
    pub earth_curvature: Option<f64>,
    /// The sky of the sky-illumination layer: overcast (three times brighter at the zenith than
    /// at the horizon) or uniform [default: overcast].
    #[arg(long, value_name = "SKY")]
    pub sky_model: Option<SkyModel>,
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
    /// When and where the sun shines: --date, --time, --timezone, --step, --lat, --lon.
    #[command(flatten)]
    pub when: super::when::SunTimeArgs,
    /// Write the stage timings and ray counts to this .json file.
    #[arg(long, value_name = "F.json")]
    pub stats: Option<PathBuf>,
}
