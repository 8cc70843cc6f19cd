//! Step 1, rain: water on each cell's top column, `2 u rain dt` with `u` uniform in [0, 1)
//! from a counter-based generator keyed by seed, step and cell (reference: `rain.cu`).

use super::random::uniform;
use super::slots::{par_rows, Slots};
use super::{ErosionParams, ErosionState, StepVolumes};

/// Adds this step's rain; returns the water added (m per cell area).
pub(crate) fn rain(state: &mut ErosionState, params: &ErosionParams, seed: u64) -> StepVolumes {
    if params.rain == 0.0 {
        return StepVolumes::default();
    }
    let (width, cells, step) = (state.width, state.cells(), state.step);
    let counts = &state.layer_counts;
    let columns = Slots::new(&mut state.columns);
    par_rows(state.height, |y| {
        let mut v = StepVolumes::default();
        for x in 0..width {
            let i = x + y * width;
            let top = i + (usize::from(counts[i]) - 1) * cells;
            let amount = 2.0 * uniform(seed, step, i as u64) * params.rain * params.dt;
            // SAFETY: slot `top` belongs to cell (x, y) of this row only.
            unsafe {
                let mut c = columns.get(top);
                let before = c.water;
                c.water += amount;
                v.rain += f64::from(c.water) - f64::from(before);
                columns.set(top, c);
            }
        }
        v
    })
}
