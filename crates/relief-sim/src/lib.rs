//! relief-sim: synthetic and dynamic terrain.
//!
//! - [`fbm_terrain`]: deterministic, seeded fBm mountains of any size, with
//!   [`FbmParams::for_size`] picking parameters that look like real mountains; [`FbmRows`]
//!   computes the same terrain a band of rows at a time, for terrains larger than memory;
//! - [`rivers_rain`]: the reference MLHM simulator's procedural RiversRain scene (fBm hills on
//!   a slope, 256 m square) at any grid size, as a multi-layered height map;
//! - [`carved_scene`]: MLHM scenes of the same extent with arches, a cave, a chasm and
//!   overhanging cliffs carved explicitly ([`CarvedScene`]), for tests and benchmarks;
//! - [`stacks_terrain`]: seeded material-stack terrains (Löffler et al. 2011) with overhangs,
//!   caves, arches, sand and water, at the paper's benchmark size ([`StacksTerrainParams`]);
//! - [`erosion`]: the reference simulator's layered hydraulic erosion ([`ErosionState`],
//!   [`ErosionParams`]), parallel and deterministic;
//! - [`dynamic`]: dynamic height fields: brushes that [`stamp`] the terrain, the ocean
//!   [`WaveSimulation`] and the [`HeightFieldErosion`], errors in [`SimError`].
#![deny(missing_docs)]

mod carved_scenes;
pub mod dynamic;
pub mod erosion;
mod error;
mod fbm_params;
mod fbm_terrain;
mod gradient_noise;
mod rivers_rain;
mod stacks_terrain;

pub use carved_scenes::{carved_scene, CarvedScene, CARVED_EXTENT};
pub use dynamic::{stamp, Brush, BrushKind, HeightFieldErosion, WaveParams, WaveSimulation};
pub use erosion::{ErosionError, ErosionParams, ErosionState, SimulationPlanes, StepVolumes};
pub use error::SimError;
pub use fbm_params::{FbmParams, MAX_OCTAVES};
pub use fbm_terrain::{fbm_terrain, FbmRows};
pub use rivers_rain::{rivers_rain, RIVERS_RAIN_EXTENT, RIVERS_RAIN_SEED};
pub use stacks_terrain::{stacks_terrain, StacksTerrainParams, MIN_LAYER};
