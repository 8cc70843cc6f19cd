//! Water and material conservation of the erosion simulation on random layered scenes, and
//! the MLHM invariants after every step.

mod erosion_common;

use erosion_common::{assert_valid, closed, random_scene};
use proptest::prelude::*;
use relief_sim::erosion::{ErosionParams, ErosionState, StepVolumes};

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Rain and evaporation off: 100 steps keep the water to 1e-4 relative.
    #[test]
    fn water_is_conserved_without_rain_and_evaporation(
        w in 3usize..12, h in 3usize..12, layers in 1usize..4, seed in any::<u64>()
    ) {
        let map = random_scene(w, h, layers, seed);
        let mut state = ErosionState::from_mlhm(&map, None, layers + 2, 0).unwrap();
        let before = state.totals().water;
        let params = closed();
        let mut volumes = StepVolumes::default();
        for step in 0..100 {
            volumes.add(&state.step(&params, seed).unwrap());
            assert_valid(&state, &format!("step {step}"));
        }
        let after = state.totals().water;
        prop_assert!(
            (after - before).abs() <= 1e-4 * before.max(1e-3),
            "water {before} -> {after}, clamped {}", volumes.water_clamped
        );
    }

    /// Every step: material changes by what the steps create and remove by design, water by
    /// rain and evaporation; the invariants hold.
    #[test]
    fn material_is_conserved_once_the_designed_volumes_are_counted(
        w in 3usize..12, h in 3usize..12, layers in 1usize..4, seed in any::<u64>()
    ) {
        let map = random_scene(w, h, layers, seed);
        let mut state = ErosionState::from_mlhm(&map, None, layers + 2, 0).unwrap();
        let params = ErosionParams::default();
        let start = state.totals();
        let mut volumes = StepVolumes::default();
        for step in 0..100 {
            volumes.add(&state.step(&params, seed).unwrap());
            assert_valid(&state, &format!("step {step}"));
        }
        let end = state.totals();
        let expected = start.material() + volumes.material_created() - volumes.material_removed();
        prop_assert!(
            (end.material() - expected).abs() <= 1e-4 * start.material().abs().max(1.0),
            "material {} -> {}, expected {expected}: {volumes:?}", start.material(), end.material()
        );
        let expected = start.water + volumes.rain - volumes.evaporation - volumes.water_clamped;
        prop_assert!(
            (end.water - expected).abs() <= 1e-4 * expected.max(1.0),
            "water {} -> {}, expected {expected}", start.water, end.water
        );
    }
}

/// The RiversRain scene under the default parameters for 200 steps: valid throughout, and
/// material accounted for.
#[test]
fn rivers_rain_erodes_validly() {
    let map = relief_sim::rivers_rain(32, 4, relief_sim::RIVERS_RAIN_SEED).unwrap();
    let mut state = ErosionState::from_mlhm(&map, None, 4, 0).unwrap();
    let start = state.totals();
    let mut volumes = StepVolumes::default();
    for step in 0..200 {
        volumes.add(&state.step(&ErosionParams::default(), 3).unwrap());
        assert_valid(&state, &format!("step {step}"));
    }
    let end = state.totals();
    let expected = start.material() + volumes.material_created() - volumes.material_removed();
    assert!((end.material() - expected).abs() <= 1e-4 * start.material(), "{volumes:?}");
    assert!(volumes.rain > 0.0 && volumes.evaporation > 0.0);
    assert!(end.sediment > 0.0, "water carries sediment after 200 steps");
}

/// The carved scenes (arches, a cave, a chasm, overhangs) under the default parameters for
/// 150 steps: valid after every step, and material accounted for.
#[test]
fn carved_scenes_erode_validly() {
    use relief_sim::{carved_scene, CarvedScene};
    for scene in
        [CarvedScene::Arches, CarvedScene::Cave, CarvedScene::Chasm, CarvedScene::Overhangs]
    {
        let map = carved_scene(scene, 48, 4).unwrap();
        let mut state = ErosionState::from_mlhm(&map, None, 6, 0).unwrap();
        let start = state.totals();
        let mut volumes = StepVolumes::default();
        for step in 0..150 {
            volumes.add(&state.step(&ErosionParams::default(), 11).unwrap());
            assert_valid(&state, &format!("{scene}, step {step}"));
        }
        let end = state.totals();
        let expected = start.material() + volumes.material_created() - volumes.material_removed();
        assert!(
            (end.material() - expected).abs() <= 1e-4 * start.material(),
            "{scene}: {} -> {}, expected {expected}: {volumes:?}",
            start.material(),
            end.material()
        );
    }
}
