//! `relief.Scene`: any input relief takes, opened by the scene layer (relief_render::Scene),
//! drawn from a camera as `relief render` draws it; a height field's shade layers; an MLHM
//! scene's erosion state, stepped by `relief.simulate`, read as arrays and written as a file.

use crate::camera::{warn, warn_note, CameraSpec, SCENE_KEYS};
use crate::errors::{invalid, scene as scene_error};
use crate::info::{Crs, SceneInfo};
use crate::options;
use crate::picture::{arrays, check_image, Rendered};
use crate::shade::{layer_arrays, map_params, shade_field, SunTime};
use crate::simulation::{Overrides, Simulation};
use crate::state_arrays::{state_arrays, StateCopy};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_render::scenes::mlhm::{mlhm_base, mlhm_bounds};
use relief_render::{ImageHolding, KeptHits, Picture, RenderError, Scene, Silent, TracerChoice};
use relief_shade::horizon::HorizonParams;
use std::path::{Path, PathBuf};
use std::sync::{Arc, RwLock, RwLockReadGuard, RwLockWriteGuard};

/// A scene as it was opened, and its simulation once one has begun.
pub struct Opened {
    /// The scene.
    pub scene: Scene,
    /// The input, `None` for the default fBm terrain.
    pub path: Option<PathBuf>,
    /// The memory the input may take, bytes (`None`: the default).
    pub max_memory: Option<u64>,
    /// The CRS the input names, if any.
    pub crs: Option<Crs>,
    /// An MLHM scene's erosion simulation, from its first `simulate` (or `state`) on.
    pub simulation: Option<Simulation>,
}

/// A scene opened by ``relief.open``: a height field, an MLHM scene, a material-stacks
/// terrain or a tile store. ``render`` draws it as ``relief render`` does; ``shade`` makes a
/// height field's shade layers; ``info`` says what it is; ``state`` and ``write`` read and
/// save an MLHM scene's erosion state (stepped by ``relief.simulate``).
///
/// A scene may be used from several threads: renders run side by side, and a simulation
/// step waits for them (and they for it).
#[pyclass(name = "Scene", module = "relief", frozen)]
pub struct PyScene {
    opened: RwLock<Opened>,
}

impl PyScene {
    /// A Python scene of `opened`.
    pub fn new(opened: Opened) -> Self {
        PyScene { opened: RwLock::new(opened) }
    }

    /// The scene, to read (a thread that panicked while holding it left it as it was).
    fn locked(&self) -> RwLockReadGuard<'_, Opened> {
        self.opened.read().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// The scene, to change.
    fn locked_mut(&self) -> RwLockWriteGuard<'_, Opened> {
        self.opened.write().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Takes `steps` erosion steps of the MLHM scene (starting its simulation as `relief
    /// simulate` starts it, where none has begun) with the scene's parameters and
    /// `overrides`, the rain drawn from `seed`; the scene then draws the stepped terrain.
    /// Returns the steps simulated in all. The GIL is released meanwhile.
    pub fn simulate(
        &self,
        py: Python<'_>,
        steps: u64,
        seed: u64,
        overrides: Overrides,
    ) -> PyResult<u64> {
        let stepped = py.detach(|| {
            let mut opened = self.locked_mut();
            let opened = &mut *opened;
            let simulation = simulation_of(opened)?;
            let params = simulation.params(overrides)?;
            if let Err(e) = simulation.step(steps, &params, seed) {
                // A failed step leaves the state broken: the next call starts again from the
                // scene's file; the scene keeps drawing the terrain of the last call.
                opened.simulation = None;
                return Err(RenderError::Erosion(e));
            }
            // The solid ends where relief render ends the terrain a simulation writes.
            let mut map = simulation.drawn_terrain()?;
            map.set_base(mlhm_base(&map));
            let map = Arc::new(map);
            let step = simulation.state().step_count();
            let Scene::Mlhm(layered) = &mut opened.scene else {
                unreachable!("simulation_of refuses every scene but an MLHM scene")
            };
            let bounds = mlhm_bounds(&map)?;
            (layered.map, layered.bounds) = (map, bounds);
            Ok(step)
        });
        stepped.map_err(scene_error)
    }
}

