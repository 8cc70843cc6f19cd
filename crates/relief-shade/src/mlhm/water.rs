//! How much light water absorbs on the way (Beer's law with the reference extinction
//! coefficients), in the paper's cheap and expensive modes.

use super::preset::WaterAbsorption;
use relief_core::DVec3;

/// Extinction coefficients of water per metre for red, green and blue.
pub const WATER_EXTINCTION: [f64; 3] = [0.2, 0.15, 0.1];

/// The distance light is taken to travel through water for a view ray that ran `t_water`
/// through water to a point `depth_below_surface` under it (section 4.6).
pub fn absorption_distance(mode: WaterAbsorption, t_water: f64, depth_below_surface: f64) -> f64 {
    match mode {
        WaterAbsorption::Cheap => 2.0 * t_water,
        WaterAbsorption::Expensive => (t_water + depth_below_surface).min(2.0 * t_water),
    }
}

/// Beer's law: the fraction of light of each channel left after `distance` metres of water,
/// `exp(-0.5 σ d)` as the reference renderer takes it.
pub fn water_transmittance(distance: f64) -> DVec3 {
    DVec3::from(WATER_EXTINCTION.map(|sigma| (-0.5 * sigma * distance.max(0.0)).exp()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absorption_follows_the_two_modes() {
        assert_eq!(absorption_distance(WaterAbsorption::Cheap, 3.0, 0.5), 6.0);
        assert_eq!(absorption_distance(WaterAbsorption::Expensive, 3.0, 0.5), 3.5);
        assert_eq!(absorption_distance(WaterAbsorption::Expensive, 3.0, 10.0), 6.0);
        let t = water_transmittance(2.0);
        assert!((t.x - (-0.2f64).exp()).abs() < 1e-15 && t.z > t.y && t.y > t.x);
        assert_eq!(water_transmittance(0.0), DVec3::ONE);
    }
}
