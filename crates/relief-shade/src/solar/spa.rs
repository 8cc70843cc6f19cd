//! NREL's Solar Position Algorithm (Reda & Andreas 2004, "Solar position algorithm for solar
//! radiation applications", NREL/TP-560-34302): the sun's topocentric azimuth and elevation
//! for an observer on the earth at an instant, to 0.0003 degrees from -2000 to 6000.

use super::civil_time::UtcInstant;
use super::spa_terms::{B0, B1, L0, L1, L2, L3, L4, L5, NUTATION, R0, R1, R2, R3, R4};
use crate::ShadeError;

/// Air pressure in millibars unless given (the standard atmosphere at sea level).
pub const DEFAULT_PRESSURE_MBAR: f64 = 1013.25;

/// Air temperature in degrees Celsius unless given (pvlib's default yearly mean).
pub const DEFAULT_TEMPERATURE_C: f64 = 12.0;

/// TT - UT1 in seconds unless given (pvlib's default).
pub const DEFAULT_DELTA_T_S: f64 = 67.0;

/// The sun's radius (0.26667 degrees) plus the refraction at the horizon (0.5667 degrees):
/// below `-SUNRISE_DEPRESSION_DEG` the SPA applies no refraction.
const SUNRISE_DEPRESSION_DEG: f64 = 0.26667 + 0.5667;

/// Where the sun is observed from, and the air it is seen through.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observer {
    /// Geodetic latitude in degrees, north positive, in [-90, 90].
    pub latitude_deg: f64,
    /// Longitude in degrees, east positive, in [-180, 180].
    pub longitude_deg: f64,
    /// Height above the ellipsoid in metres.
    pub elevation_m: f64,
    /// Mean air pressure in millibars (for refraction).
    pub pressure_mbar: f64,
    /// Mean air temperature in degrees Celsius (for refraction).
    pub temperature_c: f64,
    /// TT - UT1 in seconds.
    pub delta_t_s: f64,
}

impl Observer {
    /// An observer at `latitude_deg`, `longitude_deg` at sea level, in the SPA's default air
    /// (1013.25 mbar, 12 C) and delta T of 67 s.
    pub fn at(latitude_deg: f64, longitude_deg: f64) -> Observer {
        Observer {
            latitude_deg,
            longitude_deg,
            elevation_m: 0.0,
            pressure_mbar: DEFAULT_PRESSURE_MBAR,
            temperature_c: DEFAULT_TEMPERATURE_C,
            delta_t_s: DEFAULT_DELTA_T_S,
        }
    }

    /// Checks every field, naming the one that is wrong.
    pub fn validate(&self) -> Result<(), ShadeError> {
        let finite_in = |name: &'static str, value: f64, low: f64, high: f64| {
            if value.is_finite() && (low..=high).contains(&value) {
                Ok(())
            } else {
                Err(ShadeError::parameter(name, format!("{value} is not in [{low}, {high}]")))
            }
        };
        finite_in("latitude", self.latitude_deg, -90.0, 90.0)?;
        finite_in("longitude", self.longitude_deg, -180.0, 180.0)?;
        // The SPA's own limits (its C implementation refuses outside them).
        finite_in("elevation", self.elevation_m, -6_500_000.0, f64::MAX)?;
        finite_in("pressure", self.pressure_mbar, 0.0, 5000.0)?;
        finite_in("temperature", self.temperature_c, -273.0, 6000.0)?;
        finite_in("delta T", self.delta_t_s, -8000.0, 8000.0)?;
        Ok(())
    }
}

/// The sun's place in the sky as an observer sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolarPosition {
    /// Topocentric azimuth in degrees clockwise from north, in [0, 360).
    pub azimuth_deg: f64,
    /// Topocentric elevation of the sun's centre above the horizon in degrees, without
    /// atmospheric refraction.
    pub elevation_deg: f64,
    /// The elevation as seen through the atmosphere (refraction added when the sun is not
    /// below the horizon by more than its radius plus the refraction there).
    pub apparent_elevation_deg: f64,
}

impl SolarPosition {
    /// The apparent zenith angle in degrees (90 minus the apparent elevation).
    pub fn apparent_zenith_deg(&self) -> f64 {
        90.0 - self.apparent_elevation_deg
    }
}

