//! `relief info`.

use crate::args::*;
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
