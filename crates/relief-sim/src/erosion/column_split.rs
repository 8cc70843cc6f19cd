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
            let mut n = usize::from(unsafe { counts.get(i) });
            let mut k = 0;
            while k < n {
                let s = i + k * cells;
                let [bottom, top] = splits[s];
                let d = unsafe { damage.get(s) };
                let window = top - bottom;
                if d < params.split_damage || window.is_nan() || window <= 0.0 || n >= max_layers {
                    k += 1;
                    continue;
                }
                // Shift columns k..n up by one slot.
                for j in (k..n).rev() {
                    let (from, to) = (i + j * cells, i + (j + 1) * cells);
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
                k += 2;
            }
            unsafe { counts.set(i, n as u8) };
        }
        v
    })
}
