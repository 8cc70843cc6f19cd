//! Rows of one-column cells: where the terrain has no overhang, the kernels take a path with
//! no loop over a neighbour's columns and no branch on the data, which the compiler
//! vectorizes across cells. It computes the same values, bit for bit, as the general path.
//!
//! A kernel that reads the four neighbours of a cell takes it for the cells `1..width - 1` of
//! a row in a one-column band ([`one_column_band`]); a kernel that reads only the cell's own
//! columns, for a row of one-column cells ([`one_column_row`]).

/// Whether row `y` and the rows beside it hold one column a cell, and the row has interior
/// cells (`1 <= y < height - 1`, `width >= 3`): its interior cells' four neighbours are then
/// one-column cells too, each with a `+inf` ceiling.
#[inline]
pub(crate) fn one_column_band(counts: &[u8], width: usize, height: usize, y: usize) -> bool {
    width >= 3
        && y >= 1
        && y + 1 < height
        && counts[(y - 1) * width..(y + 2) * width].iter().all(|&n| n == 1)
}

/// Whether every cell of row `y` holds one column.
#[inline]
pub(crate) fn one_column_row(counts: &[u8], width: usize, y: usize) -> bool {
    counts[y * width..(y + 1) * width].iter().all(|&n| n == 1)
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
