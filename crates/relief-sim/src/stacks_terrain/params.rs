//! The parameters of a stacks terrain, and their ranges.

use crate::error::{non_negative, positive};
use crate::SimError;

/// The parameters of [`stacks_terrain`](crate::stacks_terrain).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StacksTerrainParams {
    /// Distance between neighbouring stacks in metres, > 0 [default: 2, the paper's 4 km x
    /// 8 km over 2048 x 4096 stacks].
    pub spacing: f64,
    /// Highest height in metres, > 0 [default: 768, the paper's 512 voxels of 1.5 m].
    pub max_height: f64,
    /// Fraction of the stacks whose ground lies under the sea level, 0 to 1 [default: 0.1].
    pub water_fraction: f64,
    /// Thickness in metres of the sand on flat low ground, thinning to none on slopes of 2 in
    /// 5 and steeper and on the upper half of the relief, >= 0 [default: 3].
    pub sand_thickness: f64,
}

impl Default for StacksTerrainParams {
    fn default() -> Self {
        StacksTerrainParams {
            spacing: 2.0,
            max_height: 768.0,
            water_fraction: 0.1,
            sand_thickness: 3.0,
        }
    }
}

impl StacksTerrainParams {
    /// Checks every field's range; the error names the first field out of range.
    pub fn validate(&self) -> Result<(), SimError> {
        positive("spacing", self.spacing)?;
        positive("max_height", self.max_height)?;
        if !(self.max_height <= f64::from(f32::MAX) / 4.0 && self.spacing <= 1e12) {
            return Err(SimError::parameter("max_height", "spacing or max_height too large"));
        }
        if !(0.0..=1.0).contains(&self.water_fraction) {
            return Err(SimError::parameter(
                "water_fraction",
                format!("{} is not in 0..=1", self.water_fraction),
            ));
        }
        non_negative("sand_thickness", self.sand_thickness)
    }
}
