//! The height-field erosion writes the layered state's surface into the field after every
//! step, keeps one column per cell, and refuses fields it cannot simulate.

use relief_core::{GridGeometry, HeightField};
use relief_sim::erosion::ErosionParams;
use relief_sim::{HeightFieldErosion, SimError};

fn hills(width: usize, height: usize, z_scale: f64) -> HeightField {
    let samples = (0..width * height)
        .map(|i| {
            let (x, y) = ((i % width) as f32, (i / width) as f32);
            (x * 0.4).sin() * 3.0 + (y * 0.3).cos() * 2.0 + y * 0.2 + 5.0
        })
        .collect();
    let g = GridGeometry { dx: 2.0, dy: 2.0, z_scale, ..GridGeometry::unit() };
    HeightField::new(width, height, samples, g).unwrap()
}

#[test]
fn the_field_is_the_state_surface_after_every_step() {
    for z_scale in [1.0, 2.5] {
        let mut field = hills(24, 19, z_scale);
        let start = field.clone();
        let mut erosion = HeightFieldErosion::new(&field, ErosionParams::default()).unwrap();
        for step in 1..=30 {
            erosion.step(&mut field).unwrap();
            let state = erosion.state();
            assert_eq!(state.step_count(), step);
            for y in 0..19 {
                for x in 0..24 {
                    assert_eq!(state.layer_counts()[x + y * 24], 1);
                    let top = state.column(x, y, 0).unwrap().solid_top();
                    let expected =
                        if z_scale == 1.0 { top } else { (f64::from(top) / z_scale) as f32 };
                    assert_eq!(field.sample(x, y), expected, "step {step}, ({x}, {y})");
                }
            }
        }
        assert_eq!(field.samples(), erosion.surface());
        assert_ne!(field, start, "30 steps of rain and erosion changed nothing");
    }
}

#[test]
fn same_bytes_with_one_and_two_threads() {
    let in_pool = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut field = hills(33, 20, 1.0);
            let mut erosion =
                HeightFieldErosion::new(&field, ErosionParams::default()).unwrap().with_seed(9);
            for _ in 0..20 {
                erosion.step(&mut field).unwrap();
            }
            field.samples().iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        })
    };
    assert_eq!(in_pool(1), in_pool(2));
}

#[test]
fn fields_it_cannot_simulate_are_refused() {
    let params = ErosionParams::default();
    let field = hills(8, 8, 1.0);
    let g = GridGeometry { dx: 1.0, dy: 2.0, ..*field.geometry() };
    let oblong = field.clone().with_geometry(g).unwrap();
    assert!(matches!(HeightFieldErosion::new(&oblong, params), Err(SimError::Mismatch(_))));
    let mut mask = vec![false; 64];
    mask[9] = true;
    let holed = field.clone().with_holes(mask).unwrap();
    assert!(matches!(HeightFieldErosion::new(&holed, params), Err(SimError::Mismatch(_))));
    let bad = ErosionParams { dt: -1.0, ..params };
    assert!(matches!(HeightFieldErosion::new(&field, bad), Err(SimError::Erosion(_))));
    let mut erosion = HeightFieldErosion::new(&field, params).unwrap();
    let mut other = hills(9, 8, 1.0);
    assert!(matches!(erosion.step(&mut other), Err(SimError::Mismatch(_))));
}
