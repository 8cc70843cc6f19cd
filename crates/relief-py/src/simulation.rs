//! The erosion simulation of an MLHM scene opened from Python (relief_sim's erosion state,
//! started by the scene layer as `relief simulate` starts it), its parameters as `relief
//! simulate` takes them, the terrain it renders and the scene file it writes: the bytes
//! `relief simulate` writes after as many steps with the same seed.

use relief_core::{Mlhm, Precision};
use relief_io::{MlhmScene, SimulationState};
use relief_render::input::{is_native_mlhm, is_reference_scene, load_mlhm};
use relief_render::simulation::{scene_params, start_state, BYTES_PER_SLOT, STEP_KEY};
use relief_render::{ReadSettings, RenderError};
use relief_sim::erosion::{ErosionError, ErosionParams, ErosionState, SimulationPlanes};
use serde_json::{Map, Value};
use std::path::{Path, PathBuf};

/// What a caller may change of a scene's simulation settings for a run (`None`: the scene's,
/// else the reference defaults), as `relief simulate`'s `--rain`, `--evaporation` and `--dt`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Overrides {
    /// Rain, metres of water per second.
    pub rain: Option<f32>,
    /// Evaporation, metres of water per second.
    pub evaporation: Option<f32>,
    /// Time step, seconds.
    pub dt: Option<f32>,
}

/// A running simulation of the MLHM scene read from `path`.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The scene file it started from.
    path: PathBuf,
    /// The terrain and the simulator's planes.
    state: ErosionState,
    /// The scene's settings (its `Simulation/*` ones included).
    settings: Map<String, Value>,
    /// The scene's layer capacity.
    max_layer_count: usize,
    /// The precision the scene is stored at.
    precision: Precision,
    /// The scene's own layer planes: the terrain written has at least these.
    initial_layers: usize,
}

impl Simulation {
    /// The simulation of the scene at `path` (read within `max_memory`), as `relief
    /// simulate` starts it: its columns, saved planes and step count.
    pub fn start(path: &Path, max_memory: Option<u64>) -> Result<Self, RenderError> {
        let read = ReadSettings { max_memory, ..ReadSettings::default() };
        let scene = load_mlhm(path, &read)?;
        let state = start_state(&scene, path, max_memory, BYTES_PER_SLOT)?;
        Ok(Simulation {
            path: path.to_path_buf(),
            state,
            initial_layers: scene.mlhm.max_layers(),
            settings: scene.settings,
            max_layer_count: scene.max_layer_count,
            precision: scene.precision,
        })
    }

    /// The scene's parameters (the reference defaults, its `Simulation/*` settings over them)
    /// with `overrides` over those, checked.
    pub fn params(&self, overrides: Overrides) -> Result<ErosionParams, RenderError> {
        let mut params = scene_params(&self.settings);
        params.rain = overrides.rain.unwrap_or(params.rain);
        params.evaporation = overrides.evaporation.unwrap_or(params.evaporation);
        params.dt = overrides.dt.unwrap_or(params.dt);
        params.validate().map_err(|source| RenderError::SimulationSettings {
            path: self.path.clone(),
            source,
        })?;
        Ok(params)
    }

    /// Takes `steps` steps with `params`, the rain's random numbers drawn from `seed`. A step
    /// that fails leaves the state broken: the caller drops it.
    pub fn step(
        &mut self,
        steps: u64,
        params: &ErosionParams,
        seed: u64,
    ) -> Result<(), ErosionError> {
        for _ in 0..steps {
            self.state.step(params, seed)?;
        }
        Ok(())
    }

    /// The state: the terrain, the planes and the step count.
    pub fn state(&self) -> &ErosionState {
        &self.state
    }

    /// Layer planes of the terrain as written: the layers it uses, at least the scene's own.
    pub fn layers(&self) -> usize {
        self.state.used_layers().max(self.initial_layers)
    }

    /// The terrain at f32, in [`Simulation::layers`] layer planes.
    pub fn terrain(&self) -> Result<Mlhm, ErosionError> {
        self.state.to_mlhm_with_layers(self.layers())
    }

    /// The terrain as `relief simulate` writes it and `relief render` then reads it: at the
    /// scene's precision.
    pub fn drawn_terrain(&self) -> Result<Mlhm, RenderError> {
        let map = self.terrain()?;
        if self.precision == Precision::F32 {
            return Ok(map);
        }
        map.to_precision(self.precision).map_err(RenderError::Rounding)
    }

    /// The simulator's planes, in [`Simulation::layers`] layer planes.
    pub fn planes(&self) -> SimulationPlanes {
        self.state.planes_with_layers(self.layers())
    }

    /// The scene file of the state, as `relief simulate` writes it: the scene's settings with
    /// the step count, the terrain in the layers it uses (at least the scene's), the planes.
    pub fn scene_file(&self) -> Result<MlhmScene, RenderError> {
        let layers = self.layers();
        let planes = self.planes();
        let mut settings = self.settings.clone();
        settings.insert(STEP_KEY.into(), Value::from(self.state.step_count()));
        Ok(MlhmScene {
            mlhm: self.terrain()?,
            max_layer_count: self.max_layer_count.max(layers),
            precision: self.precision,
            simulation: Some(SimulationState {
                fluxes: planes.fluxes,
                stability: planes.stability,
                sediment: planes.sediment,
                damage: planes.damage,
            }),
            settings,
            repaired: 0,
        })
    }

    /// Writes the state to `path` as `relief simulate -o path` does: a `.json` reference
    /// scene (with its `.dat` beside it, the simulation state and step count included) or a
    /// `.mlhm` (the terrain only, at the scene's precision).
    pub fn write(&self, path: &Path) -> Result<(), RenderError> {
        let scene = self.scene_file()?;
        if is_reference_scene(path) {
            relief_io::write_mlhm_scene(path, &scene)?;
        } else if is_native_mlhm(path) {
            let map = scene.mlhm.to_precision(scene.precision).map_err(RenderError::Rounding)?;
            relief_io::write_mlhm_native(path, &map)?;
        } else {
            return Err(RenderError::Unsupported(format!(
                "{}: a simulated scene is written as .json (the reference simulator's scene, \
                 with its .dat beside it) or .mlhm",
                path.display()
            )));
        }
        Ok(())
    }
}
