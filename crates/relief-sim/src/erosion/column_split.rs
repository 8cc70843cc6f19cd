//! Step 4b, column splitting (reference: `erosion.cu`, `damageKernel`): a column whose
//! damage reaches `split_damage` metres splits at the window horizontal erosion exposed
//! (`[bottom, top]`), when the cell has room for another column. The upper part keeps the
//! column as it was (its floor now the window's top); the lower part is new: bedrock up to the
//! window's bottom, and the gap above it filled with sand up to `window - damage`, so the
//! air gap (the cave) is as high as the damage. The window's bedrock is removed and the sand
//! created, both counted; the damage is cleared.

use super::slots::{fit_column, par_rows, Slots};
use super::{ErosionParams, ErosionState, StepVolumes};
use relief_core::MlhmColumn;

/// Splits every column whose damage reached the threshold.
pub(crate) fn split_columns(state: &mut ErosionState, params: &ErosionParams) -> StepVolumes {
    let (width, height, cells, max_layers) =
        (state.width, state.height, state.cells(), state.max_layers);
    let counts = Slots::new(&mut state.layer_counts);
    let columns = Slots::new(&mut state.columns);
    let fluxes = Slots::new(&mut state.fluxes);
    let stability = Slots::new(&mut state.stability);
    let sediment = Slots::new(&mut state.sediment);
    let damage = Slots::new(&mut state.damage);
    let velocities = Slots::new(&mut state.scratch.velocities);
    let slopes = Slots::new(&mut state.scratch.slopes);
    let splits = &state.scratch.splits;
    par_rows(height, |y| {
        let mut v = StepVolumes::default();
        for x in 0..width {
            let i = x + y * width;
            // SAFETY (every access below): the slots touched are those of cell (x, y), which
            // only this row's thread touches.
            let original = usize::from(unsafe { counts.get(i) });
            let mut n = original;
            // Column `j` of the cell as horizontal erosion saw it, whose window is recorded at
            // its slot then: after `splits_here` splits below it in this cell it sits
            // `splits_here` slots higher, but its window stays at slot `i + j cells` (a record
            // read at the shifted slot would be another column's window, or a stale record
            // beyond the cell's columns, and split the column outside its bedrock).
            let mut splits_here = 0;
            for j in 0..original {
                let k = j + splits_here;
                let s = i + k * cells;
                let [bottom, top] = splits[i + j * cells];
                let d = unsafe { damage.get(s) };
                let window = top - bottom;
                if d < params.split_damage || window.is_nan() || window <= 0.0 || n >= max_layers {
                    continue;
                }
                // Shift columns k..n up by one slot.
                for from_k in (k..n).rev() {
                    let (from, to) = (i + from_k * cells, i + (from_k + 1) * cells);
                    unsafe {
                        columns.set(to, columns.get(from));
                        fluxes.set(to, fluxes.get(from));
                        stability.set(to, stability.get(from));
                        sediment.set(to, sediment.get(from));
                        damage.set(to, damage.get(from));
                        velocities.set(to, velocities.get(from));
                        slopes.set(to, slopes.get(from));
                    }
                }
                let sand = (window - d).max(0.0);
                let mut lower = MlhmColumn::new(bottom, sand, 0.0, top);
                let (_, clamped) = fit_column(&mut lower);
                unsafe {
                    damage.set(s + cells, 0.0);
                    columns.set(s, lower);
                    fluxes.set(s, [0.0; 4]);
                    sediment.set(s, 0.0);
                    damage.set(s, 0.0);
                    velocities.set(s, [0.0; 2]);
                    slopes.set(s, 0.0);
                }
                v.split_bedrock += f64::from(top) - f64::from(bottom);
                v.split_sand += f64::from(sand);
                v.sand_clamped += f64::from(clamped);
                v.splits += 1;
                n += 1;
                splits_here += 1;
            }
            unsafe { counts.set(i, n as u8) };
        }
        v
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::Mlhm;

    const INF: f32 = f32::INFINITY;

    /// A cell of three columns, the upper two damaged enough to split at their windows.
    fn two_splits_in_one_cell() -> ErosionState {
        let mut map = Mlhm::new(1, 1, 3, 1.0).unwrap();
        map.set_cell(
            0,
            0,
            &[
                MlhmColumn::new(0.0, 0.0, 0.0, 2.0),
                MlhmColumn::new(10.0, 0.0, 0.0, 12.0),
                MlhmColumn::new(20.0, 0.0, 0.0, INF),
            ],
        )
        .unwrap();
        let mut state = ErosionState::from_mlhm(&map, None, 8, 0).unwrap();
        state.scratch.splits[1] = [4.0, 8.0];
        state.scratch.splits[2] = [14.0, 18.0];
        // A record beyond the cell's columns, left there by an earlier step when the cell had
        // four: no column's window now.
        state.scratch.splits[3] = [11.5, 11.9];
        state.damage[1] = 1.0;
        state.damage[2] = 1.0;
        state
    }

    #[test]
    fn each_column_splits_at_its_own_window_after_a_split_below_it() {
        let mut state = two_splits_in_one_cell();
        let v = split_columns(&mut state, &ErosionParams::default());
        // Before the fix the second split read the record at the column's shifted slot (3),
        // the stale window, and made a column whose bedrock (11.5) is under the ceiling (12)
        // of the column below it.
        state.validate().unwrap();
        assert_eq!(v.splits, 2);
        let cell: Vec<MlhmColumn> = (0..5).map(|k| state.column(0, 0, k).unwrap()).collect();
        assert_eq!(
            cell,
            [
                MlhmColumn::new(0.0, 0.0, 0.0, 2.0),
                MlhmColumn::new(4.0, 3.0, 0.0, 8.0),
                MlhmColumn::new(10.0, 0.0, 0.0, 12.0),
                MlhmColumn::new(14.0, 3.0, 0.0, 18.0),
                MlhmColumn::new(20.0, 0.0, 0.0, INF),
            ]
        );
        assert_eq!(state.damage()[..5], [0.0; 5]);
        assert_eq!((v.split_bedrock, v.split_sand), (8.0, 6.0));
    }

    #[test]
    fn a_full_cell_does_not_split() {
        let mut state = two_splits_in_one_cell();
        state.max_layers = 4;
        let v = split_columns(&mut state, &ErosionParams::default());
        state.validate().unwrap();
        assert_eq!((v.splits, state.layer_counts()[0]), (1, 4));
        assert_eq!(state.column(0, 0, 1), Some(MlhmColumn::new(4.0, 3.0, 0.0, 8.0)));
        assert_eq!(state.damage()[3], 1.0);
    }
}
