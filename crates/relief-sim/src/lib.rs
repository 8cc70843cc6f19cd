//! relief-sim: synthetic and dynamic terrain.
//!
//! - [`fbm_terrain`]: deterministic, seeded fBm mountains of any size, with
//!   [`FbmParams::for_size`] picking parameters that look like real mountains.
#![deny(missing_docs)]

mod fbm_params;
mod fbm_terrain;
mod gradient_noise;

pub use fbm_params::{FbmParams, MAX_OCTAVES};
pub use fbm_terrain::fbm_terrain;