/// The sun's topocentric position seen by `observer` at `instant` (NREL's SPA, every step of
/// the paper: Julian days, the earth's heliocentric longitude, latitude and radius vector,
/// nutation, aberration, apparent sidereal time, topocentric parallax and refraction).
///
/// ```
/// use relief_shade::solar::{solar_position, Observer, UtcInstant};
/// // The paper's example: 2003-10-17 12:30:30 at UTC-7 in Golden, Colorado.
/// let instant = UtcInstant::from_unix_seconds(1_066_419_030.0);
/// let observer = Observer {
///     latitude_deg: 39.742476, longitude_deg: -105.1786, elevation_m: 1830.14,
///     pressure_mbar: 820.0, temperature_c: 11.0, delta_t_s: 67.0,
/// };
/// let sun = solar_position(instant, &observer).unwrap();
/// assert!((sun.apparent_zenith_deg() - 50.11162).abs() < 1e-5);
/// assert!((sun.azimuth_deg - 194.34024).abs() < 1e-5);
/// ```
pub fn solar_position(
    instant: UtcInstant,
    observer: &Observer,
) -> Result<SolarPosition, ShadeError> {
    observer.validate()?;
    let jd = instant.julian_day();
    if !jd.is_finite() {
        return Err(ShadeError::parameter("time", format!("{instant:?} is not a finite instant")));
    }
    Ok(position_at(jd, observer))
}

/// Every step of the SPA for Julian day `jd` (UT) and a checked observer.
fn position_at(jd: f64, observer: &Observer) -> SolarPosition {
    let jde = jd + observer.delta_t_s / 86400.0;
    let jc = (jd - 2451545.0) / 36525.0;
    let jce = (jde - 2451545.0) / 36525.0;
    let jme = jce / 10.0;

    // The earth's heliocentric coordinates, then the sun's geocentric ones.
    let earth_longitude = wrap_degrees(series(&[&L0, &L1, &L2, &L3, &L4, &L5], jme).to_degrees());
    let earth_latitude = series(&[&B0, &B1], jme).to_degrees();
    let radius_au = series(&[&R0, &R1, &R2, &R3, &R4], jme);
    let sun_longitude = wrap_degrees(earth_longitude + 180.0);
    let sun_latitude = -earth_latitude;

    let (nutation_longitude, nutation_obliquity) = nutation(jce);
    let obliquity = mean_obliquity_arcsec(jme / 10.0) / 3600.0 + nutation_obliquity;
    let aberration = -20.4898 / (3600.0 * radius_au);
    let apparent_longitude = sun_longitude + nutation_longitude + aberration;

    let mean_sidereal = wrap_degrees(
        280.46061837 + 360.98564736629 * (jd - 2451545.0) + 0.000387933 * jc * jc
            - jc * jc * jc / 38_710_000.0,
    );
    let sidereal = mean_sidereal + nutation_longitude * obliquity.to_radians().cos();

    let (lambda, epsilon, beta) =
        (apparent_longitude.to_radians(), obliquity.to_radians(), sun_latitude.to_radians());
    let right_ascension = wrap_degrees(
        (lambda.sin() * epsilon.cos() - beta.tan() * epsilon.sin())
            .atan2(lambda.cos())
            .to_degrees(),
    );
    let declination =
        (beta.sin() * epsilon.cos() + beta.cos() * epsilon.sin() * lambda.sin()).asin();
    let hour_angle = wrap_degrees(sidereal + observer.longitude_deg - right_ascension).to_radians();

    // Topocentric parallax.
    let latitude = observer.latitude_deg.to_radians();
    let parallax = (8.794 / (3600.0 * radius_au)).to_radians();
    let u = (0.99664719 * latitude.tan()).atan();
    let x = u.cos() + observer.elevation_m / 6_378_140.0 * latitude.cos();
    let y = 0.99664719 * u.sin() + observer.elevation_m / 6_378_140.0 * latitude.sin();
    let denominator = declination.cos() - x * parallax.sin() * hour_angle.cos();
    let delta_alpha = (-x * parallax.sin() * hour_angle.sin()).atan2(denominator);
    let topocentric_declination =
        ((declination.sin() - y * parallax.sin()) * delta_alpha.cos()).atan2(denominator);
    let topocentric_hour_angle = hour_angle - delta_alpha;

    let elevation = (latitude.sin() * topocentric_declination.sin()
        + latitude.cos() * topocentric_declination.cos() * topocentric_hour_angle.cos())
    .asin()
    .to_degrees();
    let apparent_elevation = elevation + refraction(elevation, observer);
    let astronomers_azimuth = topocentric_hour_angle.sin().atan2(
        topocentric_hour_angle.cos() * latitude.sin()
            - topocentric_declination.tan() * latitude.cos(),
    );
    SolarPosition {
        azimuth_deg: wrap_degrees(astronomers_azimuth.to_degrees() + 180.0),
        elevation_deg: elevation,
        apparent_elevation_deg: apparent_elevation,
    }
}

