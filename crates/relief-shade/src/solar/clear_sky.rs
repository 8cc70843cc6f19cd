//! The direct beam of a clear sky: the relative optical air mass of Kasten & Young (1989) and
//! Meinel & Meinel's (1976) transmittance of the clear atmosphere.

/// The total solar irradiance at the earth's mean distance from the sun, W/m^2 (Kopp & Lean
/// 2011, "A new, lower value of total solar irradiance", Geophysical Research Letters 38).
pub const SOLAR_CONSTANT_W_M2: f64 = 1361.0;

/// The relative optical air mass at apparent solar elevation `elevation_deg` (Kasten &
/// Young 1989, "Revised optical air mass tables and approximation formula", Applied Optics
/// 28(22), 4735-4738): `1 / (cos z + 0.50572 (96.07995 - z)^-1.6364)`, z the zenith angle
/// in degrees; 1 with the sun overhead, about 38 at the horizon. `None` when the sun is below
/// the horizon (elevation < 0).
pub fn relative_air_mass(elevation_deg: f64) -> Option<f64> {
    if !(0.0..=90.0).contains(&elevation_deg) {
        return None;
    }
    let zenith = 90.0 - elevation_deg;
    Some(1.0 / (zenith.to_radians().cos() + 0.50572 * (96.07995 - zenith).powf(-1.6364)))
}

/// The direct-beam (normal) irradiance of a clear sky in W/m^2 with the sun at apparent
/// elevation `elevation_deg`, by Meinel & Meinel's transmittance (A. B. Meinel and M. P.
/// Meinel 1976, "Applied Solar Energy: An Introduction", Addison-Wesley; the form used by
/// PVEducation and by Laue 1970 at sea level): `I = 1361 * 0.7^(AM^0.678)`, AM the
/// [`relative_air_mass`]: 0.7 of the light passes one air mass, and the exponent 0.678
/// accounts for the atmosphere's non-uniform layers. 0 when the sun is below the horizon,
/// about 1.0 kW/m^2 with the sun overhead.
///
/// ```
/// use relief_shade::solar::clear_sky_beam;
/// assert!((clear_sky_beam(90.0) - 1361.0 * 0.7).abs() < 0.5);
/// assert_eq!(clear_sky_beam(-0.1), 0.0);
/// ```
pub fn clear_sky_beam(elevation_deg: f64) -> f64 {
    match relative_air_mass(elevation_deg) {
        Some(air_mass) => SOLAR_CONSTANT_W_M2 * 0.7f64.powf(air_mass.powf(0.678)),
        None => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn air_mass_of_kasten_and_young() {
        // Their table: 1 overhead, 1.9942 at 60 degrees zenith, 37.92 at the horizon.
        assert!((relative_air_mass(90.0).unwrap() - 1.0).abs() < 1e-3);
        assert!((relative_air_mass(30.0).unwrap() - 1.9942).abs() < 2e-3);
        assert!((relative_air_mass(0.0).unwrap() - 37.92).abs() < 0.05);
        assert_eq!(relative_air_mass(-1.0), None);
        assert_eq!(relative_air_mass(f64::NAN), None);
    }

    #[test]
    fn the_beam_falls_with_the_sun() {
        // Meinel at air mass 1.5 (elevation 41.8 degrees): 1361 * 0.7^(1.5^0.678) = 902 W/m^2.
        let am15 = 90.0 - (1.0f64 / 1.5).acos().to_degrees();
        assert!((relative_air_mass(am15).unwrap() - 1.5).abs() < 0.01);
        assert!((clear_sky_beam(am15) - 1361.0 * 0.7f64.powf(1.5f64.powf(0.678))).abs() < 2.0);
        let mut previous = 0.0;
        for tenth in 0..=900 {
            let beam = clear_sky_beam(f64::from(tenth) / 10.0);
            assert!(beam >= previous && beam.is_finite(), "{tenth}: {beam}");
            previous = beam;
        }
        assert_eq!(clear_sky_beam(f64::NAN), 0.0);
    }
}
