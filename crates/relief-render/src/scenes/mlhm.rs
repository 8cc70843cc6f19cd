//! A multi-layered height map scene to draw: the map, how its columns are drawn (boxes or the
//! smooth surface), the tracer, and the shading preset (Nilles & Müller 2025, sections 4.6
//! and 5).

use crate::error::RenderError;
use crate::input;
use crate::options::{refuse_shading_normals, RenderMode, SceneOptions};
use crate::tracer_spec::TracerChoice;
use relief_core::{Aabb, Camera, DVec2, DVec3, Mlhm, Precision};
use relief_shade::mlhm::{MlhmPreset, MlhmShading};
use relief_shade::Sun;
use relief_trace::{
    MlhmBacktrack, MlhmHierarchyTracer, MlhmMode, MlhmNaiveTracer, MlhmNormalScheme,
    MlhmSmoothOptions, MlhmSmoothTracer, MlhmTracer, TracerKind,
};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The MLHM tracers a scene may be drawn with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MlhmTracerChoice {
    /// Every column of every cell the ray crosses.
    Naive,
    /// The hierarchy of bounds, climbing back up as it says, its bounds stored at a precision.
    Hierarchy(MlhmBacktrack, Precision),
}

/// An MLHM scene opened to draw.
pub struct LayeredScene {
    /// The map.
    pub map: Arc<Mlhm>,
    /// Boxes or the smooth surface (default: boxes).
    pub mode: RenderMode,
    /// The tracer (default: the hierarchy, stack backtracking, f32 bounds).
    pub choice: MlhmTracerChoice,
    /// The smoothing radius of the smooth surface, metres (default: one cell).
    pub sigma: Option<f64>,
    /// The quality preset (default: mid).
    pub preset: MlhmPreset,
    /// The preset's shading with the options' sun, exposure, shadows and AO.
    pub shading: MlhmShading,
    /// A finite box holding every visible surface.
    pub bounds: Aabb,
    /// The scene's file, which its simulation starts from.
    pub path: PathBuf,
    /// The memory the scene (and its simulation) may take, bytes [default: the budget's].
    pub max_memory: Option<u64>,
    /// Whether the options left every preset's shadows out.
    pub no_shadows: bool,
    /// Whether the options left every preset's ambient occlusion out.
    pub no_ao: bool,
}

/// The scene has no georeference: cell (x, y) covers [x s, (x + 1) s) x [y s, (y + 1) s).
const ORIGIN: DVec2 = DVec2::ZERO;

impl LayeredScene {
    /// Reads the MLHM scene at `path` as `options` say.
    pub fn open(path: &Path, options: &SceneOptions) -> Result<Self, RenderError> {
        options.light.colours.refuse_for("MLHM scenes")?;
        refuse_shading_normals(&options.light, "MLHM scenes")?;
        let mode = options.mode.unwrap_or(RenderMode::Boxes);
        if mode == RenderMode::Mesh {
            return Err(RenderError::Unsupported(
                "--mode mesh is drawn by relief render and written by relief mesh, not here".into(),
            ));
        }
        let choice = tracer_choice(options)?;
        let preset = options.mlhm.preset.unwrap_or_default();
        let mut shading = MlhmShading::new(preset);
        let light = &options.light;
        let (azimuth_deg, elevation_deg) = light.sun;
        shading.sun = Sun { azimuth_deg, elevation_deg, ..shading.sun };
        shading.quality.shadows &= !light.no_shadows;
        if options.mlhm.no_ao {
            shading.quality.ao_radius = None;
        }
        shading.exposure = light.exposure;
        shading.validate()?;

        let mut map = input::load_mlhm(path, &options.terrain.read)?.mlhm;
        map.set_base(mlhm_base(&map));
        let map = Arc::new(map);
        if let Some(sigma) = options.sigma {
            check_sigma(sigma, map.cell_size())?;
        }
        let bounds = mlhm_bounds(&map)?;
        Ok(LayeredScene {
            map,
            mode,
            choice,
            sigma: options.sigma,
            preset,
            shading,
            bounds,
            path: path.to_path_buf(),
            max_memory: options.terrain.read.max_memory,
            no_shadows: light.no_shadows,
            no_ao: options.mlhm.no_ao,
        })
    }

    /// The scene in a few words.
    pub fn describe(&self) -> String {
        format!("{}x{} MLHM scene", self.map.width(), self.map.height())
    }

    /// The warning for a `camera` whose eye is inside the terrain, if it is.
    pub fn camera_warning(&self, camera: &Camera) -> Option<String> {
        crate::warnings::eye_in_mlhm(&self.map, camera)
    }

