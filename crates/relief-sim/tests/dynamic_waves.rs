//! The ocean wave simulation: the same bytes for any thread count, a calm sea stays flat,
//! a drop's wave neither grows (stable time step) nor outlives its damping, and the field
//! is always max(sea bed, sea level + wave).

use relief_core::{GridGeometry, HeightField};
use relief_sim::{SimError, WaveParams, WaveSimulation};

/// A basin: a bed sloping up from -4 to 4 along x, a bump in the middle.
fn basin(width: usize, height: usize) -> HeightField {
    let samples = (0..width * height)
        .map(|i| {
            let (x, y) = ((i % width) as f32, (i / width) as f32);
            -4.0 + 8.0 * x / width as f32
                + 2.0 * (-((x - 10.0).powi(2) + (y - 8.0).powi(2)) / 9.0).exp()
        })
        .collect();
    let g = GridGeometry { dx: 1.5, dy: 1.0, z_scale: 0.5, ..GridGeometry::unit() };
    HeightField::new(width, height, samples, g).unwrap()
}

fn run(params: WaveParams, steps: usize) -> (HeightField, WaveSimulation) {
    let mut field = basin(40, 33);
    let mut sea = WaveSimulation::new(&field, params).unwrap();
    for _ in 0..steps {
        sea.step(&mut field).unwrap();
    }
    (field, sea)
}

fn max_abs(v: &[f32]) -> f32 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn same_bytes_with_one_two_and_three_threads() {
    let params = WaveParams { drop_interval: 3, ..WaveParams::for_field(&basin(40, 33)) };
    let in_pool = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let (field, sea) = run(params, 60);
            let bits: Vec<u32> = field.samples().iter().map(|v| v.to_bits()).collect();
            let wave: Vec<u32> = sea.wave().iter().map(|v| v.to_bits()).collect();
            (bits, wave)
        })
    };
    let one = in_pool(1);
    assert!(max_abs(&one.1.iter().map(|&b| f32::from_bits(b)).collect::<Vec<_>>()) > 0.0);
    assert_eq!(one, in_pool(2));
    assert_eq!(one, in_pool(3));
}

#[test]
fn the_field_is_the_sea_over_the_bed() {
    let params = WaveParams { sea_level: 0.25, ..WaveParams::for_field(&basin(40, 33)) };
    let (field, sea) = run(params, 25);
    let sea_level = 0.25 / 0.5; // sample units at z scale 0.5
    let mut wet = 0;
    for ((&v, &bed), &u) in field.samples().iter().zip(sea.sea_bed()).zip(sea.wave()) {
        assert_eq!(v, bed.max(sea_level + u));
        wet += usize::from(v > bed);
    }
    assert!(wet > 100, "only {wet} wet samples");
    assert_eq!(sea.step_count(), 25);
}

#[test]
fn a_calm_sea_stays_flat() {
    let params = WaveParams {
        drop_interval: 0,
        wind_amplitude: 0.0,
        sea_level: 0.0,
        ..WaveParams::for_field(&basin(40, 33))
    };
    let (field, sea) = run(params, 50);
    assert_eq!(max_abs(sea.wave()), 0.0);
    for (&v, &bed) in field.samples().iter().zip(sea.sea_bed()) {
        assert_eq!(v, bed.max(0.0));
    }
}

#[test]
fn a_drop_stays_bounded_at_a_stable_step_and_damping_calms_it() {
    // The sea over the whole basin, one drop at step 0, no wind.
    let one_drop = WaveParams {
        sea_level: 10.0,
        drop_interval: 100_000,
        wind_amplitude: 0.0,
        courant: 0.95,
        damping: 0.0,
        drop_amplitude: 1.0,
        ..WaveParams::for_field(&basin(40, 33))
    };
    let (_, first) = run(one_drop, 1);
    let peak = max_abs(first.wave());
    assert!(peak > 1.0, "the drop lifts the sea by {peak} sample units");
    // Reflections off the walls may add up, but a stable scheme keeps the wave of the order
    // of the drop (an unstable one grows without bound within these steps).
    let (_, undamped) = run(one_drop, 600);
    let late = max_abs(undamped.wave());
    assert!(late.is_finite() && late < 2.0 * peak, "an undamped wave grew from {peak} to {late}");
    assert!(late > 0.01 * peak, "an undamped wave vanished ({late})");
    let (_, damped) = run(WaveParams { damping: 2.0, ..one_drop }, 600);
    let calm = max_abs(damped.wave());
    assert!(calm < 0.1 * late, "damping left {calm} of {late}");
}

#[test]
fn land_keeps_a_zero_wave() {
    // The sea covers only the low (west) end; drops and wind never move the land beyond the
    // last wet column of a row.
    let params =
        WaveParams { sea_level: -1.0, drop_interval: 1, ..WaveParams::for_field(&basin(40, 33)) };
    let (_, sea) = run(params, 80);
    let bed = sea.sea_bed();
    let sea_level = -2.0; // sample units at z scale 0.5
    let mut moved = 0;
    for row in 0..33 {
        let r = &bed[row * 40..(row + 1) * 40];
        let last_wet = r.iter().rposition(|&b| b < sea_level).unwrap();
        for col in 0..40 {
            let u = sea.wave()[col + row * 40];
            if col > last_wet {
                assert_eq!(u, 0.0, "({col}, {row}) is land");
            } else {
                moved += usize::from(u != 0.0);
            }
        }
    }
    assert!(moved > 50, "the sea hardly moved ({moved} samples)");
}

#[test]
fn bad_parameters_and_other_fields_are_refused() {
    let field = basin(8, 8);
    let good = WaveParams::for_field(&field);
    for bad in [
        WaveParams { courant: 1.0, ..good },
        WaveParams { courant: 0.0, ..good },
        WaveParams { wave_speed: -1.0, ..good },
        WaveParams { damping: f64::NAN, ..good },
        WaveParams { drop_radius: 0.0, ..good },
        WaveParams { wind_wavelength: f64::INFINITY, ..good },
        WaveParams { sea_level: 1e300, ..good },
    ] {
        assert!(matches!(WaveSimulation::new(&field, bad), Err(SimError::Parameter { .. })));
    }
    let mut sea = WaveSimulation::new(&field, good).unwrap();
    let mut other = basin(9, 8);
    let before = other.clone();
    assert!(matches!(sea.step(&mut other), Err(SimError::Mismatch(_))));
    assert_eq!(other, before);
}
