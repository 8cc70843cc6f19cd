//! Hand-built cases: a column split by water rushing past a cliff, and the support check
//! collapsing a floating slab while keeping a supported arch.

mod erosion_common;

use erosion_common::{assert_valid, closed};
use relief_core::{Mlhm, MlhmColumn};
use relief_sim::erosion::{
    end_support_check, start_support_check, support_pass, ErosionParams, ErosionState,
    SimulationPlanes, StepVolumes,
};

const INF: f32 = f32::INFINITY;

/// A 4 x 3 grid of 10 m rock with a channel at x = 2 holding 5 m of water that flows north
/// at the channel's south end, beside the cliff of cell (1, 0), whose damage is `damage`.
fn channel(damage: f32) -> ErosionState {
    let mut map = Mlhm::new(4, 3, 2, 1.0).unwrap();
    for y in 0..3 {
        for x in 0..4 {
            let c = if x == 2 {
                MlhmColumn::new(0.0, 0.0, 5.0, INF)
            } else {
                MlhmColumn::new(10.0, 0.0, 0.0, INF)
            };
            map.set_cell(x, y, &[c]).unwrap();
        }
    }
    let mut planes = SimulationPlanes::zeros(4 * 3 * 2);
    planes.fluxes[2] = [0.0, 4.0, 0.0, 0.0];
    planes.damage[1] = damage;
    ErosionState::from_mlhm(&map, Some(&planes), 2, 1).unwrap()
}

#[test]
fn water_beside_a_cliff_splits_the_column_keeping_invariants_and_volumes() {
    let mut state = channel(0.74);
    let params = ErosionParams { support_check: false, ..closed() };
    let start = state.totals();
    let volumes = state.step(&params, 0).unwrap();
    assert_valid(&state, "after the split");
    assert_eq!(volumes.splits, 1, "{volumes:?}");
    assert_eq!(state.layer_counts()[1], 2);
    let lower = state.column(1, 0, 0).unwrap();
    let upper = state.column(1, 0, 1).unwrap();
    assert!(lower.ceiling <= upper.bedrock && lower.ceiling <= 5.0 + 1e-3, "{lower:?} {upper:?}");
    assert_eq!(upper.bedrock, 10.0);
    // The gap is as high as the damage was; sand fills the rest of the window.
    let gap = lower.ceiling - lower.solid_top();
    assert!(gap >= 0.74 && gap <= lower.ceiling - lower.bedrock, "{lower:?}");
    assert_eq!(state.damage()[1], 0.0);
    let end = state.totals();
    let expected = start.material() + volumes.material_created() - volumes.material_removed();
    assert!((end.material() - expected).abs() < 1e-4 * start.material(), "{volumes:?}");
    assert!((end.water - start.water).abs() < 1e-4 * start.water);
    // Later steps keep the split cell valid.
    for step in 0..40 {
        state.step(&params, 0).unwrap();
        assert_valid(&state, &format!("step {step} after the split"));
    }
}

#[test]
fn a_column_does_not_split_below_the_damage_threshold() {
    let mut state = channel(0.0);
    let volumes = state.step(&ErosionParams { support_check: false, ..closed() }, 0).unwrap();
    assert_eq!(volumes.splits, 0);
    assert!(volumes.horizontal_erosion_sand > 0.0, "the water erodes the cliff: {volumes:?}");
    assert!(state.damage()[1] > 0.0);
    assert_eq!(state.layer_counts()[1], 1);
}

/// An `w x h` grid of ground at 0 m with `cells` holding a second column: bedrock from 5 m
/// to 8 m over an air gap; `pillars` are ground cells of rock up to 8 m.
fn slab_scene(
    w: usize,
    h: usize,
    cells: &[(usize, usize)],
    pillars: &[(usize, usize)],
) -> ErosionState {
    let mut map = Mlhm::new(w, h, 2, 1.0).unwrap();
    for &(x, y) in cells {
        map.set_cell(
            x,
            y,
            &[MlhmColumn::new(0.0, 0.0, 0.0, 5.0), MlhmColumn::new(8.0, 0.0, 0.0, INF)],
        )
        .unwrap();
    }
    for &(x, y) in pillars {
        map.set_cell(x, y, &[MlhmColumn::new(8.0, 0.0, 0.0, INF)]).unwrap();
    }
    ErosionState::from_mlhm(&map, None, 2, 0).unwrap()
}

fn support_check(state: &mut ErosionState) -> StepVolumes {
    let params = ErosionParams::default();
    start_support_check(state);
    for _ in 0..12 {
        support_pass(state, &params);
    }
    end_support_check(state, &params)
}

#[test]
fn a_floating_slab_falls_as_sand() {
    let mut state = slab_scene(7, 7, &[(3, 3), (3, 4)], &[]);
    let start = state.totals();
    let volumes = support_check(&mut state);
    assert_valid(&state, "after the collapse");
    assert_eq!(volumes.collapses, 2);
    assert!(state.layer_counts().iter().all(|&n| n == 1));
    let c = state.column(3, 3, 0).unwrap();
    assert_eq!(c, MlhmColumn::new(0.0, 3.0, 0.0, INF));
    let end = state.totals();
    assert!((end.material() - start.material()).abs() < 1e-9);
}

#[test]
fn a_supported_arch_stays_and_nothing_else_moves() {
    // Pillars at x = 1 and x = 9 of row 2 carry an arch over x = 2..=8; a slab floats apart.
    let arch: Vec<_> = (2..=8).map(|x| (x, 2)).collect();
    let mut cells = arch.clone();
    cells.push((5, 5));
    let mut state = slab_scene(11, 7, &cells, &[(1, 2), (9, 2)]);
    let before: Vec<_> = state.columns().to_vec();
    let volumes = support_check(&mut state);
    assert_valid(&state, "after the check");
    assert_eq!(volumes.collapses, 1, "only the floating slab falls");
    for &(x, y) in &arch {
        assert_eq!(state.layer_counts()[x + y * 11], 2, "arch cell ({x}, {y})");
        assert!(state.stability()[x + y * 11 + 77] > 0.0);
    }
    assert_eq!(state.layer_counts()[5 + 5 * 11], 1);
    for (i, (a, b)) in before.iter().zip(state.columns()).enumerate() {
        if i % 77 != 5 + 5 * 11 {
            assert_eq!(a, b, "slot {i} changed");
        }
    }
}

#[test]
fn a_thin_overhang_collapses() {
    let mut map = Mlhm::new(5, 5, 2, 1.0).unwrap();
    for y in 0..5 {
        map.set_cell(0, y, &[MlhmColumn::new(8.0, 0.0, 0.0, INF)]).unwrap();
    }
    // Anchored to the pillar column at x = 0 but only 0.5 m thick.
    map.set_cell(1, 2, &[MlhmColumn::new(0.0, 0.0, 0.0, 7.5), MlhmColumn::new(8.0, 0.0, 0.0, INF)])
        .unwrap();
    let mut state = ErosionState::from_mlhm(&map, None, 2, 0).unwrap();
    let volumes = support_check(&mut state);
    assert_eq!(volumes.collapses, 1);
    assert_valid(&state, "after the collapse");
}
