//! Insolation on analytic cases: an open flat plane over a day equals its closed form, a
//! sample under a horizon above the sun gets nothing, an infinite slope gets the cosine of
//! its tilt, and the sun's place between the map's directions is the one
//! `HorizonMap::angle_towards` gives.

use relief_core::{GridGeometry, HeightField};
use relief_shade::horizon::HorizonMap;
use relief_shade::solar::{
    insolation, parse_date_range, sun_samples_over, Observer, SunSample, UtcOffset,
};
use relief_shade::ShadeError;

/// A horizon map of `directions` evenly spaced directions, every angle `angle` (radians).
fn uniform_horizons(width: usize, height: usize, directions: usize, angle: f32) -> HorizonMap {
    HorizonMap {
        width,
        height,
        azimuths_deg: (0..directions).map(|k| k as f64 * 360.0 / directions as f64).collect(),
        angles: vec![vec![angle; width * height]; directions],
    }
}

/// A `width x height` field of heights `f(col, row)` at spacing `spacing`.
fn field(
    width: usize,
    height: usize,
    spacing: f64,
    f: impl Fn(usize, usize) -> f32,
) -> HeightField {
    let samples = (0..width * height).map(|i| f(i % width, i / width)).collect();
    let geometry = GridGeometry { dx: spacing, dy: spacing, ..GridGeometry::unit() };
    HeightField::new(width, height, samples, geometry).unwrap()
}

/// The sun over 2026-06-21 at 15-minute steps in Bern.
fn bern_midsummer() -> Vec<SunSample> {
    let day = parse_date_range("2026-06-21").unwrap();
    let zone = UtcOffset::from_minutes(120).unwrap();
    sun_samples_over(day, zone, 900.0, &Observer::at(46.95, 7.45)).unwrap()
}

#[test]
fn an_open_flat_plane_equals_the_closed_form() {
    let plane = field(6, 5, 10.0, |_, _| 100.0);
    let suns = bern_midsummer();
    let result = insolation(&plane, None, &uniform_horizons(6, 5, 32, 0.0), &suns).unwrap();
    let daylight: f64 = suns.iter().filter(|s| s.elevation_deg > 0.0).map(|s| s.hours).sum();
    let energy: f64 = suns
        .iter()
        .map(|s| s.beam_w_m2 * s.elevation_deg.to_radians().sin().max(0.0) * s.hours)
        .sum();
    // Midsummer in Bern: about 16 hours of sun and some 8 kWh/m^2 of clear-sky beam.
    assert!((15.5..17.0).contains(&daylight), "{daylight}");
    assert!((6000.0..10000.0).contains(&energy), "{energy}");
    for i in 0..30 {
        assert!((f64::from(result.sun_hours[i]) - daylight).abs() < 1e-4, "{i}");
        assert!((f64::from(result.energy_wh_m2[i]) - energy).abs() < 1e-3 * energy, "{i}");
    }
}

#[test]
fn a_sample_under_a_horizon_above_the_sun_gets_nothing() {
    let plane = field(5, 5, 1.0, |_, _| 0.0);
    let mut horizons = uniform_horizons(5, 5, 16, 0.0);
    // Sample (2, 2) sits at the bottom of a well 80 degrees deep in every direction.
    for angles in &mut horizons.angles {
        angles[12] = 80f32.to_radians();
    }
    let suns = bern_midsummer();
    let result = insolation(&plane, None, &horizons, &suns).unwrap();
    assert_eq!(result.sun_hours[12], 0.0);
    assert_eq!(result.energy_wh_m2[12], 0.0);
    assert!(result.sun_hours[11] > 15.0 && result.energy_wh_m2[13] > 6000.0);
    // A horizon only to the south: shaded around noon, lit in the morning and evening.
    let mut south_wall = uniform_horizons(5, 5, 16, 0.0);
    for (k, angles) in south_wall.angles.iter_mut().enumerate() {
        let azimuth = k as f64 * 22.5;
        if (135.0..=225.0).contains(&azimuth) {
            angles[12] = 85f32.to_radians();
        }
    }
    let walled = insolation(&plane, None, &south_wall, &suns).unwrap();
    let daylight_outside = |low: f64, high: f64| -> f64 {
        suns.iter()
            .filter(|s| s.elevation_deg > 0.0 && !(low..=high).contains(&s.azimuth_deg))
            .map(|s| s.hours)
            .sum()
    };
    // Shaded for certain between 135 and 225 degrees (the wall's directions), lit for certain
    // outside 112.5 to 247.5 (where both neighbouring directions are open).
    let lit = f64::from(walled.sun_hours[12]);
    assert!(lit <= daylight_outside(135.0, 225.0) + 1e-4, "{lit}");
    assert!(lit >= daylight_outside(112.5, 247.5) - 1e-4, "{lit}");
    assert!(lit > 4.0 && lit < f64::from(result.sun_hours[11]) - 2.0, "{lit}");
}

