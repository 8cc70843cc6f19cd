//! The erosion simulation gives the same bytes whatever the thread count, and a run saved
//! (to an MLHM and planes) and resumed equals an unbroken one.

mod erosion_common;

use erosion_common::{bits, random_scene};
use relief_sim::erosion::{ErosionParams, ErosionState};

fn run(state: &mut ErosionState, steps: usize, seed: u64) {
    for _ in 0..steps {
        state.step(&ErosionParams::default(), seed).unwrap();
    }
}

fn scene() -> ErosionState {
    let map = random_scene(24, 20, 3, 99);
    ErosionState::from_mlhm(&map, None, 4, 0).unwrap()
}

#[test]
fn same_bytes_with_one_and_two_threads() {
    let in_pool = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut state = scene();
            run(&mut state, 60, 5);
            bits(&state)
        })
    };
    let one = in_pool(1);
    assert_eq!(one, in_pool(2));
    assert_eq!(one, in_pool(3));
}

#[test]
fn rain_depends_on_the_seed() {
    let (mut a, mut b) = (scene(), scene());
    run(&mut a, 3, 1);
    run(&mut b, 3, 2);
    assert_ne!(bits(&a), bits(&b));
}

#[test]
fn saved_and_resumed_run_equals_an_unbroken_one() {
    let mut unbroken = scene();
    run(&mut unbroken, 50, 8);
    let mut first = scene();
    run(&mut first, 23, 8);
    let (map, planes) = (first.to_mlhm().unwrap(), first.planes());
    let mut resumed = ErosionState::from_mlhm(&map, Some(&planes), 4, first.step_count()).unwrap();
    run(&mut resumed, 27, 8);
    assert_eq!(resumed.step_count(), 50);
    assert_eq!(bits(&resumed), bits(&unbroken));
}
