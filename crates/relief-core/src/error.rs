//! The error type of relief-core: invalid data or parameters, arranged by cause.

use thiserror::Error;

/// What can be wrong with data or parameters handed to relief-core.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CoreError {
    /// A grid has no samples, or its sample count does not match its dimensions.
    #[error("invalid grid: {0}")]
    Grid(String),
    /// A sample is NaN or infinite.
    #[error("non-finite sample {value} at column {col}, row {row}")]
    NonFiniteSample {
        /// Column of the offending sample.
        col: usize,
        /// Row of the offending sample.
        row: usize,
        /// The value found.
        value: f32,
    },
    /// A multi-layered height map's cell has a layer count outside `1..=max`.
    #[error("cell ({x}, {y}) of the MLHM has {count} columns, outside 1..={max}")]
    MlhmLayerCount {
        /// Cell column (x).
        x: usize,
        /// Cell row (y).
        y: usize,
        /// The layer count found.
        count: usize,
        /// The map's maximum layer count.
        max: usize,
    },
    /// A column of a multi-layered height map breaks an invariant (a non-finite or negative
    /// value, water above the ceiling, a ceiling above the next bedrock, a finite top ceiling).
    #[error("cell ({x}, {y}), column {column} of the MLHM: {reason}")]
    MlhmColumn {
        /// Cell column (x).
        x: usize,
        /// Cell row (y).
        y: usize,
        /// Column index within the cell, 0 at the bottom.
        column: usize,
        /// What is wrong.
        reason: String,
    },
    /// A layer of a material stack breaks an invariant (not finite, empty or running
    /// backwards, overlapping the layer below, an unknown material).
    #[error("stack ({x}, {y}), layer {layer}: {reason}")]
    StackLayer {
        /// Stack column (x).
        x: usize,
        /// Stack row (y).
        y: usize,
        /// Layer index within the stack, 0 at the bottom.
        layer: usize,
        /// What is wrong.
        reason: String,
    },
    /// A geometric parameter (spacing, scale, origin) is out of range.
    #[error("invalid {name}: {reason}")]
    Parameter {
        /// Which parameter.
        name: &'static str,
        /// Why it was refused.
        reason: String,
    },
    /// The camera cannot be built from the values given.
    #[error("invalid camera: {0}")]
    Camera(String),
}
