//! Dynamic height fields: edits and simulations that rewrite a [`relief_core::HeightField`]
//! in place, as the hybrid-rendering paper's section 5.3 runs them (Ammann et al. 2010):
//!
//! - [`stamp`] (`stamp.rs`): brushes that raise, lower, smooth or flatten a disc and return the
//!   [`relief_core::SampleRegion`] they touched, so that renderers update only that;
//! - [`WaveSimulation`] (`waves.rs`, parameters in `wave_params.rs`): the ocean wave
//!   simulation, rewriting the whole field every step;
//! - [`HeightFieldErosion`] (`height_field_erosion.rs`): the layered hydraulic erosion of
//!   [`crate::erosion`] on one column per cell, rewriting the whole field every step.

mod height_field_erosion;
mod stamp;
mod wave_params;
mod waves;

pub use height_field_erosion::HeightFieldErosion;
pub use stamp::{stamp, Brush, BrushKind};
pub use wave_params::WaveParams;
pub use waves::WaveSimulation;
