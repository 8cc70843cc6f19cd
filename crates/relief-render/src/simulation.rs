//! An MLHM scene's erosion simulation (relief_sim::erosion) as `relief simulate` and the
//! viewer run it: the state made from the scene (its saved planes and step count, its
//! `Simulation/*` settings over the defaults, the same seed), so that N steps anywhere give
//! the terrain `relief simulate SCENE --steps N` writes.

use crate::error::RenderError;
use crate::input;
use crate::memory;
use crate::options::ReadSettings;
use relief_core::{Mlhm, Precision};
use relief_io::MlhmScene;
use relief_sim::erosion::{ErosionParams, ErosionState, SimulationPlanes};
use serde_json::{Map, Value};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

mod scene_file;

pub use scene_file::{write_scene, SceneTemplate, STEP_KEY};

/// Bytes the simulation holds per column slot: the terrain, the saved planes and the
/// per-step scratch planes.
pub const BYTES_PER_SLOT: u64 = 16 + 16 + 12 + 64;

/// The seed of the rain's random numbers: `relief simulate`'s default.
pub const SEED: u64 = 1;

/// The most steps one call of [`MlhmSimulation::advance`] takes, whatever its time budget.
pub const MAX_STEPS_PER_ADVANCE: u32 = 1000;

/// The simulation state of `scene` (read from `path`) as `relief simulate` and `relief view`
/// start it: its columns, its saved planes and step count, at the scene's layer capacity.
/// Refuses a scene whose simulation, holding `bytes_per_slot` bytes per column slot, would
/// not fit the memory budget `max_memory` gives.
pub fn start_state(
    scene: &MlhmScene,
    path: &Path,
    max_memory: Option<u64>,
    bytes_per_slot: u64,
) -> Result<ErosionState, RenderError> {
    let map = &scene.mlhm;
    let capacity = scene.max_layer_count.clamp(map.max_layers(), 255);
    let budget = memory::budget(max_memory);
    let needed =
        (map.width() * map.height()) as u128 * capacity as u128 * u128::from(bytes_per_slot);
    if needed > u128::from(budget.bytes) {
        return Err(RenderError::SimulationOverBudget {
            width: map.width(),
            height: map.height(),
            capacity,
            needed_mib: needed >> 20,
            budget,
        });
    }
    let first_step = scene.settings.get(STEP_KEY).and_then(Value::as_u64).unwrap_or(0);
    let planes = scene.simulation.as_ref().map(|s| SimulationPlanes {
        fluxes: s.fluxes.clone(),
        stability: s.stability.clone(),
        sediment: s.sediment.clone(),
        damage: s.damage.clone(),
    });
    ErosionState::from_mlhm(map, planes.as_ref(), capacity, first_step)
        .map_err(|source| RenderError::SimulationState { path: path.to_path_buf(), source })
}

/// The reference defaults with a scene's `Simulation/*` settings over them (not validated).
pub fn scene_params(settings: &Map<String, Value>) -> ErosionParams {
    let number = |key: &str| settings.get(&format!("Simulation/{key}")).and_then(Value::as_f64);
    let flag = |key: &str| settings.get(&format!("Simulation/{key}")).and_then(Value::as_bool);
    let mut p = ErosionParams::default();
    let numbers: [(&str, &mut f32); 13] = [
        ("DeltaTime", &mut p.dt),
        ("Rain", &mut p.rain),
        ("Evaporation", &mut p.evaporation),
        ("Petrification", &mut p.petrification),
        ("SlippageInterpolationRange", &mut p.slippage_interpolation_range),
        ("SedimentCapacityConstant", &mut p.sediment_capacity),
        ("BedrockDissolvingConstant", &mut p.bedrock_dissolving),
        ("SandDissolvingConstant", &mut p.sand_dissolving),
        ("SedimentDepositionConstant", &mut p.deposition),
        ("MinSlopeErosionScale", &mut p.min_slope_erosion_scale),
        ("MaxSlopeErosionScale", &mut p.max_slope_erosion_scale),
        ("HorizontalErosionStrength", &mut p.horizontal_erosion_strength),
        ("Gravity", &mut p.gravity),
    ];
    for (key, field) in numbers {
        if let Some(v) = number(key) {
            *field = v as f32;
        }
    }
    // The reference stores gravity as a negative acceleration and talus angles in radians.
    p.gravity = p.gravity.abs();
    if let Some(v) = number("DryTalusAngle") {
        p.dry_talus_angle = v.to_degrees() as f32;
    }
    if let Some(v) = number("WetTalusAngle") {
        p.wet_talus_angle = v.to_degrees() as f32;
    }
    let flags: [(&str, &mut bool); 4] = [
        ("EnableSlippage", &mut p.slippage),
        ("EnableVerticalErosion", &mut p.vertical_erosion),
        ("EnableHorizontalErosion", &mut p.horizontal_erosion),
        ("EnableSupportCheck", &mut p.support_check),
    ];
    for (key, field) in flags {
        if let Some(v) = flag(key) {
            *field = v;
        }
    }
    p
}

/// What one [`MlhmSimulation::advance`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Advanced {
    /// Steps taken.
    pub steps: u32,
    /// Steps simulated in all, the scene's own included.
    pub step_count: u64,
    /// Milliseconds the steps took.
    pub step_ms: f64,
}

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
    /// The simulation of the scene at `path` (read within `max_memory`), as `relief
    /// simulate` starts it.
    pub fn open(path: &Path, max_memory: Option<u64>) -> Result<Self, RenderError> {
        let read = ReadSettings { max_memory, ..ReadSettings::default() };
        let scene = input::load_mlhm(path, &read)?;
        let params = scene_params(&scene.settings);
        params.validate().map_err(|source| RenderError::SimulationSettings {
            path: PathBuf::from(path),
            source,
        })?;
        let state = start_state(&scene, path, max_memory, BYTES_PER_SLOT)?;
        let map = &scene.mlhm;
        Ok(MlhmSimulation {
            state,
            rain: params.rain,
            params,
            initial_layers: map.max_layers(),
            precision: scene.precision,
        })
    }

    /// Takes `steps` steps (at least one, at most [`MAX_STEPS_PER_ADVANCE`]), and more while
    /// another is predicted to fit `budget`, with the rain on where `rain` says; the terrain
    /// after them, as `relief simulate` writes it.
    pub fn advance(
        &mut self,
        steps: u32,
        budget: Option<Duration>,
        rain: bool,
    ) -> Result<(Mlhm, Advanced), RenderError> {
        self.params.rain = if rain { self.rain } else { 0.0 };
        let started = Instant::now();
        let mut taken = 0u32;
        loop {
            self.state.step(&self.params, SEED)?;
            taken += 1;
            if taken >= MAX_STEPS_PER_ADVANCE {
                break;
            }
            if taken >= steps {
                let Some(budget) = budget else { break };
                let elapsed = started.elapsed();
                // Another step only if it is predicted to fit.
                if elapsed + elapsed / taken > budget {
                    break;
                }
            }
        }
        let step_ms = started.elapsed().as_secs_f64() * 1e3;
        let layers = self.state.used_layers().max(self.initial_layers);
        let mut map = self.state.to_mlhm_with_layers(layers)?;
        if self.precision != Precision::F32 {
            map = map.to_precision(self.precision).map_err(RenderError::Rounding)?;
        }
        let advanced = Advanced { steps: taken, step_count: self.state.step_count(), step_ms };
        Ok((map, advanced))
    }
}
