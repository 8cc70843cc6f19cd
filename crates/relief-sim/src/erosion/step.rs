//! One simulation step: the reference's kernels in its order (`core/geo/systems/terrain.inl`):
//! rain, pipes and slippage, transport, horizontal erosion with splits, vertical erosion, and
//! the support check.

use super::column_split::split_columns;
use super::horizontal_erosion::horizontal_erosion;
use super::pipes::pipes;
use super::rain::rain;
use super::support::{end_support_check, start_support_check, support_passes};
use super::transport::transport;
use super::vertical_erosion::vertical_erosion;
use super::{ErosionError, ErosionParams, ErosionState, StepVolumes};

impl ErosionState {
    /// Simulates one step of `params.dt` seconds with rain seeded by `seed`; returns the
    /// volumes (m³) the step added or removed by design (see [`StepVolumes`]).
    ///
    /// The support check runs `support_passes_per_step` passes per step; every
    /// [`ErosionParams::support_cycle_steps`] steps (counted from step 0) it ends, collapsing
    /// what is unsupported, and starts again. Deterministic: the same state, parameters and
    /// seed give the same bytes whatever the thread count.
    ///
    /// Errors: parameters [`ErosionParams::validate`] refuses; the state is then unchanged.
    ///
    /// ```
    /// use relief_sim::erosion::{ErosionParams, ErosionState};
    /// let heights: Vec<f32> = (0..64).map(|i| (i % 8) as f32 * 0.5).collect();
    /// let mut state = ErosionState::from_heights(8, 8, 1.0, &heights, 0.5, 4)?;
    /// let volumes = state.step(&ErosionParams::default(), 1)?;
    /// assert!(volumes.rain > 0.0);
    /// state.to_mlhm()?.validate()?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn step(&mut self, params: &ErosionParams, seed: u64) -> Result<StepVolumes, ErosionError> {
        params.validate()?;
        let mut volumes = StepVolumes { steps: 1, ..StepVolumes::default() };
        volumes.add(&rain(self, params, seed));
        pipes(self, params);
        volumes.add(&transport(self, params));
        if params.horizontal_erosion {
            let (eroded, windows) = horizontal_erosion(self, params);
            volumes.add(&eroded);
            // Only a column that eroded this step has a window to split at.
            if windows {
                volumes.add(&split_columns(self, params));
            }
        }
        volumes.add(&vertical_erosion(self, params));
        if params.support_check {
            let cycle = params.support_cycle_steps(self.cell_size);
            if self.step.is_multiple_of(cycle) {
                if self.step > 0 {
                    volumes.add(&end_support_check(self, params));
                }
                start_support_check(self);
            }
            support_passes(self, params, params.support_passes_per_step);
        }
        self.step += 1;
        let area = f64::from(self.cell_size) * f64::from(self.cell_size);
        Ok(volumes.scaled(area))
    }
}
