//! Insolation over the horizon engine's angles: a wall south of a plain keeps its winter sun
//! from the samples behind it and not from those before it, and `solar::insolation` agrees
//! with the insolation layers of `shade_map` on a rough terrain.

use relief_core::{GridGeometry, HeightField, Surface};
use relief_shade::horizon::{horizon_map, HorizonParams};
use relief_shade::shade_map::{shade_map, ShadeLayer, ShadeMapParams};
use relief_shade::solar::{
    insolation, parse_date_range, sun_samples_over, Observer, SunSample, UtcOffset,
};
use relief_trace::{build_tracer, TracerKind};
use std::sync::Arc;

/// A `w x h` field of heights `f(col, row)`, cells `spacing` metres wide.
fn field(w: usize, h: usize, spacing: f64, f: impl Fn(usize, usize) -> f32) -> HeightField {
    let samples = (0..w * h).map(|i| f(i % w, i / w)).collect();
    HeightField::new(
        w,
        h,
        samples,
        GridGeometry { dx: spacing, dy: spacing, ..GridGeometry::unit() },
    )
    .unwrap()
}

/// The sun over `date` at 15-minute steps in Bern (UTC+1 in winter).
fn bern(date: &str) -> Vec<SunSample> {
    let days = parse_date_range(date).unwrap();
    let zone = UtcOffset::from_minutes(60).unwrap();
    sun_samples_over(days, zone, 900.0, &Observer::at(46.95, 7.45)).unwrap()
}

#[test]
fn a_wall_keeps_the_winter_sun_from_the_plain_behind_it() {
    // 60 x 60 cells of 10 m, flat but for an east-west wall 50 m high on rows 30 and 31.
    let plain = field(60, 60, 10.0, |_, row| if (30..=31).contains(&row) { 50.0 } else { 0.0 });
    let horizons = horizon_map(&plain, None, &HorizonParams::default(), &|_| {}).unwrap();
    let suns = bern("2026-12-21");
    let daylight: f64 = suns.iter().filter(|s| s.elevation_deg > 0.0).map(|s| s.hours).sum();
    assert!((8.0..9.0).contains(&daylight), "{daylight}");
    let result = insolation(&plain, None, &horizons, &suns).unwrap();
    // 90 m north of the wall, the sun (at most 19.6 degrees up) never clears it: the wall
    // rises atan(50 cos(phi) / 90) at phi from south, 29 degrees due south.
    let behind = 30 + 40 * 60;
    assert_eq!(result.sun_hours[behind], 0.0);
    assert_eq!(result.energy_wh_m2[behind], 0.0);
    // South of the wall the winter sun is in the open.
    let before = 30 + 20 * 60;
    assert!((f64::from(result.sun_hours[before]) - daylight).abs() < 1e-4);
    let flat_energy: f64 = suns
        .iter()
        .map(|s| s.beam_w_m2 * s.elevation_deg.to_radians().sin().max(0.0) * s.hours)
        .sum();
    assert!((f64::from(result.energy_wh_m2[before]) - flat_energy).abs() < 1e-3 * flat_energy);
    // At midsummer the sun (66 degrees at noon) clears the wall for the samples behind it.
    let summer = insolation(&plain, None, &horizons, &bern("2026-06-21")).unwrap();
    assert!(summer.sun_hours[behind] > 8.0, "{}", summer.sun_hours[behind]);
}

#[test]
fn insolation_agrees_with_the_shade_maps_layers() {
    let rough = field(48, 40, 5.0, |c, r| {
        let (x, y) = (c as f32, r as f32);
        30.0 * (x * 0.21).sin() * (y * 0.17).cos() + 12.0 * ((x + y) * 0.5).sin()
    });
    let mut void = vec![false; 48 * 40];
    void[48 * 12 + 7] = true;
    let suns = bern("2026-03-20..2026-03-21");
    let horizon = HorizonParams { azimuths: 16, ..HorizonParams::default() };
    let horizons = horizon_map(&rough, Some(&void), &horizon, &|_| {}).unwrap();
    let ours = insolation(&rough, Some(&void), &horizons, &suns).unwrap();

    // With openness asked for too, the shade map marches the true horizons, below the
    // horizontal included, as horizon_map does. (Without it, it marches horizons clamped at
    // the horizontal, and the horizon interpolated between a clamped direction and a rising
    // one stands higher: on this terrain sample 53 gets 9.25 hours instead of 9.75.)
    let params = ShadeMapParams {
        layers: vec![ShadeLayer::Insolation, ShadeLayer::SunHours, ShadeLayer::OpennessPos],
        horizon,
        insolation: suns.clone(),
        ..ShadeMapParams::default()
    };
    let shared = Arc::new(rough.clone());
    let tracer = build_tracer(shared, Surface::Triangles, TracerKind::Mipmap);
    let map = shade_map(&rough, &*tracer, Some(&void), &params, &|_| {}).unwrap();
    let (energy, hours) =
        (map.layer(ShadeLayer::Insolation).unwrap(), map.layer(ShadeLayer::SunHours).unwrap());
    let mut differing_hours = 0;
    for i in 0..48 * 40 {
        if void[i] {
            assert!(ours.energy_wh_m2[i].is_nan() && energy[i].is_nan(), "{i}");
            continue;
        }
        // The two compare the sun with the interpolated horizon in f32 and in f64: a sun
        // within rounding of a horizon may fall either way, a step of 15 minutes.
        let hour_gap = (ours.sun_hours[i] - hours[i]).abs();
        if hour_gap > 1e-4 {
            differing_hours += 1;
            assert!(hour_gap <= 0.25 + 1e-4, "{i}: {} vs {}", ours.sun_hours[i], hours[i]);
        } else {
            let scale = energy[i].abs().max(1.0);
            assert!((ours.energy_wh_m2[i] - energy[i]).abs() <= 1e-4 * scale, "{i}");
        }
    }
    assert!(differing_hours <= 2, "{differing_hours} samples differ");
    assert!(ours.sun_hours.iter().any(|&h| h > 0.0 && h < 20.0), "some shade, some sun");
}

#[test]
fn the_sun_s_layers_alone_equal_them_beside_the_sky() {
    // Alone, the shade map finds only the horizons beside the sun's path; beside the sky it
    // finds every direction's. The same bits either way.
    let rough = field(52, 44, 5.0, |c, r| {
        let (x, y) = (c as f32, r as f32);
        25.0 * (x * 0.23).sin() * (y * 0.19).cos() + 9.0 * ((x - y) * 0.4).sin()
    });
    let suns = bern("2026-12-21");
    let shared = Arc::new(rough.clone());
    let tracer = build_tracer(shared, Surface::Triangles, TracerKind::Mipmap);
    let layers_of = |layers: Vec<ShadeLayer>| {
        let params = ShadeMapParams {
            layers,
            horizon: HorizonParams { azimuths: 24, ..HorizonParams::default() },
            insolation: suns.clone(),
            ..ShadeMapParams::default()
        };
        let map = shade_map(&rough, &*tracer, None, &params, &|_| {}).unwrap();
        [ShadeLayer::Insolation, ShadeLayer::SunHours]
            .map(|l| map.layer(l).unwrap().iter().map(|v| v.to_bits()).collect::<Vec<_>>())
    };
    let alone = layers_of(vec![ShadeLayer::Insolation, ShadeLayer::SunHours]);
    let beside = layers_of(vec![ShadeLayer::Sky, ShadeLayer::Insolation, ShadeLayer::SunHours]);
    assert_eq!(alone, beside);
    assert!(alone[1].iter().any(|&h| f32::from_bits(h) > 0.0));
}
