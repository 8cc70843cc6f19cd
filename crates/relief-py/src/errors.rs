//! relief's errors as Python exceptions: bad arguments raise [`ReliefError`] (a
//! `ValueError`), files that cannot be read raise `OSError` (or the subclass the operating
//! system's error names, such as `FileNotFoundError`), each with relief's message.

use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError, PyValueError,
};
use pyo3::PyErr;
use relief_io::IoError;
use relief_render::RenderError;
use std::io::ErrorKind;

create_exception!(
    relief,
    ReliefError,
    PyValueError,
    "An argument relief cannot use: a wrong array shape or dtype, an option out of its range, \
     a camera that sees nothing. A subclass of ValueError; the message is the one the relief \
     command line gives for the same mistake."
);

/// A [`ReliefError`] with `message`.
pub fn invalid(message: impl Into<String>) -> PyErr {
    ReliefError::new_err(message.into())
}

/// Any error of relief's library crates about an argument, as a [`ReliefError`].
pub fn argument(error: impl std::fmt::Display) -> PyErr {
    invalid(error.to_string())
}

/// An error reading a file: the operating system's refusals as the `OSError` subclass of
/// their kind, a malformed, unsupported or too large file as `OSError`.
pub fn file(error: IoError) -> PyErr {
    let message = error.to_string();
    match &error {
        IoError::Io { source, .. } => match source.kind() {
            ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
            ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
            ErrorKind::IsADirectory => PyIsADirectoryError::new_err(message),
            _ => PyOSError::new_err(message),
        },
        _ => PyOSError::new_err(message),
    }
}

/// An error of the scene layer: a file that cannot be read as [`file`] raises it, anything
/// else (an option that does not apply, a scene over the memory limit, ...) as a
/// [`ReliefError`].
pub fn scene(error: RenderError) -> PyErr {
    match error {
        RenderError::Io(error) => file(error),
        other => argument(other),
    }
}