/// A VSOP87 series `(sum_i T_i(jme) jme^i) / 1e8` of the tables `orders`, each term
/// `A cos(B + C jme)`.
fn series(orders: &[&[[f64; 3]]], jme: f64) -> f64 {
    let mut total = 0.0;
    let mut power = 1.0;
    for terms in orders {
        let sum: f64 = terms.iter().map(|[a, b, c]| a * (b + c * jme).cos()).sum();
        total += sum * power;
        power *= jme;
    }
    total / 1e8
}

/// The nutation in longitude and in obliquity, in degrees, at Julian ephemeris century
/// `jce`.
fn nutation(jce: f64) -> (f64, f64) {
    let (t2, t3) = (jce * jce, jce * jce * jce);
    let arguments = [
        297.85036 + 445267.111480 * jce - 0.0019142 * t2 + t3 / 189474.0,
        357.52772 + 35999.050340 * jce - 0.0001603 * t2 - t3 / 300000.0,
        134.96298 + 477198.867398 * jce + 0.0086972 * t2 + t3 / 56250.0,
        93.27191 + 483202.017538 * jce - 0.0036825 * t2 + t3 / 327270.0,
        125.04452 - 1934.136261 * jce + 0.0020708 * t2 + t3 / 450000.0,
    ];
    let (mut longitude, mut obliquity) = (0.0, 0.0);
    for (multipliers, [a, b, c, d]) in &NUTATION {
        let angle: f64 = multipliers.iter().zip(&arguments).map(|(y, x)| y * x).sum();
        let angle = angle.to_radians();
        longitude += (a + b * jce) * angle.sin();
        obliquity += (c + d * jce) * angle.cos();
    }
    (longitude / 36_000_000.0, obliquity / 36_000_000.0)
}

/// The mean obliquity of the ecliptic in arc seconds, `u` in units of 10000 Julian years
/// from J2000.
fn mean_obliquity_arcsec(u: f64) -> f64 {
    const COEFFICIENTS: [f64; 11] =
        [84381.448, -4680.93, -1.55, 1999.25, -51.38, -249.67, -39.05, 7.12, 27.87, 5.79, 2.45];
    COEFFICIENTS.iter().rev().fold(0.0, |acc, c| acc * u + c)
}

/// The atmospheric refraction in degrees at true elevation `elevation_deg` (Bennett's
/// formula as the SPA takes it), 0 when the sun is well below the horizon.
fn refraction(elevation_deg: f64, observer: &Observer) -> f64 {
    if elevation_deg < -SUNRISE_DEPRESSION_DEG {
        return 0.0;
    }
    (observer.pressure_mbar / 1010.0) * (283.0 / (273.0 + observer.temperature_c)) * 1.02
        / (60.0 * (elevation_deg + 10.3 / (elevation_deg + 5.11)).to_radians().tan())
}

