//! The errors of the erosion simulation, arranged by cause.

use super::invariants::{after_stage, Stage};
use relief_core::CoreError;
use thiserror::Error;

/// What can be wrong with the parameters or the state handed to the erosion simulation.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ErosionError {
    /// A parameter of [`ErosionParams`](super::ErosionParams) is out of range.
    #[error("invalid erosion parameter {name}: {reason}")]
    Parameter {
        /// The parameter's field name.
        name: &'static str,
        /// Why it was refused.
        reason: String,
    },
    /// A simulation plane (fluxes, stability, sediment, damage, heights) has the wrong length.
    #[error("simulation plane {plane} holds {found} values, {expected} expected")]
    PlaneLength {
        /// Which plane.
        plane: &'static str,
        /// Values found.
        found: usize,
        /// Values expected (one per column slot).
        expected: usize,
    },
    /// A value of a simulation plane is out of range (NaN, infinite or negative).
    #[error("cell ({x}, {y}), column {column}: {plane} is {value}, {reason}")]
    PlaneValue {
        /// Which plane.
        plane: &'static str,
        /// Cell column (x).
        x: usize,
        /// Cell row (y).
        y: usize,
        /// Column within the cell, 0 at the bottom.
        column: usize,
        /// The value found.
        value: f32,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The terrain breaks an MLHM invariant, or its shape is invalid.
    #[error(transparent)]
    Terrain(#[from] CoreError),
    /// A simulation step broke the state's invariants ([`ErosionState::validate`]): a bug of
    /// the simulation, which the state's last valid copy survives.
    ///
    /// [`ErosionState::validate`]: super::ErosionState::validate
    #[error("simulation step {step} broke the terrain {}: {error}", after_stage(.stage))]
    Invariant {
        /// The step (its number before it ran, as [`super::ErosionState::step_count`]).
        step: u64,
        /// The stage after which the check failed, when each stage was checked
        /// ([`super::ErosionState::step_checking_stages`]); `None` for the check after the step.
        stage: Option<Stage>,
        /// What is wrong, naming the cell and the column.
        error: Box<ErosionError>,
    },
}
