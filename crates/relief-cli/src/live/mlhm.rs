//! An MLHM scene drawn live: boxes or the smooth surface, by the hierarchy or the naive
//! tracer (built when first asked for, then kept), shaded at the preset the viewer selects;
//! and its erosion simulation, run, paused and stepped from the viewer (the state made when
//! first asked for; after each request's steps the terrain is converted back to an MLHM and
//! the tracers, hierarchy included, are built anew over it).

use super::simulation::MlhmSimulation;
use anyhow::Result;
use relief_core::Camera;
use relief_render::{LayeredScene, MlhmTracerChoice, RenderMode as MlhmRenderMode};
use relief_shade::mlhm::{render_mlhm, MlhmPreset, MlhmShading};
use relief_shade::tonemap_reinhard_to_rgb8;
use relief_trace::adapters::Interruptible;
use relief_trace::MlhmTracer;
use relief_viewer::{
    Cancel, Frame, FrameStats, SceneChoices, SceneRenderer, SimulationReport, SimulationRequest,
    ViewSettings,
};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, RwLock};

/// The modes an MLHM scene offers, in the order the viewer cycles them.
const MODES: [(MlhmRenderMode, &str); 2] =
    [(MlhmRenderMode::Boxes, "boxes"), (MlhmRenderMode::Smooth, "smooth")];

/// A tracer: the mode it draws, the choice of tracer, and whether the smooth surface's
/// normals are central differences.
type TracerKey = (usize, usize, bool);

