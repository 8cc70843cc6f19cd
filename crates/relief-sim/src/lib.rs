//! relief-sim: synthetic and dynamic terrain.
//!
//! - [`fbm_terrain`]: deterministic, seeded fBm mountains of any size, with
//!   [`FbmParams::for_size`] picking parameters that look like real mountains;
//! - [`rivers_rain`]: the reference MLHM simulator's procedural RiversRain scene (fBm hills on
//!   a slope, 256 m square) at any grid size, as a multi-layered height map.
#![deny(missing_docs)]

mod fbm_params;
mod fbm_terrain;
mod gradient_noise;
mod rivers_rain;

pub use fbm_params::{FbmParams, MAX_OCTAVES};
pub use fbm_terrain::fbm_terrain;
pub use rivers_rain::{rivers_rain, RIVERS_RAIN_EXTENT, RIVERS_RAIN_SEED};
