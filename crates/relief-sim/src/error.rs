//! The error type of relief-sim's dynamic terrain (stamping, waves, height-field erosion),
//! arranged by cause.

use crate::erosion::ErosionError;
use relief_core::CoreError;
use thiserror::Error;

/// What can be wrong with the parameters or the terrain handed to a dynamic-terrain edit or
/// simulation.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    /// A brush or simulation parameter is out of range (NaN, infinite, negative, ...).
    #[error("invalid {name}: {reason}")]
    Parameter {
        /// The parameter's name.
        name: &'static str,
        /// Why it was refused.
        reason: String,
    },
    /// The height field does not fit the simulation (another size than the one it started
    /// with, non-square cells for the erosion, holes).
    #[error("height field does not fit: {0}")]
    Mismatch(String),
    /// The height field refused the new samples.
    #[error(transparent)]
    Terrain(#[from] CoreError),
    /// The layered erosion refused its parameters or state.
    #[error(transparent)]
    Erosion(#[from] ErosionError),
}

impl SimError {
    /// A [`SimError::Parameter`] for `name`.
    pub(crate) fn parameter(name: &'static str, reason: impl Into<String>) -> Self {
        SimError::Parameter { name, reason: reason.into() }
    }
}

/// Checks that `value` is finite.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<(), SimError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(SimError::parameter(name, format!("{value} is not finite")))
    }
}

/// Checks that `value` is finite and more than 0.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<(), SimError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SimError::parameter(name, format!("{value} is not a finite number > 0")))
    }
}

/// Checks that `value` is finite and at least 0.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<(), SimError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(SimError::parameter(name, format!("{value} is not a finite number >= 0")))
    }
}
