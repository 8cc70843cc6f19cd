//! The scene files of a simulation's states, as `relief simulate` and relief-py write them:
//! the scene it started from (its settings, layer capacity and precision) with the state's
//! step count, terrain and simulation planes.

use crate::error::RenderError;
use crate::input::{is_native_mlhm, is_reference_scene};
use relief_core::Precision;
use relief_io::{MlhmScene, SimulationState};
use relief_sim::erosion::ErosionState;
use serde_json::{Map, Value};
use std::path::Path;

/// The scene key holding the steps simulated so far (the reference simulator's).
pub const STEP_KEY: &str = "Simulation/CurrentSimulationStep";

/// What a simulation keeps of the scene it started from to write its states as scenes.
#[derive(Debug, Clone)]
pub struct SceneTemplate {
    /// The scene's settings (its `Simulation/*` ones included).
    settings: Map<String, Value>,
    /// The scene's layer capacity.
    max_layer_count: usize,
    /// The precision the scene is stored at.
    precision: Precision,
    /// The scene's own layer planes: a state is written in at least these.
    initial_layers: usize,
}

impl SceneTemplate {
    /// The template of `scene`.
    pub fn of(scene: &MlhmScene) -> Self {
        SceneTemplate {
            settings: scene.settings.clone(),
            max_layer_count: scene.max_layer_count,
            precision: scene.precision,
            initial_layers: scene.mlhm.max_layers(),
        }
    }

    /// The scene's settings.
    pub fn settings(&self) -> &Map<String, Value> {
        &self.settings
    }

    /// The precision the scene is stored at.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// Layer planes `state` is written in: the layers it uses, at least the scene's own.
    pub fn layers(&self, state: &ErosionState) -> usize {
        state.used_layers().max(self.initial_layers)
    }

    /// The scene file of `state`: the scene's settings with the step count, the terrain in
    /// [`SceneTemplate::layers`] layer planes, the simulation planes.
    pub fn scene(&self, state: &ErosionState) -> Result<MlhmScene, RenderError> {
        let layers = self.layers(state);
        let mlhm = state.to_mlhm_with_layers(layers)?;
        let planes = state.planes_with_layers(layers);
        let mut settings = self.settings.clone();
        settings.insert(STEP_KEY.into(), Value::from(state.step_count()));
        Ok(MlhmScene {
            mlhm,
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
}

/// Writes a simulated `scene` to `path` as `relief simulate -o path` does: a `.json`
/// reference scene (with its `.dat` beside it, the simulation state and step count included)
/// or a `.mlhm` (the terrain only, at the scene's precision).
pub fn write_scene(path: &Path, scene: &MlhmScene) -> Result<(), RenderError> {
    if is_reference_scene(path) {
        relief_io::write_mlhm_scene(path, scene)?;
    } else if is_native_mlhm(path) {
        let map = scene.mlhm.to_precision(scene.precision).map_err(RenderError::Rounding)?;
        relief_io::write_mlhm_native(path, &map)?;
    } else {
        return Err(RenderError::Unsupported(format!(
            "{}: a simulated scene is written as .json (the reference simulator's scene, with \
             its .dat beside it) or .mlhm",
            path.display()
        )));
    }
    Ok(())
}
