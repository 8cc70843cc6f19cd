//! `relief info` and `relief convert`.

use super::input::*;
use clap::Args;
use std::path::PathBuf;

/// `relief info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Height file, or an MLHM scene (.json or .mlhm).
    pub input: PathBuf,
    /// How to read it.
    #[command(flatten)]
    pub read: ReadArgs,
}

/// `relief convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// Height file to read.
    pub input: PathBuf,
    /// File to write: .tif (float32 GeoTIFF), .hgt, .asc, .png (16-bit grey) or .npy; an MLHM
    /// scene converts between .json and .mlhm.
    pub output: PathBuf,
    /// How to read the input (voids are kept as nodata unless --voids fill is given).
    #[command(flatten)]
    pub read: ReadArgs,
}
