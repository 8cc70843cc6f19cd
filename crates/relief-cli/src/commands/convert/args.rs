//! `relief convert`.

use crate::args::*;
use clap::Args;
use std::path::PathBuf;

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
