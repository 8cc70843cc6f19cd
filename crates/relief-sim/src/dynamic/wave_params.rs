//! The parameters of the ocean wave simulation, with defaults scaled to a height field.

use crate::error::{finite, non_negative, positive};
use crate::SimError;
use relief_core::HeightField;

/// How the sea of [`WaveSimulation`](super::WaveSimulation) behaves: its level, the damped
/// wave equation's speed and damping, and the two deterministic disturbances (seeded drops
/// and a travelling wind pattern). Lengths and heights are world units, times seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveParams {
    /// World height of the sea at rest.
    pub sea_level: f64,
    /// Speed of the waves, world units per second, > 0.
    pub wave_speed: f64,
    /// Damping rate, per second, >= 0: with no disturbance a wave's amplitude falls by
    /// `exp(-damping t)`.
    pub damping: f64,
    /// Courant number `wave_speed * dt * sqrt(1/dx² + 1/dy²)`, in (0, 1): the time step is
    /// chosen from it; leapfrog is stable below 1 (at 1 the finest mode grows).
    pub courant: f64,
    /// A drop falls every this many steps (0: no drops).
    pub drop_interval: u32,
    /// Height a drop lifts the sea at its centre, world units, >= 0.
    pub drop_amplitude: f64,
    /// Radius of a drop's Gaussian (its standard deviation), world units, > 0.
    pub drop_radius: f64,
    /// Peak acceleration of the sea surface by the wind, world units per second², >= 0.
    pub wind_amplitude: f64,
    /// Wavelength of the wind pattern, world units, > 0.
    pub wind_wavelength: f64,
    /// Direction the wind pattern travels to, degrees counter-clockwise from +x (east).
    pub wind_direction_deg: f64,
    /// Seed of the drops' places.
    pub seed: u64,
}

impl WaveParams {
    /// Defaults for `field`: the sea at 35 % of its height range, waves crossing 200 cells
    /// in about 10 s, drops of 3 cells' radius every 8 steps, and a wind pattern of 40
    /// cells' wavelength travelling north-east.
    pub fn for_field(field: &HeightField) -> Self {
        let g = field.geometry();
        let (lo, hi) =
            (f64::from(field.min_sample()) * g.z_scale, f64::from(field.max_sample()) * g.z_scale);
        let cell = g.dx.max(g.dy);
        let relief = (hi - lo).max(cell);
        WaveParams {
            sea_level: lo + 0.35 * (hi - lo),
            wave_speed: 20.0 * cell,
            damping: 0.2,
            courant: 0.5,
            drop_interval: 8,
            drop_amplitude: 0.02 * relief,
            drop_radius: 3.0 * cell,
            wind_amplitude: 0.5 * cell,
            wind_wavelength: 40.0 * cell,
            wind_direction_deg: 45.0,
            seed: 1,
        }
    }

    /// Checks every value's range.
    pub fn validate(&self) -> Result<(), SimError> {
        finite("sea level", self.sea_level)?;
        positive("wave speed", self.wave_speed)?;
        non_negative("damping", self.damping)?;
        positive("courant number", self.courant)?;
        if self.courant >= 1.0 {
            return Err(SimError::parameter(
                "courant number",
                format!("{} is not below 1: the leapfrog scheme would be unstable", self.courant),
            ));
        }
        non_negative("drop amplitude", self.drop_amplitude)?;
        positive("drop radius", self.drop_radius)?;
        non_negative("wind amplitude", self.wind_amplitude)?;
        positive("wind wavelength", self.wind_wavelength)?;
        finite("wind direction", self.wind_direction_deg)
    }
}
