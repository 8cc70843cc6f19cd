//! What a format's decoder says is wrong with the bytes it reads, before the file is named:
//! the entry point that opened the file ([`read_raster`](crate::read_raster), or a format's
//! own `read_*`) names it once, turning the error into an [`IoError`] of the same cause.

use crate::IoError;
use std::path::Path;
use thiserror::Error;

/// Why bytes could not be read as a raster of their format, by cause, without the file's
/// name; [`FormatError::at`] names the file.
#[derive(Debug, Error)]
pub(crate) enum FormatError {
    /// Reading the bytes failed: becomes [`IoError::Io`].
    #[error("{0}")]
    Io(std::io::Error),
    /// The bytes are not a well-formed file of the format: becomes [`IoError::Format`].
    #[error("malformed file: {0}")]
    Format(String),
    /// The file uses a feature relief does not read: becomes [`IoError::Unsupported`].
    #[error("unsupported {0}")]
    Unsupported(String),
    /// The values read are not acceptable: becomes [`IoError::InvalidData`].
    #[error("invalid data: {0}")]
    InvalidData(String),
    /// The raster would need more memory than the budget: becomes [`IoError::Limits`].
    #[error("{width} x {height} samples need {needed} bytes, over the {limit}-byte limit")]
    Limits {
        /// Raster width in samples.
        width: u64,
        /// Raster height in samples.
        height: u64,
        /// Bytes reading it would need.
        needed: u64,
        /// The budget in bytes.
        limit: u64,
    },
    /// An error about another file, which names that file itself (a sidecar beside the one
    /// read): kept as it is.
    #[error("{0}")]
    OtherFile(IoError),
}

impl FormatError {
    /// The error as an [`IoError`] naming `path`, the file whose bytes were read.
    pub(crate) fn at(self, path: &Path) -> IoError {
        let path = path.to_path_buf();
        match self {
            FormatError::Io(source) => IoError::Io { path, source },
            FormatError::Format(reason) => IoError::Format { path, reason },
            FormatError::Unsupported(what) => IoError::Unsupported { path, what },
            FormatError::InvalidData(reason) => IoError::InvalidData { path, reason },
            FormatError::Limits { width, height, needed, limit } => {
                IoError::Limits { path, width, height, needed, limit }
            }
            FormatError::OtherFile(error) => error,
        }
    }
}

impl From<IoError> for FormatError {
    fn from(error: IoError) -> Self {
        FormatError::OtherFile(error)
    }
}
