//! An MLHM scene drawn live: boxes or the smooth surface, by the hierarchy or the naive
//! tracer (built when first asked for, then kept), shaded at the preset the viewer selects;
//! and its erosion simulation, run, paused and stepped from the viewer (the state made when
//! first asked for; after each request's steps the terrain is converted back to an MLHM and
//! the tracers, hierarchy included, are built anew over it).

use super::drawing::Drawing;
use super::tracer_cache::TracerCache;
use super::view_shading::viewer_sun;
use crate::{
    Cancel, Frame, FrameStats, SceneChoices, SimulationReport, SimulationRequest, ViewSettings,
};
use relief_core::Camera;
use relief_render::draw::mlhm::mlhm_frame;
use relief_render::simulation::MlhmSimulation;
use relief_render::{LayeredScene, MlhmTracerChoice, RenderError, RenderMode};
use relief_shade::mlhm::{MlhmPreset, MlhmShading};
use relief_trace::adapters::Interruptible;
use relief_trace::MlhmTracer;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, RwLock};

/// The modes an MLHM scene offers, in the order the viewer cycles them.
const MODES: [(RenderMode, &str); 2] =
    [(RenderMode::Boxes, "boxes"), (RenderMode::Smooth, "smooth")];

/// A tracer: the mode it draws, the choice of tracer, and whether the smooth surface's
/// normals are central differences.
type TracerKey = (usize, usize, bool);

/// An MLHM scene and the tracers drawing it.
pub struct LiveMlhm {
    /// The scene; its map is replaced as the simulation advances.
    scene: RwLock<LayeredScene>,
    /// The scene in words, as it opened.
    describe: String,
    /// The diagonal of the scene's bounds as it opened, metres.
    size: f64,
    /// The tracers offered: the hierarchy (with the scene's options) and the naive one.
    choices: [(MlhmTracerChoice, &'static str); 2],
    /// The tracers built so far (over the current map).
    built: TracerCache<TracerKey, dyn MlhmTracer>,
    /// The simulation, once made.
    simulation: Mutex<Option<MlhmSimulation>>,
}

impl LiveMlhm {
    /// Draws `scene`; its options leaving out shadows and ambient occlusion leave them out of
    /// every preset (shadows can be switched back on in the viewer).
    pub fn new(scene: LayeredScene) -> Self {
        let hierarchy = match scene.choice {
            MlhmTracerChoice::Hierarchy(..) => scene.choice,
            MlhmTracerChoice::Naive => {
                MlhmTracerChoice::Hierarchy(Default::default(), relief_core::Precision::F32)
            }
        };
        let choices = [(hierarchy, "hierarchy"), (MlhmTracerChoice::Naive, "naive")];
        let describe = scene.describe();
        let size = (scene.bounds.max - scene.bounds.min).length();
        LiveMlhm {
            scene: RwLock::new(scene),
            describe,
            size,
            choices,
            built: TracerCache::new(HashMap::new()),
            simulation: Mutex::new(None),
        }
    }

    /// The scene, read.
    fn scene(&self) -> std::sync::RwLockReadGuard<'_, LayeredScene> {
        self.scene.read().expect("no render panicked")
    }

    /// The viewer's starting settings: the scene's mode, tracer, preset, sun, exposure and
    /// shadows.
    pub fn settings(&self) -> ViewSettings {
        let names = SceneChoices {
            tracers: self.choices.iter().map(|(_, name)| name.to_string()).collect(),
            modes: MODES.iter().map(|(_, name)| name.to_string()).collect(),
            presets: MlhmPreset::ALL.iter().map(|p| p.name().to_string()).collect(),
            ..SceneChoices::default()
        };
        let scene = self.scene();
        let shading = &scene.shading;
        let sun = (shading.sun.azimuth_deg, shading.sun.elevation_deg);
        // The preset decides whether there are shadows at all; this switch can only take them
        // away, as --no-shadows does.
        let mut settings = ViewSettings::new(names, sun, shading.exposure, !scene.no_shadows);
        settings.tracer = usize::from(scene.choice == MlhmTracerChoice::Naive);
        settings.mode = MODES.iter().position(|(m, _)| *m == scene.mode).unwrap_or(0);
        settings.preset = MlhmPreset::ALL.iter().position(|p| *p == scene.preset).unwrap_or(0);
        settings
    }

    /// The shading of `settings`: its preset with the viewer's sun, exposure and shadows.
    fn shading(&self, settings: &ViewSettings) -> MlhmShading {
        let preset = MlhmPreset::ALL[settings.preset.min(MlhmPreset::ALL.len() - 1)];
        let mut shading = MlhmShading::new(preset);
        shading.sun = viewer_sun(shading.sun, settings);
        shading.quality.shadows &= settings.shadows;
        if self.scene().no_ao {
            shading.quality.ao_radius = None;
        }
        shading.exposure = settings.exposure;
        shading
    }
}

impl Drawing for LiveMlhm {
    fn describe(&self) -> String {
        self.describe.clone()
    }

    fn scene_size(&self) -> f64 {
        self.size
    }

    fn draw(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        cancel: &Cancel,
    ) -> Result<Frame, RenderError> {
        let shading = self.shading(settings);
        let mode = settings.mode.min(MODES.len() - 1);
        let choice = settings.tracer.min(self.choices.len() - 1);
        // Only the smooth surface's normals depend on the preset.
        let central = MODES[mode].0 == RenderMode::Smooth && shading.quality.central_differences;
        let built = self.built.get_or_build((mode, choice, central), || {
            let tracer = self.scene().tracer(MODES[mode].0, self.choices[choice].0, central)?;
            Ok(Arc::from(tracer))
        })?;
        let tracer = Interruptible { inner: built.as_ref(), stop: cancel.flag() };
        let frame = mlhm_frame(&tracer, camera, &shading)?;
        let stats = FrameStats {
            rays: frame.counts.rays(),
            steps_per_ray: Some(frame.counts.primary.mean_steps()),
        };
        let (width, height) = (camera.width(), camera.height());
        Ok(Frame { width, height, rgb: frame.rgb, stats, note: None })
    }

    fn has_simulation(&self) -> bool {
        true
    }

    /// Takes the simulation's steps `request` asks for (making the simulation first, if this
    /// is its first request) and puts the terrain after them in the scene.
    fn simulate(&self, request: &SimulationRequest) -> Result<SimulationReport, RenderError> {
        let mut simulation = self.simulation.lock().expect("no step panicked");
        if simulation.is_none() {
            let scene = self.scene();
            *simulation = Some(MlhmSimulation::open(&scene.path, scene.max_memory)?);
        }
        let running = simulation.as_mut().expect("made above");
        let (mut map, advanced) = running.advance(request.steps, request.budget, request.rain)?;
        let mut scene = self.scene.write().expect("no render panicked");
        // The solid ends where it ended as the scene opened (lower if erosion dug deeper).
        map.set_base(scene.map.base());
        scene.map = Arc::new(map);
        drop(scene);
        // The tracers, hierarchy included, are built anew over the new terrain.
        self.built.clear();
        let report = SimulationReport {
            steps: advanced.steps,
            step_count: advanced.step_count,
            step_ms: advanced.step_ms,
        };
        Ok(report)
    }
}