/// `degrees` wrapped to [0, 360).
fn wrap_degrees(degrees: f64) -> f64 {
    let wrapped = degrees.rem_euclid(360.0);
    // rem_euclid of a tiny negative number may round to 360 itself.
    if wrapped >= 360.0 {
        0.0
    } else {
        wrapped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The observer of the paper's worked example (Golden, Colorado).
    fn golden() -> Observer {
        Observer {
            latitude_deg: 39.742476,
            longitude_deg: -105.1786,
            elevation_m: 1830.14,
            pressure_mbar: 820.0,
            temperature_c: 11.0,
            delta_t_s: 67.0,
        }
    }

    /// 2003-10-17 12:30:30 at UTC-7: 19:30:30 UTC.
    fn example_instant() -> UtcInstant {
        UtcInstant::from_civil_text("2003-10-17", "12:30:30", "-07:00").unwrap()
    }

    #[test]
    fn the_papers_worked_example() {
        let instant = example_instant();
        // The paper's intermediate results (table A5.1).
        let jd = instant.julian_day();
        assert!((jd - 2452930.312847).abs() < 1e-6, "{jd}");
        let sun = solar_position(instant, &golden()).unwrap();
        assert!((sun.apparent_zenith_deg() - 50.11162).abs() < 1e-5, "{sun:?}");
        assert!((sun.azimuth_deg - 194.34024).abs() < 1e-5, "{sun:?}");
        // The topocentric elevation without refraction: 90 - 50.11162 less the refraction
        // of the paper's example (0.016332 degrees).
        assert!((sun.elevation_deg - (90.0 - 50.11162 - 0.016332)).abs() < 1e-5, "{sun:?}");
    }

    #[test]
    fn the_papers_intermediate_values() {
        let instant = example_instant();
        let jde = instant.julian_day() + 67.0 / 86400.0;
        let jme = (jde - 2451545.0) / 365250.0;
        let l = wrap_degrees(series(&[&L0, &L1, &L2, &L3, &L4, &L5], jme).to_degrees());
        let b = series(&[&B0, &B1], jme).to_degrees();
        let r = series(&[&R0, &R1, &R2, &R3, &R4], jme);
        assert!((l - 24.0182616917).abs() < 1e-6, "L {l}");
        assert!((b - -0.0001011219).abs() < 1e-8, "B {b}");
        assert!((r - 0.9965422974).abs() < 1e-9, "R {r}");
        let (dpsi, deps) = nutation(jme * 10.0);
        assert!((dpsi - -0.00399840).abs() < 1e-8, "delta psi {dpsi}");
        assert!((deps - 0.00166657).abs() < 1e-8, "delta epsilon {deps}");
        let epsilon = mean_obliquity_arcsec(jme / 10.0) / 3600.0 + deps;
        assert!((epsilon - 23.440465).abs() < 1e-6, "epsilon {epsilon}");
    }

    #[test]
    fn no_refraction_far_below_the_horizon() {
        let observer = golden();
        assert_eq!(refraction(-5.0, &observer), 0.0);
        assert!(refraction(0.0, &observer) > 0.3);
        // 2003-10-17 07:00 UTC is midnight in Colorado: the sun is far below.
        let night = UtcInstant::from_civil_text("2003-10-17", "07:00", "Z").unwrap();
        let sun = solar_position(night, &observer).unwrap();
        assert!(sun.elevation_deg < -30.0);
        assert_eq!(sun.elevation_deg, sun.apparent_elevation_deg);
    }

    #[test]
    fn bad_observers_are_refused_by_name() {
        let instant = example_instant();
        for (observer, name) in [
            (Observer { latitude_deg: 91.0, ..golden() }, "latitude"),
            (Observer { longitude_deg: f64::NAN, ..golden() }, "longitude"),
            (Observer { pressure_mbar: -1.0, ..golden() }, "pressure"),
            (Observer { temperature_c: -300.0, ..golden() }, "temperature"),
            (Observer { delta_t_s: 1e5, ..golden() }, "delta T"),
        ] {
            let error = solar_position(instant, &observer).unwrap_err();
            assert!(error.to_string().contains(name), "{error}");
        }
        let never = UtcInstant::from_unix_seconds(f64::INFINITY);
        assert!(solar_position(never, &golden()).is_err());
    }

    #[test]
    fn angles_wrap_into_one_turn() {
        assert_eq!(wrap_degrees(-1e-20), 0.0);
        assert_eq!(wrap_degrees(370.0), 10.0);
        assert_eq!(wrap_degrees(-90.0), 270.0);
    }
}