    /// The tracer `choice` draws the scene's columns with in `mode`; the smooth surface's
    /// normals averaged over half the spacing (closer to the terrain, as the paper's central
    /// differences at `h = σ/2`) where `central_differences` (as the max preset asks).
    pub fn tracer(
        &self,
        mode: RenderMode,
        choice: MlhmTracerChoice,
        central_differences: bool,
    ) -> Result<Box<dyn MlhmTracer>, RenderError> {
        let map = &self.map;
        Ok(match (mode, choice) {
            (RenderMode::Mesh, _) => {
                return Err(RenderError::Unsupported(
                    "--mode mesh has no tracer: it is rasterized".into(),
                ))
            }
            (RenderMode::Boxes, MlhmTracerChoice::Naive) => {
                Box::new(MlhmNaiveTracer::new(map.clone(), ORIGIN))
            }
            (RenderMode::Boxes, MlhmTracerChoice::Hierarchy(backtrack, bounds)) => Box::new(
                MlhmHierarchyTracer::new_with_precision(map.clone(), ORIGIN, bounds)
                    .with_backtrack(backtrack),
            ),
            (RenderMode::Smooth, choice) => {
                let mut options =
                    MlhmSmoothOptions { radius: self.sigma, ..MlhmSmoothOptions::default() };
                if central_differences {
                    // Differences at half the spacing follow the terrain more closely
                    // (section 4.4); of the blurred volume, so that they stay smooth.
                    options.normals = MlhmNormalScheme::Smoothed;
                    options.normal_spacing = Some(0.5 * self.sigma_or_cell());
                }
                match choice {
                    MlhmTracerChoice::Naive => options.hierarchy = false,
                    MlhmTracerChoice::Hierarchy(backtrack, bounds) => {
                        (options.backtrack, options.precision) = (backtrack, bounds);
                    }
                }
                Box::new(MlhmSmoothTracer::with_options(map.clone(), ORIGIN, options)?)
            }
        })
    }

    /// The smoothing radius, metres: the one asked for, or one cell.
    pub fn sigma_or_cell(&self) -> f64 {
        self.sigma.unwrap_or(self.map.cell_size())
    }
}

/// The tracer the options' tracer, backtracking and hierarchy bounds name for an MLHM scene
/// (default: the hierarchy, climbing by its exit stack, with f32 bounds).
fn tracer_choice(options: &SceneOptions) -> Result<MlhmTracerChoice, RenderError> {
    let mlhm = &options.mlhm;
    let hierarchy_options = mlhm.backtrack.is_some() || mlhm.hierarchy_bounds.is_some();
    match &options.tracer {
        None | Some(TracerChoice::Hierarchy) => Ok(MlhmTracerChoice::Hierarchy(
            mlhm.backtrack.unwrap_or_default(),
            mlhm.hierarchy_bounds.unwrap_or(Precision::F32),
        )),
        Some(TracerChoice::Plain(TracerKind::Naive)) if hierarchy_options => {
            Err(RenderError::Unsupported(
                "--backtrack and --hierarchy-bounds apply to the hierarchy tracer only, not to \
                 --tracer naive"
                    .into(),
            ))
        }
        Some(TracerChoice::Plain(TracerKind::Naive)) => Ok(MlhmTracerChoice::Naive),
        Some(other) => Err(RenderError::Unsupported(format!(
            "the {other} tracer renders height fields only; MLHM scenes (.json, .mlhm) take --tracer naive or hierarchy"
        ))),
    }
}

/// Smallest and largest smoothing radius, in cells: the marcher's step shrinks with the radius
/// and its volume queries grow with it; outside this range a 1280x720 render takes minutes
/// (measured: sigma 1/64 cell and 8 cells take about 1 and 4 s at 640x360).
const SIGMA_CELLS: (f64, f64) = (1.0 / 64.0, 8.0);

/// Refuses a smoothing radius `sigma` outside [`SIGMA_CELLS`] for cells of `cell_size` metres.
fn check_sigma(sigma: f64, cell_size: f64) -> Result<(), RenderError> {
    let (low, high) = (SIGMA_CELLS.0 * cell_size, SIGMA_CELLS.1 * cell_size);
    if !(low..=high).contains(&sigma) {
        return Err(RenderError::SigmaOutOfRange { sigma, low, high, cell: cell_size });
    }
    Ok(())
}

/// Where the solid of an MLHM scene ends below (see [`Mlhm::set_base`]): a little below the
/// lowest terrain that can be seen, the lowest bedrock top of any cell's lowest column
/// (every sand, water or column top seen lies at or above it), by 5% of the terrain's height
/// range and at least one cell. Without it the lowest columns reach down forever and every
/// picture is of a tall grey pillar under the terrain.
pub fn mlhm_base(map: &Mlhm) -> f32 {
    let heights = map.heights();
    let (lowest, top) = (heights.bedrock_min, heights.solid_max.max(heights.water_max));
    let margin = (0.05 * (top - lowest)).max(map.cell_size());
    (lowest - margin) as f32
}

/// The box an MLHM scene is framed and coloured by: its solids and water, from the solid's
/// [base](Mlhm::base) (or, where none is set, [`mlhm_base`]) up to the highest solid or
/// water top, so that it is finite and holds the whole visible block.
pub fn mlhm_bounds(map: &Arc<Mlhm>) -> Result<Aabb, RenderError> {
    let bounds = MlhmNaiveTracer::new(map.clone(), ORIGIN).world_bounds(MlhmMode::SolidsWater);
    let base = map.base();
    let base = if base.is_finite() { base } else { mlhm_base(map) } as f64;
    let finite = Aabb::new(DVec3::new(bounds.min.x, bounds.min.y, base), bounds.max);
    if !(finite.min.is_finite() && finite.max.is_finite() && base <= finite.max.z) {
        return Err(RenderError::NoFiniteBounds(format!("{finite:?}")));
    }
    Ok(finite)
}
