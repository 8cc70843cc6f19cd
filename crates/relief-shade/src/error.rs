//! The error type of relief-shade: refused parameters and buffers, arranged by cause.

use thiserror::Error;

/// What can be wrong with the parameters or buffers handed to relief-shade.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ShadeError {
    /// A shading or texture parameter is out of range (NaN, negative, ...).
    #[error("invalid {name}: {reason}")]
    Parameter {
        /// Which parameter.
        name: &'static str,
        /// Why it was refused.
        reason: String,
    },
    /// Buffers that must agree in size do not (e.g. a G-buffer and the camera that shades it).
    #[error("size mismatch: {0}")]
    Mismatch(String),
    /// An image is too large to allocate.
    #[error("limit exceeded: {0}")]
    Limits(String),
}

impl ShadeError {
    /// A [`ShadeError::Parameter`] for `name`.
    pub(crate) fn parameter(name: &'static str, reason: impl Into<String>) -> Self {
        ShadeError::Parameter { name, reason: reason.into() }
    }
}

/// Checks that a void mask, if given, has one flag per sample of a `width` x `height` field.
pub(crate) fn check_void_mask(
    void: Option<&[bool]>,
    width: usize,
    height: usize,
) -> Result<(), ShadeError> {
    match void {
        Some(void) if void.len() != width * height => Err(ShadeError::Mismatch(format!(
            "a void mask of {} samples for a {width}x{height} height field",
            void.len()
        ))),
        _ => Ok(()),
    }
}

/// Checks that `value` is finite and at least 0.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<(), ShadeError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(ShadeError::parameter(name, format!("{value} is not a finite number >= 0")))
    }
}

/// Checks that every channel of a colour is finite and at least 0.
pub(crate) fn non_negative_colour(name: &'static str, c: [f32; 3]) -> Result<(), ShadeError> {
    if c.iter().all(|v| v.is_finite() && *v >= 0.0) {
        Ok(())
    } else {
        Err(ShadeError::parameter(name, format!("{c:?} must have finite channels >= 0")))
    }
}
