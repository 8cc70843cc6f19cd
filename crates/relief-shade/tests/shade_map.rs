//! Shade maps against ground truth: the shadow and sky layers equal rays traced by an
//! independent brute-force tracer from the same surface points (property tests), and analytic
//! scenes (a flat plane, a slope, a pit, a wall half hiding a soft sun) have the values their
//! geometry gives.

#[path = "../../relief-trace/tests/common/reference.rs"]
#[allow(dead_code)]
mod reference;
#[path = "../../relief-trace/tests/common/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use proptest::prelude::*;
use relief_core::{DVec3, GridGeometry, HeightField, Surface};
use relief_shade::shade_map::{
    disc_directions, shade_map, sky_directions, surface_ray, ShadeLayer, ShadeMapParams,
    SunPosition, SKY_SHARE,
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
    fn shadow_and_sky_layers_equal_brute_force_rays(
        field in scenes::terrain(),
        quadrant in 0..4u32,
        azimuth in 0.5f64..89.5,
        elevation in 1.0f64..89.0,
        sun_radius in prop_oneof![Just(0.0f64), 0.5f64..8.0],
        picks in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0), 24),
    ) {
        let field = Arc::new(field);
        let params = ShadeMapParams {
            layers: vec![ShadeLayer::Shadow, ShadeLayer::Sky],
            suns: vec![SunPosition { azimuth_deg: azimuth + 90.0 * quadrant as f64, elevation_deg: elevation }],
            sun_radius_deg: sun_radius,
            sun_rays: 5,
            sky_rays: 32,
        };
        let sun_dirs = disc_directions(params.suns[0].direction(), sun_radius, 5);
        let sky_dirs = sky_directions(32);
        for surface in Surface::ALL {
            for kind in TracerKind::ALL {
                let tracer = build_tracer(field.clone(), surface, kind);
                let map = shade_map(&field, &*tracer, None, &params, &|_| {}).unwrap();
                let (shadow, sky) =
                    (map.layer(ShadeLayer::Shadow).unwrap(), map.layer(ShadeLayer::Sky).unwrap());
                for &(u, v) in &picks {
                    let col = ((u * field.width() as f64) as usize).min(field.width() - 1);
                    let row = ((v * field.height() as f64) as usize).min(field.height() - 1);
                    let index = col + row * field.width();
                    if field.is_hole(col, row) {
                        prop_assert!(shadow[index].is_nan() && sky[index].is_nan());
                        continue;
                    }
                    if on_border(&field, col, row) || next_to_a_hole(&field, col, row) {
                        // Its rays that leave the surface at once, over the grid's border or a
                        // hole's rim, pass the solid's wall within a few lifts of its top
                        // edge: grazing ties, where either answer is exact.
                        continue;
                    }
                    let expected_shadow = brute_force_seen(&field, surface, col, row, &sun_dirs);
                    let expected_sky = brute_force_seen(&field, surface, col, row, &sky_dirs);
                    prop_assert_eq!(shadow[index], expected_shadow,
                        "{} {} shadow at ({}, {})", surface, kind, col, row);
                    prop_assert_eq!(sky[index], expected_sky,
                        "{} {} sky at ({}, {})", surface, kind, col, row);
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

fn all_layers(sky_rays: u32) -> ShadeMapParams {
    ShadeMapParams {
        layers: ShadeLayer::ALL.to_vec(),
        suns: vec![SunPosition { azimuth_deg: 200.0, elevation_deg: 35.0 }],
        sky_rays,
        ..ShadeMapParams::default()
    }
}

#[test]
fn a_flat_plane_sees_the_whole_sky_and_the_sun() {
    for surface in Surface::ALL {
        let map = map(field_of(20, 12, 30.0, |_, _| 412.0), surface, &all_layers(64));
        let lambert = 35f64.to_radians().sin();
        for (layer, values) in &map.layers {
            let expected = match layer {
                ShadeLayer::Shadow | ShadeLayer::Sky => 1.0,
                ShadeLayer::Hillshade => lambert,
                ShadeLayer::Combined => (1.0 - SKY_SHARE) * lambert + SKY_SHARE,
            };
            for &v in values {
                assert!((v as f64 - expected).abs() < 1e-6, "{surface} {layer}: {v} vs {expected}");
            }
        }
        // One sun ray, and one ray per sky azimuth (16 of 4 bands): the lowest band escapes.
        assert_eq!(map.rays, 20 * 12 * (1 + 16));
    }
}

#[test]
fn a_slope_sees_one_minus_its_angle_over_pi_of_the_sky() {
    // A plane rising towards the north-east at slope s: the sky above the horizontal plane but
    // below the slope's plane is a lune of 2s steradians, so the sky-view factor is 1 - s/π.
    let n = 256;
    for slope_deg in [10.0f64, 30.0, 60.0] {
        let grade = slope_deg.to_radians().tan() / 2f64.sqrt();
        let field = field_of(24, 24, 5.0, |x, y| 100.0 + grade * (x + y));
        let map = map(field, Surface::Triangles, &all_layers(n));
        let sky = map.layer(ShadeLayer::Sky).unwrap();
        let expected = 1.0 - slope_deg.to_radians() / std::f64::consts::PI;
        // Off the borders, where rays just below the slope leave the grid before they meet it.
        for row in 1..23 {
            for col in 1..23 {
                let v = sky[col + row * 24] as f64;
                assert!((v - expected).abs() <= 3.0 / n as f64, "{slope_deg}°: {v} vs {expected}");
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
    let n = 512;
    let map = map(field, Surface::Triangles, &all_layers(n));
    let sky = map.layer(ShadeLayer::Sky).unwrap()[40 + 40 * size] as f64;
    let low = (depth / ((radius + 1.0) * cell)).atan().sin();
    let high = (depth / ((radius - 0.5) * cell)).atan().sin();
    let tolerance = 1.0 / n as f64;
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
    for (layer, values) in &map.layers {
        for (k, v) in values.iter().enumerate() {
            assert_eq!(v.is_nan(), void[k], "{layer} at {k}");
            assert!(v.is_nan() || (0.0..=1.0).contains(v), "{layer} at {k}: {v}");
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
    let params = ShadeMapParams { sun_radius_deg: 1.0, ..all_layers(24) };
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
