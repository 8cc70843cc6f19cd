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
use super::{ErosionError, ErosionParams, ErosionState, Stage, StepVolumes};

impl ErosionState {
    /// Simulates one step of `params.dt` seconds with rain seeded by `seed`; returns the
    /// volumes (m³) the step added or removed by design (see [`StepVolumes`]).
    ///
    /// The support check runs `support_passes_per_step` passes per step; every
    /// [`ErosionParams::support_cycle_steps`] steps (counted from step 0) it ends, collapsing
    /// what is unsupported, and starts again. Deterministic: the same state, parameters and
    /// seed give the same bytes whatever the thread count.
    ///
    /// Checks the invariants after the step ([`ErosionState::validate`]).
    ///
    /// Errors: parameters [`ErosionParams::validate`] refuses (the state is then unchanged);
    /// [`ErosionError::Invariant`] when the step broke the invariants (a bug: the state is
    /// then as the step left it, its step count not advanced; go back to a copy).
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
        self.run_step(params, seed, false)
    }

    /// [`ErosionState::step`], checking the invariants ([`ErosionState::validate`]) after each
    /// of its stages instead of once after the step: a diagnostic run, a few times slower,
    /// whose [`ErosionError::Invariant`] names the [`Stage`] that broke them.
    pub fn step_checking_stages(
        &mut self,
        params: &ErosionParams,
        seed: u64,
    ) -> Result<StepVolumes, ErosionError> {
        self.run_step(params, seed, true)
    }

    /// One step; checks the invariants after each stage when `stages`, else after the step.
    fn run_step(
        &mut self,
        params: &ErosionParams,
        seed: u64,
        stages: bool,
    ) -> Result<StepVolumes, ErosionError> {
        params.validate()?;
        let step = self.step;
        let check = |state: &ErosionState, stage: Option<Stage>| {
            state.validate().map_err(|e| ErosionError::Invariant {
                step,
                stage,
                error: Box::new(e),
            })
        };
        let after = |state: &ErosionState, stage: Stage| {
            if stages {
                check(state, Some(stage))
            } else {
                Ok(())
            }
        };
        let mut volumes = StepVolumes { steps: 1, ..StepVolumes::default() };
        volumes.add(&rain(self, params, seed));
        after(self, Stage::Rain)?;
        pipes(self, params);
        after(self, Stage::Pipes)?;
        volumes.add(&transport(self, params));
        after(self, Stage::Transport)?;
        if params.horizontal_erosion {
            let (eroded, windows) = horizontal_erosion(self, params);
            volumes.add(&eroded);
            after(self, Stage::HorizontalErosion)?;
            // Only a column that eroded this step has a window to split at.
            if windows {
                volumes.add(&split_columns(self, params));
                after(self, Stage::ColumnSplit)?;
            }
        }
        volumes.add(&vertical_erosion(self, params));
        after(self, Stage::VerticalErosion)?;
        if params.support_check {
            let cycle = params.support_cycle_steps(self.cell_size);
            if self.step.is_multiple_of(cycle) {
                if self.step > 0 {
                    volumes.add(&end_support_check(self, params));
                }
                start_support_check(self);
            }
            support_passes(self, params, params.support_passes_per_step);
            after(self, Stage::Support)?;
        }
        if !stages {
            check(self, None)?;
        }
        self.step += 1;
        let area = f64::from(self.cell_size) * f64::from(self.cell_size);
        Ok(volumes.scaled(area))
    }
}
