//! Runs of one-column cells: where the terrain has no overhang, the kernels take a path with
//! no loop over a neighbour's columns and no branch on the data, which computes [`LANES`]
//! cells at a time in vector registers. It computes the same values, bit for bit, as the
//! general path.
//!
//! A kernel that reads the four neighbours of a cell takes it for lanes of cells whose own
//! and whose neighbours' cells hold one column each ([`neighbourhood_run`]); a kernel that
//! reads only the cell's own columns, for lanes of one-column cells ([`row_run`]). Both find
//! runs of whole lanes from a cell on; the cells between runs take the general path.

use super::lanes::LANES;
use std::ops::Range;

/// How many whole lanes of cells from `(x, y)` on (cells `x..x + n LANES`) have one column
/// each, and so have their four neighbours: the cells of rows `y - 1..=y + 1` from `x - 1` to
/// `x + n LANES` inclusive. Neighbours beyond the grid do not count: the run stays inside
/// (`1 <= y < height - 1`, `x >= 1`, `x + n LANES < width`). A one-column cell's ceiling is
/// `+inf`.
#[inline]
pub(crate) fn neighbourhood_run(
    counts: &[u8],
    width: usize,
    height: usize,
    y: usize,
    x: usize,
) -> usize {
    if y == 0 || y + 1 >= height || x == 0 || counts[x + y * width] != 1 {
        return 0;
    }
    let rows = [(y - 1) * width, y * width, (y + 1) * width];
    let ones = |from: usize, to: usize| {
        rows.iter().all(|&r| counts[r + from..r + to].iter().all(|&n| n == 1))
    };
    // Cells `x - 1..checked` of the three rows hold one column.
    let (mut lanes, mut checked) = (0, x - 1);
    while x + (lanes + 1) * LANES < width {
        let to = x + (lanes + 1) * LANES + 1;
        if !ones(checked, to) {
            break;
        }
        (lanes, checked) = (lanes + 1, to);
    }
    lanes
}

/// How many whole lanes of cells from `(x, y)` on (cells `x..x + n LANES` of row `y`) have one
/// column each.
#[inline]
pub(crate) fn row_run(counts: &[u8], width: usize, y: usize, x: usize) -> usize {
    let row = &counts[y * width..(y + 1) * width];
    let mut lanes = 0;
    while x + (lanes + 1) * LANES <= width
        && row[x + lanes * LANES..x + (lanes + 1) * LANES].iter().all(|&n| n == 1)
    {
        lanes += 1;
    }
    lanes
}

/// Goes along a row of `width` cells: where `run(x)` finds whole lanes of cells from `x` on,
/// `lanes(state, x..x + n LANES)`; every other cell, `cell(state, x)`; in the order of the
/// cells.
#[inline(always)]
pub(crate) fn along_row<S>(
    width: usize,
    state: &mut S,
    run: impl Fn(usize) -> usize,
    mut lanes: impl FnMut(&mut S, Range<usize>),
    mut cell: impl FnMut(&mut S, usize),
) {
    let mut x = 0;
    while x < width {
        match run(x) {
            0 => {
                cell(state, x);
                x += 1;
            }
            n => {
                lanes(state, x..x + n * LANES);
                x += n * LANES;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::erosion::{ErosionParams, ErosionState, StepVolumes};
    use crate::{carved_scene, rivers_rain, CarvedScene, RIVERS_RAIN_SEED};

    /// Every value of the state, as bits.
    fn bits(state: &ErosionState) -> Vec<u32> {
        let mut b: Vec<u32> = state.layer_counts().iter().map(|&n| u32::from(n)).collect();
        for (s, c) in state.columns().iter().enumerate() {
            b.extend([c.bedrock, c.sand, c.water, c.ceiling].map(f32::to_bits));
            b.extend(state.fluxes()[s].map(f32::to_bits));
            b.extend(
                [state.stability()[s], state.sediment()[s], state.damage()[s]].map(f32::to_bits),
            );
        }
        b
    }

    /// Runs `steps` steps with and without the one-column paths: the same bits every step,
    /// and the same volumes up to the order of their f64 sums.
    fn same_either_way(mut fast: ErosionState, params: &ErosionParams, steps: usize) {
        let mut general = fast.clone();
        general.scratch.fast_paths = false;
        let (mut vf, mut vg) = (StepVolumes::default(), StepVolumes::default());
        for step in 0..steps {
            vf.add(&fast.step(params, 5).unwrap());
            vg.add(&general.step(params, 5).unwrap());
            assert!(bits(&fast) == bits(&general), "the paths part at step {step}");
        }
        for (a, b) in [
            (vf.evaporation, vg.evaporation),
            (vf.water_clamped, vg.water_clamped),
            (vf.sand_clamped, vg.sand_clamped),
            (vf.sediment_clamped, vg.sediment_clamped),
            (vf.horizontal_erosion_sand, vg.horizontal_erosion_sand),
            (vf.damage_recovery, vg.damage_recovery),
        ] {
            assert!((a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-30), "{vf:?}\n{vg:?}");
        }
        assert_eq!((vf.splits, vf.collapses), (vg.splits, vg.collapses));
    }

    #[test]
    fn one_column_paths_give_the_general_paths_bits() {
        // A one-column scene, with widths that leave cells after the last whole lanes.
        for size in [29, 40] {
            let map = rivers_rain(size, 4, RIVERS_RAIN_SEED).unwrap();
            let state = ErosionState::from_mlhm(&map, None, 4, 0).unwrap();
            same_either_way(state, &ErosionParams::default(), 60);
        }
        // Scenes with overhangs beside one-column rows: under heavy rain the arches erode
        // sideways, split (14 times in these 100 steps) and collapse (115 times).
        let wet = ErosionParams { rain: 0.5, ..ErosionParams::default() };
        for (scene, params) in
            [(CarvedScene::Arches, wet), (CarvedScene::Cave, ErosionParams::default())]
        {
            let map = carved_scene(scene, 48, 4).unwrap();
            let state = ErosionState::from_mlhm(&map, None, 6, 0).unwrap();
            same_either_way(state, &params, 100);
        }
        // No slippage, heavy rain: other branches of the same formulas.
        let params = ErosionParams { slippage: false, rain: 0.5, ..ErosionParams::default() };
        let map = rivers_rain(37, 4, RIVERS_RAIN_SEED).unwrap();
        same_either_way(ErosionState::from_mlhm(&map, None, 4, 0).unwrap(), &params, 40);
    }
}
