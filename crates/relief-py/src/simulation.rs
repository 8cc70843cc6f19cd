//! The erosion simulation of an MLHM scene opened from Python (relief_sim's erosion state,
//! started by the scene layer as `relief simulate` starts it), its parameters as `relief
//! simulate` takes them, the terrain it renders and the scene file it writes: the bytes
//! `relief simulate` writes after as many steps with the same seed.

use relief_core::{Mlhm, Precision};
use relief_io::MlhmScene;
use relief_render::input::load_mlhm;
use relief_render::simulation::{
    scene_params, start_state, write_scene, SceneTemplate, BYTES_PER_SLOT,
};
use relief_render::{ReadSettings, RenderError};
use relief_sim::erosion::{ErosionError, ErosionParams, ErosionState, SimulationPlanes};
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
    /// The scene it started from, whose states are written.
    template: SceneTemplate,
}

impl Simulation {
    /// The simulation of the scene at `path` (read within `max_memory`), as `relief
    /// simulate` starts it: its columns, saved planes and step count.
    pub fn start(path: &Path, max_memory: Option<u64>) -> Result<Self, RenderError> {
        let read = ReadSettings { max_memory, ..ReadSettings::default() };
        let scene = load_mlhm(path, &read)?;
        let state = start_state(&scene, path, max_memory, BYTES_PER_SLOT)?;
        Ok(Simulation { path: path.to_path_buf(), state, template: SceneTemplate::of(&scene) })
    }

    /// The scene's parameters (the reference defaults, its `Simulation/*` settings over them)
    /// with `overrides` over those, checked.
    pub fn params(&self, overrides: Overrides) -> Result<ErosionParams, RenderError> {
        let mut params = scene_params(self.template.settings());
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
        self.template.layers(&self.state)
    }

    /// The terrain at f32, in [`Simulation::layers`] layer planes.
    pub fn terrain(&self) -> Result<Mlhm, ErosionError> {
        self.state.to_mlhm_with_layers(self.layers())
    }

    /// The terrain as `relief simulate` writes it and `relief render` then reads it: at the
    /// scene's precision.
    pub fn drawn_terrain(&self) -> Result<Mlhm, RenderError> {
        let map = self.terrain()?;
        let precision = self.template.precision();
        if precision == Precision::F32 {
            return Ok(map);
        }
        map.to_precision(precision).map_err(RenderError::Rounding)
    }

    /// The simulator's planes, in [`Simulation::layers`] layer planes.
    pub fn planes(&self) -> SimulationPlanes {
        self.state.planes_with_layers(self.layers())
    }

    /// The scene file of the state, as `relief simulate` writes it: the scene's settings with
    /// the step count, the terrain in the layers it uses (at least the scene's), the planes.
    pub fn scene_file(&self) -> Result<MlhmScene, RenderError> {
        self.template.scene(&self.state)
    }

    /// Writes the state to `path` as `relief simulate -o path` does: a `.json` reference
    /// scene (with its `.dat` beside it, the simulation state and step count included) or a
    /// `.mlhm` (the terrain only, at the scene's precision).
    pub fn write(&self, path: &Path) -> Result<(), RenderError> {
        write_scene(path, &self.scene_file()?)
    }
}
