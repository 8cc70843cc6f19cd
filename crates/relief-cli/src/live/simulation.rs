//! An MLHM scene's erosion simulation (relief_sim::erosion) run live in the viewer: the
//! state is made from the scene as `relief simulate` makes it (its saved planes and step
//! count, its `Simulation/*` settings over the defaults, the same seed), so that N steps in
//! the viewer give the terrain `relief simulate SCENE --steps N` writes.

use crate::args::ReadArgs;
use crate::input;
use anyhow::{Context, Result};
use relief_core::{Mlhm, Precision};
use relief_sim::erosion::{ErosionParams, ErosionState};
use relief_viewer::{SimulationReport, SimulationRequest};
use serde_json::{Map, Value};
use std::path::Path;
use std::time::Instant;

/// The seed of the rain's random numbers: `relief simulate`'s default.
const SEED: u64 = 1;

/// The most steps one request takes, whatever its budget.
const MAX_STEPS_PER_REQUEST: u32 = 1000;

/// A running erosion simulation of an MLHM scene.
pub struct MlhmSimulation {
    state: ErosionState,
    params: ErosionParams,
    /// The scene's rain rate (m/s), used while the rain is on.
    rain: f32,
    /// The scene's layer planes: the terrain has at least these.
    initial_layers: usize,
    /// The precision the scene is stored at: `relief simulate` writes its result at it.
    precision: Precision,
}

impl MlhmSimulation {
    /// The simulation of the scene at `path`, as `relief simulate` starts it.
    pub fn open(path: &Path, max_memory: Option<u64>) -> Result<Self> {
        let read = ReadArgs { max_memory, ..ReadArgs::default() };
        let scene = input::load_mlhm(path, &read)?;
        let params = params(&scene.settings)
            .with_context(|| format!("the simulation settings of {}", path.display()))?;
        let state = crate::commands::start_state(&scene, path, max_memory)?;
        let map = &scene.mlhm;
        Ok(MlhmSimulation {
            state,
            rain: params.rain,
            params,
            initial_layers: map.max_layers(),
            precision: scene.precision,
        })
    }

    /// Takes the steps `request` asks for; the terrain after them, as `relief simulate`
    /// writes it.
    pub fn advance(&mut self, request: &SimulationRequest) -> Result<(Mlhm, SimulationReport)> {
        self.params.rain = if request.rain { self.rain } else { 0.0 };
        let started = Instant::now();
        let mut steps = 0u32;
        loop {
            self.state.step(&self.params, SEED)?;
            steps += 1;
            if steps >= MAX_STEPS_PER_REQUEST {
                break;
            }
            if steps >= request.steps {
                let Some(budget) = request.budget else { break };
                let elapsed = started.elapsed();
                // Another step only if it is predicted to fit.
                if elapsed + elapsed / steps > budget {
                    break;
                }
            }
        }
        let step_ms = started.elapsed().as_secs_f64() * 1e3;
        let layers = self.state.used_layers().max(self.initial_layers);
        let mut map = self.state.to_mlhm_with_layers(layers)?;
        if self.precision != Precision::F32 {
            map = map.to_precision(self.precision).context("rounding to the scene's precision")?;
        }
        let report = SimulationReport { steps, step_count: self.state.step_count(), step_ms };
        Ok((map, report))
    }
}

/// The parameters as `relief simulate` takes them without options: the reference defaults
/// and the scene's `Simulation/*` settings over them.
fn params(settings: &Map<String, Value>) -> Result<ErosionParams> {
    let p = crate::commands::scene_params(settings);
    p.validate()?;
    Ok(p)
}
