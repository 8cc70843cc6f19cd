//! Errors of relief-tiles, by cause.

use crate::TileId;
use std::path::PathBuf;
use thiserror::Error;

/// Why a tile store could not be built, opened or read.
#[derive(Debug, Error)]
pub enum TileError {
    /// A file of the store could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The input raster could not be read.
    #[error(transparent)]
    Input(#[from] relief_io::IoError),
    /// The store's index is not a tile store this version reads.
    #[error("{path}: {reason}")]
    Format {
        /// The index file.
        path: PathBuf,
        /// What was wrong.
        reason: String,
    },
    /// The store's build did not finish.
    #[error(
        "{path}: the tile store is incomplete ({done} of {total} tiles built); run the same \
         `relief tile` command again to resume it"
    )]
    Incomplete {
        /// The store.
        path: PathBuf,
        /// Tiles built.
        done: u64,
        /// Tiles the store needs.
        total: u64,
    },
    /// A tile's bytes are missing or do not match their checksum.
    #[error("{path}: {tile} is corrupt: {reason}")]
    Corrupt {
        /// The store's data file.
        path: PathBuf,
        /// The tile.
        tile: TileId,
        /// What was wrong.
        reason: String,
    },
    /// The options or inputs cannot make a store.
    #[error("{0}")]
    Invalid(String),
    /// A store exists at the output from other inputs or options, so it cannot be resumed.
    #[error("{path}: {reason}; remove it or choose another output")]
    Mismatch {
        /// The store.
        path: PathBuf,
        /// What differs.
        reason: String,
    },
    /// A build stopped on purpose (a test's injected failure).
    #[error("build stopped after {0} tiles (injected failure)")]
    Injected(u64),
}

impl TileError {
    /// An IO error of `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        TileError::Io { path: path.into(), source }
    }
}
