//! Shade maps against ground truth: the shadow layer equals rays traced by an independent
//! brute-force tracer from the same surface points (property tests), the layers built on
//! horizons follow from the horizon engine's angles (itself checked against a brute force in
//! horizon_brute_force.rs), and analytic scenes (a flat plane, a slope, a pit, a wall half
//! hiding a soft sun) have the values their geometry gives.

#[path = "../../relief-trace/tests/common/reference.rs"]
#[allow(dead_code)]
mod reference;
#[path = "../../relief-trace/tests/common/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use proptest::prelude::*;
use relief_core::{DVec3, GridGeometry, HeightField, Surface};
use relief_shade::horizon::{horizon_map, HorizonParams};
use relief_shade::shade_map::{
    disc_directions, openness_deg, shade_map, sky_view_factor, surface_ray, InsolationSun,
    ShadeLayer, ShadeMapParams, SunPosition, SKY_SHARE,
};
use relief_trace::{build_tracer, TracerKind};
use std::sync::Arc;

/// The fraction of `directions` in which the brute-force tracer sees nothing from the sample.
fn brute_force_seen(
    field: &HeightField,
    surface: Surface,
    col: usize,
    row: usize,
    directions: &[DVec3],
) -> f32 {
    let seen = directions
        .iter()
        .filter(|&&d| {
            reference::first_hit(field, surface, &surface_ray(field, col, row, d)).is_none()
        })
        .count();
    seen as f32 / directions.len() as f32
}

/// Whether (`col`, `row`) lies on the grid's border.
fn on_border(field: &HeightField, col: usize, row: usize) -> bool {
    col == 0 || row == 0 || col + 1 == field.width() || row + 1 == field.height()
}

/// Whether a hole is among the 8 neighbours of (`col`, `row`).
fn next_to_a_hole(field: &HeightField, col: usize, row: usize) -> bool {
    (0..9).any(|k| {
        let (c, r) = ((col + k % 3).wrapping_sub(1), (row + k / 3).wrapping_sub(1));
        c < field.width() && r < field.height() && field.is_hole(c, r)
    })
}

fn map(field: HeightField, surface: Surface, params: &ShadeMapParams) -> relief_shade::ShadeMap {
    let field = Arc::new(field);
    let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
    shade_map(&field, &*tracer, None, params, &|_| {}).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn the_shadow_layer_equals_brute_force_rays(
        field in scenes::terrain(),
        quadrant in 0..4u32,
        azimuth in 0.5f64..89.5,
        elevation in 1.0f64..89.0,
        sun_radius in prop_oneof![Just(0.0f64), 0.5f64..8.0],
        picks in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0), 24),
    ) {
        let field = Arc::new(field);
        let params = ShadeMapParams {
            layers: vec![ShadeLayer::Shadow],
            suns: vec![SunPosition { azimuth_deg: azimuth + 90.0 * quadrant as f64, elevation_deg: elevation }],
            sun_radius_deg: sun_radius,
            sun_rays: 5,
            ..ShadeMapParams::default()
        };
        let sun_dirs = disc_directions(params.suns[0].direction(), sun_radius, 5);
        for surface in Surface::ALL {
            for kind in TracerKind::ALL {
                let tracer = build_tracer(field.clone(), surface, kind);
                let map = shade_map(&field, &*tracer, None, &params, &|_| {}).unwrap();
                let shadow = map.layer(ShadeLayer::Shadow).unwrap();
                for &(u, v) in &picks {
                    let col = ((u * field.width() as f64) as usize).min(field.width() - 1);
                    let row = ((v * field.height() as f64) as usize).min(field.height() - 1);
                    let index = col + row * field.width();
                    if field.is_hole(col, row) {
                        prop_assert!(shadow[index].is_nan());
                        continue;
                    }
                    if on_border(&field, col, row) || next_to_a_hole(&field, col, row) {
                        // Its rays that leave the surface at once, over the grid's border or a
                        // hole's rim, pass the solid's wall within a few lifts of its top
                        // edge: grazing ties, where either answer is exact.
                        continue;
                    }
                    let expected_shadow = brute_force_seen(&field, surface, col, row, &sun_dirs);
                    prop_assert_eq!(shadow[index], expected_shadow,
                        "{} {} shadow at ({}, {})", surface, kind, col, row);
                }
            }
        }
    }
}