#[test]
fn an_infinite_slope_gets_the_cosine_of_its_tilt() {
    // A plane rising 0.5 m per metre to the north: it faces south, tilted atan(0.5).
    let slope = field(7, 7, 2.0, |_, row| row as f32);
    let tilt = 0.5f64.atan();
    let normal = [0.0, -tilt.sin(), tilt.cos()];
    let suns = bern_midsummer();
    let result = insolation(&slope, None, &uniform_horizons(7, 7, 32, -1.5), &suns).unwrap();
    let expected: f64 = suns
        .iter()
        .map(|s| {
            let (az, el) = (s.azimuth_deg.to_radians(), s.elevation_deg.to_radians());
            let towards = [az.sin() * el.cos(), az.cos() * el.cos(), el.sin()];
            let cosine: f64 = normal.iter().zip(towards).map(|(n, s)| n * s).sum();
            s.beam_w_m2 * cosine.max(0.0) * s.hours
        })
        .sum();
    // Interior samples: Horn's gradient of a plane is exact.
    for row in 1..6 {
        for col in 1..6 {
            let got = f64::from(result.energy_wh_m2[col + 7 * row]);
            assert!((got - expected).abs() < 1e-3 * expected, "({col}, {row}): {got} {expected}");
        }
    }
    // Below a horizon of -1.5 rad the sun still counts only above the horizontal: night is
    // night.
    let daylight: f64 = suns.iter().filter(|s| s.elevation_deg > 0.0).map(|s| s.hours).sum();
    assert!((f64::from(result.sun_hours[24]) - daylight).abs() < 1e-4);
    assert!(daylight < 17.0);
}

#[test]
fn the_sun_between_two_directions_is_where_angle_towards_puts_it_above_the_horizontal() {
    let (width, height) = (9, 7);
    let plane = field(width, height, 1.0, |_, _| 0.0);
    let mut horizons = uniform_horizons(width, height, 8, 0.0);
    // Pseudo-random angles from -0.3 to 0.9 rad.
    let mut state = 0x2545_f491_u64;
    for angles in &mut horizons.angles {
        for angle in angles.iter_mut() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            *angle = -0.3 + 1.2 * ((state >> 40) as f32 / (1u64 << 24) as f32);
        }
    }
    // The sun counts above the horizons clamped at the horizontal in each direction, then
    // interpolated between the two it lies between.
    let mut clamped = horizons.clone();
    for angles in &mut clamped.angles {
        for angle in angles.iter_mut() {
            *angle = angle.max(0.0);
        }
    }
    for azimuth_deg in [0.0, 10.0, 44.9, 45.0, 200.0, 359.9, -30.0, 725.0] {
        for elevation_deg in [-10.0, 5.0, 20.0, 35.0, 50.0] {
            let sun = SunSample { azimuth_deg, elevation_deg, hours: 0.5, beam_w_m2: 1000.0 };
            let result = insolation(&plane, None, &horizons, &[sun]).unwrap();
            for i in 0..width * height {
                // Above the horizontal and the horizon: at -10 degrees, under horizons
                // down to -17 degrees, nothing is lit.
                let lit = elevation_deg > 0.0
                    && elevation_deg.to_radians() as f32 > clamped.angle_towards(i, azimuth_deg);
                let expected = if lit { 0.5 } else { 0.0 };
                assert_eq!(result.sun_hours[i], expected, "{azimuth_deg} {elevation_deg} {i}");
            }
        }
    }
}

#[test]
fn voids_are_nan_and_threads_change_nothing() {
    let hills = field(40, 30, 5.0, |c, r| ((c as f32 * 0.3).sin() + (r as f32 * 0.2).cos()) * 20.0);
    let mut void = vec![false; 1200];
    void[17] = true;
    void[611] = true;
    let mut horizons = uniform_horizons(40, 30, 16, 0.1);
    for (k, angles) in horizons.angles.iter_mut().enumerate() {
        for (i, angle) in angles.iter_mut().enumerate() {
            *angle = ((i * 7 + k * 13) % 23) as f32 * 0.02 - 0.1;
        }
    }
    let suns = bern_midsummer();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| insolation(&hills, Some(&void), &horizons, &suns).unwrap())
    };
    let one = run(1);
    assert!(one.sun_hours[17].is_nan() && one.energy_wh_m2[611].is_nan());
    assert!(one.sun_hours[18].is_finite() && one.energy_wh_m2[18] > 0.0);
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let three = run(3);
    assert_eq!(bits(&one.sun_hours), bits(&three.sun_hours));
    assert_eq!(bits(&one.energy_wh_m2), bits(&three.energy_wh_m2));
}

#[test]
fn mismatched_maps_and_bad_suns_are_refused() {
    let plane = field(4, 4, 1.0, |_, _| 0.0);
    let sun = SunSample { azimuth_deg: 180.0, elevation_deg: 30.0, hours: 1.0, beam_w_m2: 900.0 };
    let small = uniform_horizons(4, 3, 8, 0.0);
    let error = insolation(&plane, None, &small, &[sun]).unwrap_err();
    assert!(matches!(error, ShadeError::Mismatch(_)), "{error}");
    let mut short = uniform_horizons(4, 4, 8, 0.0);
    short.angles[3].pop();
    assert!(matches!(insolation(&plane, None, &short, &[sun]), Err(ShadeError::Mismatch(_))));
    let none = HorizonMap { width: 4, height: 4, azimuths_deg: vec![], angles: vec![] };
    assert!(matches!(insolation(&plane, None, &none, &[sun]), Err(ShadeError::Mismatch(_))));
    let open = uniform_horizons(4, 4, 8, 0.0);
    assert!(insolation(&plane, Some(&[false; 3]), &open, &[sun]).is_err());
    for bad in [
        SunSample { hours: -1.0, ..sun },
        SunSample { beam_w_m2: f64::NAN, ..sun },
        SunSample { elevation_deg: 91.0, ..sun },
        SunSample { azimuth_deg: f64::INFINITY, ..sun },
    ] {
        let error = insolation(&plane, None, &open, &[sun, bad]).unwrap_err();
        assert!(error.to_string().contains("number 1"), "{error}");
    }
    // No suns: nothing anywhere.
    let dark = insolation(&plane, None, &open, &[]).unwrap();
    assert!(dark.sun_hours.iter().chain(&dark.energy_wh_m2).all(|&v| v == 0.0));
}