/// An MLHM scene and the tracers drawing it.
pub struct LiveMlhm {
    /// The scene; its map is replaced as the simulation advances.
    scene: RwLock<LayeredScene>,
    /// The scene's size in cells, as it opened.
    cells: (usize, usize),
    /// The diagonal of the scene's bounds as it opened, metres.
    size: f64,
    /// The tracers offered: the hierarchy (with the command line's options) and the naive one.
    choices: [(MlhmTracerChoice, &'static str); 2],
    /// Whether the command line left out shadows.
    no_shadows: bool,
    /// Whether the command line left out ambient occlusion.
    no_ao: bool,
    /// The tracers built so far (over the current map).
    built: Mutex<HashMap<TracerKey, Arc<dyn MlhmTracer>>>,
    /// The scene file and the memory limit the simulation is made from, if it may run.
    source: Option<(PathBuf, Option<u64>)>,
    /// The simulation, once made.
    simulation: Mutex<Option<MlhmSimulation>>,
}

impl LiveMlhm {
    /// Draws `scene`; `no_shadows` and `no_ao` leave out every preset's shadows and ambient
    /// occlusion (shadows can be switched back on in the viewer).
    pub fn new(scene: LayeredScene, no_shadows: bool, no_ao: bool) -> Self {
        let hierarchy = match scene.choice {
            MlhmTracerChoice::Hierarchy(..) => scene.choice,
            MlhmTracerChoice::Naive => {
                MlhmTracerChoice::Hierarchy(Default::default(), relief_core::Precision::F32)
            }
        };
        let choices = [(hierarchy, "hierarchy"), (MlhmTracerChoice::Naive, "naive")];
        let cells = (scene.map.width(), scene.map.height());
        let size = (scene.bounds.max - scene.bounds.min).length();
        LiveMlhm {
            scene: RwLock::new(scene),
            cells,
            size,
            choices,
            no_shadows,
            no_ao,
            built: Mutex::new(HashMap::new()),
            source: None,
            simulation: Mutex::new(None),
        }
    }

    /// Lets the viewer run the erosion simulation of the scene file `path` (read within
    /// `max_memory`), as `relief simulate` runs it.
    pub fn with_simulation(mut self, path: PathBuf, max_memory: Option<u64>) -> Self {
        self.source = Some((path, max_memory));
        self
    }

    /// The scene, read.
    fn scene(&self) -> std::sync::RwLockReadGuard<'_, LayeredScene> {
        self.scene.read().expect("no render panicked")
    }

    /// Takes the simulation's steps `request` asks for (making the simulation first, if this
    /// is its first request) and puts the terrain after them in the scene.
    fn advance(&self, request: &SimulationRequest) -> Result<SimulationReport> {
        let Some((path, max_memory)) = &self.source else {
            anyhow::bail!("this scene has no simulation");
        };
        let mut simulation = self.simulation.lock().expect("no step panicked");
        if simulation.is_none() {
            *simulation = Some(MlhmSimulation::open(path, *max_memory)?);
        }
        let (map, report) = simulation.as_mut().expect("made above").advance(request)?;
        self.scene.write().expect("no render panicked").map = Arc::new(map);
        // The tracers, hierarchy included, are built anew over the new terrain.
        self.built.lock().expect("no render panicked").clear();
        Ok(report)
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
        let mut settings = ViewSettings::new(names, sun, shading.exposure, !self.no_shadows);
        settings.tracer = usize::from(scene.choice == MlhmTracerChoice::Naive);
        settings.mode = MODES.iter().position(|(m, _)| *m == scene.mode).unwrap_or(0);
        settings.preset = MlhmPreset::ALL.iter().position(|p| *p == scene.preset).unwrap_or(0);
        settings
    }

    /// The shading of `settings`: its preset with the viewer's sun, exposure and shadows.
    fn shading(&self, settings: &ViewSettings) -> MlhmShading {
        let preset = MlhmPreset::ALL[settings.preset.min(MlhmPreset::ALL.len() - 1)];
        let mut shading = MlhmShading::new(preset);
        shading.sun = super::viewer_sun(shading.sun, settings);
        shading.quality.shadows &= settings.shadows;
        if self.no_ao {
            shading.quality.ao_radius = None;
        }
        shading.exposure = settings.exposure;
        shading
    }

    /// The tracer of `key`, built now if it was not yet.
    fn tracer(&self, key: TracerKey) -> Result<Arc<dyn MlhmTracer>> {
        let mut built = self.built.lock().expect("no render panicked");
        if let Some(tracer) = built.get(&key) {
            return Ok(tracer.clone());
        }
        let (mode, choice, central) = key;
        let tracer: Arc<dyn MlhmTracer> =
            Arc::from(self.scene().tracer(MODES[mode].0, self.choices[choice].0, central)?);
        built.insert(key, tracer.clone());
        Ok(tracer)
    }

    /// The frame of `camera` with `settings`, its tracer stopped by `cancel`.
    fn render_frame(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        cancel: &Cancel,
    ) -> Result<Frame> {
        let shading = self.shading(settings);
        let mode = settings.mode.min(MODES.len() - 1);
        let choice = settings.tracer.min(self.choices.len() - 1);
        // Only the smooth surface's normals depend on the preset.
        let central =
            MODES[mode].0 == MlhmRenderMode::Smooth && shading.quality.central_differences;
        let built = self.tracer((mode, choice, central))?;
        let tracer = Interruptible { inner: built.as_ref(), stop: cancel.flag() };
        let image = render_mlhm(&tracer, camera, &shading, &|_| {})?;
        let rgb = tonemap_reinhard_to_rgb8(&image.radiance, shading.exposure)?;
        let stats = FrameStats {
            rays: image.counts.rays(),
            steps_per_ray: Some(image.counts.primary.mean_steps()),
        };
        let rgb = rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
        Ok(Frame { width: camera.width(), height: camera.height(), rgb, stats, note: None })
    }
}

impl SceneRenderer for LiveMlhm {
    fn describe(&self) -> String {
        format!("{}x{} MLHM scene", self.cells.0, self.cells.1)
    }

    fn scene_size(&self) -> f64 {
        self.size
    }

    fn render(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        cancel: &Cancel,
    ) -> Result<Frame, String> {
        self.render_frame(camera, settings, cancel).map_err(|e| format!("{e:#}"))
    }

    fn has_simulation(&self) -> bool {
        self.source.is_some()
    }

    fn simulate(&self, request: &SimulationRequest) -> Result<SimulationReport, String> {
        self.advance(request).map_err(|e| format!("simulation: {e:#}"))
    }
}