/// A `w` x `h` field of `height(col, row)` with cells `dx` wide.
fn field_of(w: usize, h: usize, dx: f64, height: impl Fn(f64, f64) -> f64) -> HeightField {
    let samples =
        (0..w * h).map(|k| height((k % w) as f64 * dx, (k / w) as f64 * dx) as f32).collect();
    HeightField::new(w, h, samples, GridGeometry { dx, dy: dx, ..GridGeometry::unit() }).unwrap()
}

/// One hour of sun from the south-west, 40 degrees up, at 800 W/m².
const AFTERNOON: InsolationSun =
    InsolationSun { azimuth_deg: 225.0, elevation_deg: 40.0, hours: 1.0, beam_w_m2: 800.0 };

fn all_layers(azimuths: u32) -> ShadeMapParams {
    ShadeMapParams {
        layers: ShadeLayer::ALL.to_vec(),
        suns: vec![SunPosition { azimuth_deg: 200.0, elevation_deg: 35.0 }],
        horizon: HorizonParams { azimuths, ..HorizonParams::default() },
        insolation: vec![AFTERNOON],
        ..ShadeMapParams::default()
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// The sky-view factor and openness layers are their formulas over the horizon engine's
    /// angles, sample by sample.
    #[test]
    fn horizon_layers_follow_from_the_horizons(field in scenes::terrain(), azimuths in 1u32..20) {
        let params = ShadeMapParams {
            layers: vec![ShadeLayer::Horizon, ShadeLayer::Sky, ShadeLayer::OpennessPos],
            horizon: HorizonParams { azimuths, ..HorizonParams::default() },
            ..ShadeMapParams::default()
        };
        let map = map(field.clone(), Surface::Triangles, &params);
        let horizons = horizon_map(&field, None, &params.horizon, &|_| {}).unwrap();
        let bands: Vec<_> = map.layer_bands(ShadeLayer::Horizon).collect();
        prop_assert_eq!(bands.len(), azimuths as usize);
        for k in 0..field.width() * field.height() {
            let angles = || horizons.angles.iter().map(move |a| a[k] as f64);
            for (band, angle) in bands.iter().zip(angles()) {
                prop_assert!(band.values[k].is_nan() && angle.is_nan()
                    || band.values[k] == angle.to_degrees() as f32);
            }
            let sky = map.layer(ShadeLayer::Sky).unwrap()[k];
            let openness = map.layer(ShadeLayer::OpennessPos).unwrap()[k];
            if field.is_hole(k % field.width(), k / field.width()) {
                prop_assert!(sky.is_nan() && openness.is_nan());
            } else {
                prop_assert_eq!(sky, sky_view_factor(angles()) as f32);
                prop_assert_eq!(openness, openness_deg(angles()) as f32);
            }
        }
    }
}

#[test]
fn a_flat_plane_sees_the_whole_sky_and_the_sun() {
    for surface in Surface::ALL {
        let map = map(field_of(20, 12, 30.0, |_, _| 412.0), surface, &all_layers(16));
        let lambert = 35f64.to_radians().sin();
        // The observer, 1 cm up, sees the plane's edge at least 30 m away just below the
        // horizontal: within 0.02 degrees.
        for band in &map.bands {
            let (expected, tolerance) = match band.layer {
                ShadeLayer::Shadow
                | ShadeLayer::Sky
                | ShadeLayer::SkyAniso
                | ShadeLayer::SkyIllumination => (1.0, 1e-6),
                ShadeLayer::Hillshade => (lambert, 1e-6),
                ShadeLayer::HillshadeMulti => (45f64.to_radians().sin(), 1e-6),
                ShadeLayer::Combined => ((1.0 - SKY_SHARE) * lambert + SKY_SHARE, 1e-6),
                ShadeLayer::Horizon => (0.0, 0.02),
                ShadeLayer::OpennessPos | ShadeLayer::OpennessNeg => (90.0, 0.02),
                ShadeLayer::Insolation => (800.0 * 40f64.to_radians().sin(), 1e-3),
                ShadeLayer::SunHours => (1.0, 0.0),
            };
            for &v in &band.values {
                assert!(
                    (v as f64 - expected).abs() <= tolerance,
                    "{surface} {}: {v} vs {expected}",
                    band.name
                );
            }
        }
        assert_eq!(map.bands.len(), ShadeLayer::ALL.len() - 1 + 16);
        // One sun ray a sample.
        assert_eq!(map.rays, 20 * 12);
    }
}

#[test]
fn a_slope_sees_one_minus_its_angle_over_pi_of_the_sky() {
    // A plane rising towards the north-east at slope s: the sky above the horizontal plane but
    // below the slope's plane is a lune of 2s steradians, so the sky-view factor is 1 - s/π
    // (up to the sum over n directions standing for the integral over the compass).
    let n = 256;
    for slope_deg in [10.0f64, 30.0, 60.0] {
        let grade = slope_deg.to_radians().tan() / 2f64.sqrt();
        let field = field_of(24, 24, 5.0, |x, y| 100.0 + grade * (x + y));
        // The observer on the surface itself (its 1 cm would lower the horizons near the edges).
        let mut params = all_layers(n);
        params.horizon.observer_height = 0.0;
        let map = map(field, Surface::Triangles, &params);
        let sky = map.layer(ShadeLayer::Sky).unwrap();
        let expected = 1.0 - slope_deg.to_radians() / std::f64::consts::PI;
        // Off the borders, where some directions have no surface ahead.
        for row in 1..23 {
            for col in 1..23 {
                let v = sky[col + row * 24] as f64;
                assert!(
                    (v - expected).abs() <= 1e-4,
                    "{slope_deg}° at ({col}, {row}): {v} vs {expected}"
                );
            }
        }
        // Its openness is 90 degrees off the edges (as much up one way as down the other);
        // its multidirectional hillshade is the same everywhere inside.
        let openness = map.layer(ShadeLayer::OpennessPos).unwrap();
        let multi = map.layer(ShadeLayer::HillshadeMulti).unwrap();
        for row in 1..23 {
            for col in 1..23 {
                let k = col + row * 24;
                assert!((openness[k] - 90.0).abs() < 0.5, "{slope_deg}°: openness {}", openness[k]);
                assert!((multi[k] - multi[25]).abs() < 1e-6);
            }
        }
    }
}

#[test]
fn a_pit_floor_sees_one_minus_the_sine_of_its_horizon() {
    // A round pit 60 cells across with walls 40 m high: from the floor's centre, the rim's top
    // (the wall samples next to the floor) is between 29.5 and 31 cells away all round.
    let (cell, depth, radius) = (1.0, 40.0, 30.0);
    let size = 81;
    let centre = 40.0 * cell;
    let field = field_of(size, size, cell, |x, y| {
        let r = ((x - centre).powi(2) + (y - centre).powi(2)).sqrt() / cell;
        if r < radius - 0.5 {
            0.0
        } else {
            depth
        }
    });
    let map = map(field, Surface::Triangles, &all_layers(64));
    let sky = map.layer(ShadeLayer::Sky).unwrap()[40 + 40 * size] as f64;
    let low = (depth / ((radius + 1.0) * cell)).atan().sin();
    let high = (depth / ((radius - 0.5) * cell)).atan().sin();
    let tolerance = 1e-6;
    assert!(
        sky >= 1.0 - high - tolerance && sky <= 1.0 - low + tolerance,
        "{sky} not within [{}, {}]",
        1.0 - high,
        1.0 - low
    );
}

#[test]
fn a_wall_hides_half_of_a_sun_centred_on_its_edge() {
    // The north half of the grid stands 40 m high; a sample 20 rows south of the wall's top
    // row sees the sun in the north at exactly the elevation of the wall's edge: half its disc.
    let cell = 2.0;
    let (wall_row, sample_row) = (40usize, 20usize);
    let field = field_of(64, 64, cell, |_, y| if y >= wall_row as f64 * cell { 40.0 } else { 0.0 });
    let distance = (wall_row - sample_row) as f64 * cell;
    let edge = (40.0f64 / distance).atan().to_degrees();
    let sun = |radius: f64| ShadeMapParams {
        layers: vec![ShadeLayer::Shadow],
        suns: vec![SunPosition { azimuth_deg: 0.0, elevation_deg: edge }],
        sun_radius_deg: radius,
        sun_rays: 256,
        ..ShadeMapParams::default()
    };
    let shadow = map(field.clone(), Surface::Triangles, &sun(3.0));
    let half = shadow.layer(ShadeLayer::Shadow).unwrap()[32 + sample_row * 64];
    assert!((half - 0.5).abs() < 0.05, "{half}");
    // Raised above the edge by more than its radius, the sun is whole; lowered, it is hidden.
    let whole = ShadeMapParams {
        suns: vec![SunPosition { azimuth_deg: 0.0, elevation_deg: edge + 4.0 }],
        ..sun(3.0)
    };
    let hidden = ShadeMapParams {
        suns: vec![SunPosition { azimuth_deg: 0.0, elevation_deg: edge - 4.0 }],
        ..sun(3.0)
    };
    let at = |params: &ShadeMapParams| {
        map(field.clone(), Surface::Triangles, params).layer(ShadeLayer::Shadow).unwrap()
            [32 + sample_row * 64]
    };
    assert_eq!(at(&whole), 1.0);
    assert_eq!(at(&hidden), 0.0);
}

#[test]
fn voids_are_nan_in_every_layer() {
    let field = Arc::new(field_of(16, 16, 1.0, |x, y| (x * 0.3).sin() * 3.0 + y * 0.1));
    let mut void = vec![false; 256];
    for k in [0, 17, 100, 255] {
        void[k] = true;
    }
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    let map = shade_map(&field, &*tracer, Some(&void), &all_layers(16), &|_| {}).unwrap();
    for band in &map.bands {
        for (k, v) in band.values.iter().enumerate() {
            assert_eq!(v.is_nan(), void[k], "{} at {k}", band.name);
            if band.layer.unit() == "0 to 1" {
                assert!(v.is_nan() || (0.0..=1.0).contains(v), "{} at {k}: {v}", band.name);
            }
        }
    }
    let short = shade_map(&field, &*tracer, Some(&void[1..]), &all_layers(16), &|_| {});
    assert!(short.unwrap_err().to_string().contains("void mask of 255 samples"));
}

#[test]
fn the_map_is_the_same_whatever_the_thread_count() {
    let field =
        Arc::new(field_of(70, 45, 3.0, |x, y| (x * 0.05).sin() * 20.0 + (y * 0.08).cos() * 15.0));
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    let params = ShadeMapParams { sun_radius_deg: 1.0, ..all_layers(12) };
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| shade_map(&field, &*tracer, None, &params, &|_| {}).unwrap())
    };
    let one = run(1);
    let two = run(2);
    assert_eq!(one, two);
    // Not trivially uniform: this terrain shadows part of itself.
    let shadow = one.layer(ShadeLayer::Shadow).unwrap();
    assert!(shadow.iter().any(|&v| v < 0.5) && shadow.contains(&1.0));
}
