//! The error type of relief-io: what went wrong reading or writing a file, arranged by cause.

use std::path::PathBuf;
use thiserror::Error;

/// Why a file could not be read or written. Every variant names the file.
#[derive(Debug, Error)]
pub enum IoError {
    /// The operating system refused an operation (missing file, permissions, a directory, ...).
    #[error("{}: {source}", path.display())]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file is not a well-formed file of its kind (wrong magic, truncated, a header that
    /// disagrees with the data, ...).
    #[error("{}: malformed file: {reason}", path.display())]
    Format {
        /// The file concerned.
        path: PathBuf,
        /// What is malformed.
        reason: String,
    },
    /// The file is well formed but uses a feature relief does not read (a dtype, a number of
    /// dimensions, ...).
    #[error("{}: unsupported {what}", path.display())]
    Unsupported {
        /// The file concerned.
        path: PathBuf,
        /// The feature found.
        what: String,
    },
    /// The values read or to be written are not acceptable (non-finite heights, a buffer whose
    /// length does not match its dimensions, ...).
    #[error("{}: invalid data: {reason}", path.display())]
    InvalidData {
        /// The file concerned.
        path: PathBuf,
        /// What is wrong with the values.
        reason: String,
    },
    /// Files that cannot be read as one mosaic: of different formats, pixel sizes or
    /// coordinate reference systems, off each other's sample grid, or without a placement.
    #[error("{}: cannot be one mosaic: {reason}", list_paths(paths))]
    Mosaic {
        /// The files concerned, the first the one the others are compared with.
        paths: Vec<PathBuf>,
        /// What differs, or what is missing.
        reason: String,
    },
    /// The raster would need more memory than the user's budget allows; refused before
    /// allocating.
    #[error(
        "{}: {width} x {height} samples need {} MiB, over the {} MiB memory limit (raise it with --max-memory)",
        path.display(), needed / 1048576, limit / 1048576
    )]
    Limits {
        /// The file concerned.
        path: PathBuf,
        /// Raster width in samples.
        width: u64,
        /// Raster height in samples.
        height: u64,
        /// Bytes reading it would need.
        needed: u64,
        /// The budget in bytes.
        limit: u64,
    },
}

/// "a.tif and b.tif", "a.tif, b.tif and c.tif".
fn list_paths(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    match names.split_last() {
        None => "no files".to_string(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}

impl IoError {
    /// An [`IoError::Io`] for `path`.
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        IoError::Io { path: path.to_path_buf(), source }
    }

    /// An [`IoError::Format`] for `path`.
    pub(crate) fn format(path: &std::path::Path, reason: impl Into<String>) -> Self {
        IoError::Format { path: path.to_path_buf(), reason: reason.into() }
    }

    /// An [`IoError::Unsupported`] for `path`.
    pub(crate) fn unsupported(path: &std::path::Path, what: impl Into<String>) -> Self {
        IoError::Unsupported { path: path.to_path_buf(), what: what.into() }
    }

    /// An [`IoError::InvalidData`] for `path`.
    pub(crate) fn invalid_data(path: &std::path::Path, reason: impl Into<String>) -> Self {
        IoError::InvalidData { path: path.to_path_buf(), reason: reason.into() }
    }

    /// An [`IoError::Mosaic`] of `paths`.
    pub(crate) fn mosaic(paths: &[&std::path::Path], reason: impl Into<String>) -> Self {
        IoError::Mosaic {
            paths: paths.iter().map(|p| p.to_path_buf()).collect(),
            reason: reason.into(),
        }
    }
}