/// The simulation of `opened`, started from its file where none has begun; refused for any
/// scene but an MLHM scene.
fn simulation_of(opened: &mut Opened) -> Result<&mut Simulation, RenderError> {
    let (Scene::Mlhm(_), Some(path)) = (&opened.scene, &opened.path) else {
        return Err(RenderError::Unsupported(format!(
            "relief.simulate, Scene.state and Scene.write take MLHM scenes (.json, .mlhm); this \
             is a {}",
            opened.scene.describe()
        )));
    };
    if opened.simulation.is_none() {
        opened.simulation = Some(Simulation::start(path, opened.max_memory)?);
    }
    Ok(opened.simulation.as_mut().expect("started above"))
}

/// How the renderer of `scene` holds its picture (for the memory check): strip by strip for
/// a height field's ray casters, a whole G-buffer for the hybrid and clipmap renderers,
/// meshes and tile stores, an MLHM renderer's buffers for an MLHM scene.
fn holding(scene: &Scene) -> ImageHolding {
    match scene {
        Scene::HeightField(s)
            if matches!(s.choice, TracerChoice::Hybrid | TracerChoice::Clipmap) =>
        {
            ImageHolding::WholeGBuffer
        }
        Scene::HeightField(_) => ImageHolding::Strips { depth: true, normals: false },
        Scene::Mlhm(_) => ImageHolding::Mlhm,
        Scene::Stacks(_) | Scene::Store(_) => ImageHolding::WholeGBuffer,
    }
}

/// A picture and what its camera made the scene layer say.
struct Drawn {
    picture: Picture,
    /// The note on a replaced up vector.
    note: Option<String>,
    /// The warning of an eye inside the terrain.
    inside: Option<String>,
}

