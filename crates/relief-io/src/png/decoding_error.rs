//! The `png` crate's decoding errors by cause, before the file is named.

use crate::format_error::FormatError;
use png::DecodingError;
use std::io::ErrorKind;

/// A PNG decoding error as a [`FormatError`]: a stream that ends early is a truncated file,
/// another read failure an I/O error, anything else a malformed file.
pub(crate) fn png_decoding_error(error: DecodingError) -> FormatError {
    match error {
        DecodingError::IoError(e) if e.kind() == ErrorKind::UnexpectedEof => {
            FormatError::Format("truncated".into())
        }
        DecodingError::IoError(e) => FormatError::Io(e),
        other => FormatError::Format(other.to_string()),
    }
}
