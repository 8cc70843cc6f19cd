//! The errors of relief-trace, by cause.

use std::path::PathBuf;

/// What can go wrong building or using a tracer.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    /// Options that make no sense.
    #[error("invalid options: {0}")]
    Options(String),
    /// A terrain or surface this tracer does not handle.
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// A view (camera or light) the tracer's precomputed data was not built for.
    #[error("view not admitted: {0}")]
    ViewNotAdmitted(String),
    /// Reading or writing a cache file failed.
    #[error("cache file {path}: {source}")]
    CacheIo {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A cache file that is not what it claims to be.
    #[error("cache file {path}: {reason}")]
    CacheFormat {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
}