#[pymethods]
impl PyScene {
    /// Renders the scene as ``relief render`` does, with the same defaults: ``(rgb, depth)``.
    ///
    /// ``camera``: ``None`` for relief's framing (a three-quarter view from the south-west,
    /// 30 degrees up), or a dict of ``eye`` and ``target`` (x, y, z), ``up`` (default 0, 0,
    /// 1), ``fov`` (vertical, degrees, default 45), ``view`` (``(azimuth, elevation)`` or
    /// ``(azimuth, elevation, distance)``: the framing from that compass direction, towards
    /// ``target`` where given), ``ortho`` (an orthographic camera) and ``ortho_height`` (its
    /// image's height, metres), as ``--eye``, ``--target``, ``--up``, ``--fov``, ``--view``,
    /// ``--ortho`` and ``--ortho-height``. ``size``: ``(width, height)`` in pixels.
    ///
    /// Returns ``rgb``, a uint8 array (height, width, 3), and ``depth``, a float32 array
    /// (height, width) of the distance from the eye to each pixel's first hit, +inf for a
    /// miss: the picture ``relief render`` writes for the same input, options and camera,
    /// pixel for pixel. An eye inside the terrain, or an up along the view, is warned of
    /// (``UserWarning``). The GIL is released while the scene is drawn.
    ///
    /// ``legend``, ``scale_bar`` and ``north_arrow`` draw that furniture over the picture as
    /// ``relief render --legend --scale-bar --north-arrow`` does: a legend of the colour map
    /// (``relief.open(..., colormap=...)``), a scale bar for an orthographic camera, a north
    /// arrow where north does not run along the view; ``relief.ReliefError`` where the scene
    /// or the camera does not define one. ``aa``: anti-aliasing, ``"adaptive"`` (the
    /// default), ``"off"`` or N for N x N rays a pixel, as ``relief render --aa``.
    /// ``threads``: how many threads draw (None: all the processor's, shared by the calls of
    /// the process; ``relief.dask.flythrough`` gives each frame one); the picture is the same
    /// for any.
    #[pyo3(signature = (
        camera=None, size=(1280, 720), *, legend=false, scale_bar=false, north_arrow=false,
        aa=None, threads=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        camera: Option<&Bound<'py, PyDict>>,
        size: (i64, i64),
        legend: bool,
        scale_bar: bool,
        north_arrow: bool,
        aa: Option<&Bound<'py, PyAny>>,
        threads: Option<usize>,
    ) -> PyResult<Rendered<'py>> {
        let furniture = options::furniture(legend, scale_bar, north_arrow);
        let (width, height) = options::image_size(size)?;
        let aa = aa.map(options::antialiasing).transpose()?.unwrap_or_default();
        let spec = CameraSpec::from_dict(camera, SCENE_KEYS)?;
        let options = spec.options(width, height);
        let (holding, max_memory) = py.detach(|| {
            let opened = self.locked();
            (holding(&opened.scene), opened.max_memory)
        });
        let raise_with = Some("relief.open(..., max_memory=N)");
        check_image(width, height, holding, aa, max_memory, raise_with)?;
        let drawn = py.detach(|| {
            options::on_threads(threads, || {
                let opened = self.locked();
                let scene = &opened.scene;
                let placed = scene.camera(&options)?;
                let inside = scene.camera_warning(&placed.camera);
                let keep = KeptHits { depth: true, normals: false };
                let colours = scene.height_colours();
                furniture.check(&placed.camera, colours.as_ref())?;
                let mut picture = scene.render(&placed.camera, keep, aa, &Silent)?;
                furniture.draw(&mut picture, &placed.camera, colours.as_ref())?;
                Ok::<_, RenderError>(Drawn { picture, note: placed.note, inside })
            })
        })?;
        let drawn = drawn.map_err(scene_error)?;
        warn_note(py, drawn.note.as_deref())?;
        for line in drawn.inside.iter().chain(&drawn.picture.notes) {
            if let Some(message) = line.strip_prefix("warning: ") {
                warn(py, message)?;
            }
        }
        arrays(py, drawn.picture)
    }

    /// The shade layers of a height-field scene, each a float32 array of its grid, row 0 the
    /// north edge, as ``relief.shade`` makes them of the scene's terrain (its surface, as
    /// placed when opened), with the same keywords: ``layers``, ``suns`` as ``(azimuth,
    /// elevation)`` in degrees, each of ``sun_radius`` degrees sampled by ``sun_rays`` rays;
    /// the horizons' ``azimuths``, ``observer_height``, ``radius`` and ``earth_curvature``;
    /// ``sky_model``; the sun from ``date``, ``time``, ``timezone``, ``step``, ``latitude``
    /// and ``longitude``. NaN where the scene keeps a void as a hole (opened with
    /// ``voids="hole"``).
    ///
    /// Raises ``relief.ReliefError`` for any other scene (an MLHM scene, a stacks terrain, a
    /// tile store).
    #[pyo3(signature = (
        layers=vec!["combined".to_string()], suns=vec![(315.0, 45.0)], sun_radius=0.0,
        sun_rays=16, azimuths=32, observer_height=0.01, radius=None, earth_curvature=None,
        sky_model="overcast", date=None, time=None, timezone="Z", step="15m", latitude=None,
        longitude=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn shade<'py>(
        &self,
        py: Python<'py>,
        layers: Vec<String>,
        suns: Vec<(f64, f64)>,
        sun_radius: f64,
        sun_rays: u32,
        azimuths: u32,
        observer_height: f64,
        radius: Option<f64>,
        earth_curvature: Option<f64>,
        sky_model: &str,
        date: Option<&str>,
        time: Option<&str>,
        timezone: &str,
        step: &str,
        latitude: Option<f64>,
        longitude: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let when = SunTime { date, time, timezone, step, latitude, longitude };
        let horizon =
            HorizonParams { azimuths, observer_height, radius, refraction: earth_curvature };
        let params = map_params(layers, suns, sun_radius, sun_rays, horizon, sky_model, &when)?;
        let map = py.detach(|| {
            let opened = self.locked();
            let Scene::HeightField(scene) = &opened.scene else {
                return Err(format!(
                    "Scene.shade makes the shade layers of height fields; this is a {}",
                    opened.scene.describe()
                ));
            };
            params.check_surface(scene.surface).map_err(|e| e.to_string())?;
            shade_field(&scene.field, scene.surface, scene.field.holes(), &params)
        });
        layer_arrays(py, map.map_err(invalid)?)
    }

    /// What the scene is, as a dict: ``kind`` (``"height_field"``, ``"mlhm"``, ``"stacks"``
    /// or ``"tile_store"``), ``description``, ``path`` (``None`` for the default fBm
    /// terrain), ``size`` (samples or cells along x and y) and ``spacing`` (dx, dy in world
    /// units; both ``None`` for a stacks terrain), ``bounds`` (``((x, y, z), (x, y, z))``, the
    /// lowest and highest corners of the box the drawn surfaces fill), ``crs`` and ``epsg``
    /// (what a height file names, else ``None``), ``warnings`` (what opening it found); a
    /// height field's ``surface`` and ``tracer``; an MLHM scene's ``layers`` (layer planes)
    /// and ``step`` (steps simulated so far).
    #[getter]
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let info = py.detach(|| {
            let opened = self.locked();
            let layers_and_step = match (&opened.scene, &opened.simulation) {
                (_, Some(s)) => Some((s.layers(), s.state().step_count())),
                (Scene::Mlhm(layered), None) => {
                    Some((layered.map.max_layers(), first_step(&opened)))
                }
                _ => None,
            };
            SceneInfo::of(
                &opened.scene,
                opened.path.as_deref(),
                opened.crs.clone(),
                layers_and_step,
            )
        });
        info.to_dict(py)
    }

    /// An MLHM scene's erosion state as NumPy arrays (its file's, before any step), a dict:
    ///
    /// - ``bedrock``, ``sand``, ``water``, ``ceiling``: float32 ``(L, H, W)``, column ``k`` of
    ///   cell ``(x, y)`` at ``[k, y, x]`` (``y`` northwards: row 0 is the south edge, as the
    ///   scene file stores it): the bedrock's top (m), the sand and water on it (m), and
    ///   where its air ends (the next column's floor; +inf for a cell's top column);
    /// - ``sediment``, ``damage``, ``stability``: float32 ``(L, H, W)``: suspended sediment
    ///   (m), horizontal-erosion damage (m), the support check's stability;
    /// - ``fluxes``: float32 ``(L, H, W, 4)``: the pipes' outflow (m³/s) right (+x), up (+y),
    ///   left and down;
    /// - ``layer_counts``: uint8 ``(H, W)``: columns of each cell; slots ``k`` at or above a
    ///   cell's count are zero;
    /// - ``step``: steps simulated so far; ``cell_size``: metres.
    ///
    /// ``L`` is the layer planes the scene file holds (``info["layers"]``).
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let copy = py.detach(|| {
            let mut opened = self.locked_mut();
            let simulation = simulation_of(&mut opened)?;
            StateCopy::of(simulation)
        });
        state_arrays(py, copy.map_err(scene_error)?)
    }

    /// Writes an MLHM scene's state to ``path`` as ``relief simulate -o path`` writes it: a
    /// ``.json`` reference scene (with its ``.dat`` beside it, the simulation state and step
    /// count included, so that ``relief simulate`` continues it) or a ``.mlhm`` (the terrain
    /// only). After ``relief.simulate(scene, N, seed=S)`` the files are the bytes ``relief
    /// simulate SCENE --steps N --seed S`` writes.
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let written = py.detach(|| {
            let mut opened = self.locked_mut();
            simulation_of(&mut opened)?.write(&path)
        });
        written.map_err(scene_error)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let (description, path) = py.detach(|| {
            let opened = self.locked();
            (
                opened.scene.describe(),
                opened.path.as_deref().map(Path::display).map(|p| p.to_string()),
            )
        });
        match path {
            Some(path) => format!("<relief.Scene: {description} ({path})>"),
            None => format!("<relief.Scene: {description}>"),
        }
    }
}

/// The steps an MLHM scene's file says were simulated, read again (0 where it says none).
fn first_step(opened: &Opened) -> u64 {
    let Some(path) = &opened.path else { return 0 };
    let header = match relief_render::input::is_reference_scene(path) {
        true => relief_io::mlhm::read_mlhm_scene_header(path).ok(),
        false => None,
    };
    header
        .and_then(|h| h.settings.get(relief_render::simulation::STEP_KEY).and_then(|v| v.as_u64()))
        .unwrap_or(0)
}
