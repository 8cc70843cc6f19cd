//! A multi-layered height map scene to draw: the map, how its columns are drawn (boxes or the
//! smooth surface), the tracer, the shading preset (Nilles & Müller 2025, sections 4.6 and 5)
//! and the starting camera.

use crate::args::{MlhmRenderMode, SceneArgs};
use crate::tracers::TracerChoice;
use crate::{applies, input, parse};
use anyhow::{bail, Result};
use relief_core::{Aabb, Camera, DVec2, DVec3, Mlhm, Precision, Surface};
use relief_shade::mlhm::{MlhmPreset, MlhmShading};
use relief_shade::Sun;
use relief_trace::{
    MlhmBacktrack, MlhmHierarchyTracer, MlhmMode, MlhmNaiveTracer, MlhmNormalScheme,
    MlhmSmoothOptions, MlhmSmoothTracer, MlhmTracer, TracerKind,
};
use std::path::Path;
use std::sync::Arc;

/// The MLHM tracers `--tracer` may name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MlhmTracerChoice {
    /// Every column of every cell the ray crosses.
    Naive,
    /// The hierarchy of bounds, climbing back up as it says, its bounds stored at a precision.
    Hierarchy(MlhmBacktrack, Precision),
}

/// An MLHM scene opened from the command line.
pub struct LayeredScene {
    /// The map.
    pub map: Arc<Mlhm>,
    /// Boxes or the smooth surface (default: boxes).
    pub mode: MlhmRenderMode,
    /// The tracer (default: the hierarchy, stack backtracking, f32 bounds).
    pub choice: MlhmTracerChoice,
    /// The smoothing radius of the smooth surface, metres (default: one cell).
    pub sigma: Option<f64>,
    /// The quality preset (default: mid).
    pub preset: MlhmPreset,
    /// The preset's shading with the command line's sun, exposure, shadows and AO.
    pub shading: MlhmShading,
    /// The camera of `--eye`/`--target`, or the framing three-quarter view.
    pub camera: Camera,
    /// A finite box holding every visible surface.
    pub bounds: Aabb,
}

/// The scene has no georeference: cell (x, y) covers [x s, (x + 1) s) x [y s, (y + 1) s).
const ORIGIN: DVec2 = DVec2::ZERO;

impl LayeredScene {
    /// Reads the MLHM scene at `path`, refusing the options that do not apply to it.
    pub fn open(args: &SceneArgs, path: &Path) -> Result<Self> {
        let mode = args.mode.unwrap_or(MlhmRenderMode::Boxes);
        if mode == MlhmRenderMode::Mesh {
            bail!("--mode mesh is drawn by relief render and written by relief mesh, not here");
        }
        if args.sigma.is_some() && mode == MlhmRenderMode::Boxes {
            return Err(applies::refuse("--sigma", "--mode smooth", "--mode boxes"));
        }
        let choice = tracer_choice(args)?;
        refuse_height_field_options(args)?;
        applies::check_read_args(&args.input.read, Some(path))?;
        let preset = args.preset.unwrap_or_default();
        let mut shading = MlhmShading::new(preset);
        let (azimuth_deg, elevation_deg) = args.sun;
        shading.sun = Sun { azimuth_deg, elevation_deg, ..shading.sun };
        shading.quality.shadows &= !args.no_shadows;
        if args.no_ao {
            shading.quality.ao_radius = None;
        }
        shading.exposure = args.exposure;
        shading.validate()?;

        let map = Arc::new(input::load_mlhm(path, &args.input.read)?.mlhm);
        if let Some(sigma) = args.sigma {
            check_sigma(sigma, map.cell_size())?;
        }
        let naive = MlhmNaiveTracer::new(map.clone(), ORIGIN);
        let bounds = finite_bounds(&naive.world_bounds(MlhmMode::SolidsWater), &map)?;
        let camera = super::camera(args, &bounds)?;
        if let Some(warning) = crate::warnings::eye_in_mlhm(&map, &camera) {
            eprintln!("{warning}");
        }
        Ok(LayeredScene { map, mode, choice, sigma: args.sigma, preset, shading, camera, bounds })
    }

    /// The tracer `choice` draws the scene's columns with in `mode`; the smooth surface's
    /// normals by central differences where `central_differences` (as the high presets ask).
    pub fn tracer(
        &self,
        mode: MlhmRenderMode,
        choice: MlhmTracerChoice,
        central_differences: bool,
    ) -> Result<Box<dyn MlhmTracer>> {
        let map = &self.map;
        Ok(match (mode, choice) {
            (MlhmRenderMode::Mesh, _) => bail!("--mode mesh has no tracer: it is rasterized"),
            (MlhmRenderMode::Boxes, MlhmTracerChoice::Naive) => {
                Box::new(MlhmNaiveTracer::new(map.clone(), ORIGIN))
            }
            (MlhmRenderMode::Boxes, MlhmTracerChoice::Hierarchy(backtrack, bounds)) => Box::new(
                MlhmHierarchyTracer::new_with_precision(map.clone(), ORIGIN, bounds)
                    .with_backtrack(backtrack),
            ),
            (MlhmRenderMode::Smooth, choice) => {
                let mut options =
                    MlhmSmoothOptions { radius: self.sigma, ..MlhmSmoothOptions::default() };
                if central_differences {
                    // Central differences at half the spacing follow the terrain more closely
                    // (section 4.4).
                    options.normals = MlhmNormalScheme::Central;
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

    /// The smoothing radius, metres: `--sigma`, or one cell.
    pub fn sigma_or_cell(&self) -> f64 {
        self.sigma.unwrap_or(self.map.cell_size())
    }
}

/// The tracer `--tracer`, `--backtrack` and `--hierarchy-bounds` name for an MLHM scene
/// (default: the hierarchy, climbing by its exit stack, with f32 bounds).
fn tracer_choice(args: &SceneArgs) -> Result<MlhmTracerChoice> {
    let hierarchy_options = args.backtrack.is_some() || args.hierarchy_bounds.is_some();
    match &args.tracer {
        None | Some(TracerChoice::Hierarchy) => Ok(MlhmTracerChoice::Hierarchy(
            args.backtrack.unwrap_or_default(),
            args.hierarchy_bounds.unwrap_or(Precision::F32),
        )),
        Some(TracerChoice::Plain(TracerKind::Naive)) if hierarchy_options => bail!(
            "--backtrack and --hierarchy-bounds apply to the hierarchy tracer only, not to \
             --tracer naive"
        ),
        Some(TracerChoice::Plain(TracerKind::Naive)) => Ok(MlhmTracerChoice::Naive),
        Some(other) => bail!(
            "the {other} tracer renders height fields only; MLHM scenes (.json, .mlhm) take --tracer naive or hierarchy"
        ),
    }
}

/// Smallest and largest smoothing radius, in cells: the marcher's step shrinks with the radius
/// and its volume queries grow with it; outside this range a 1280x720 render takes minutes
/// (measured: sigma 1/64 cell and 8 cells take about 1 and 4 s at 640x360).
const SIGMA_CELLS: (f64, f64) = (1.0 / 64.0, 8.0);

/// Refuses a smoothing radius `sigma` outside [`SIGMA_CELLS`] for cells of `cell_size` metres.
fn check_sigma(sigma: f64, cell_size: f64) -> Result<()> {
    let (lo, hi) = (SIGMA_CELLS.0 * cell_size, SIGMA_CELLS.1 * cell_size);
    if !(lo..=hi).contains(&sigma) {
        bail!(
            "--sigma {} m is outside {}..{} m (1/64 of a cell to 8 cells of {} m): smaller \
             radii take ever more marching steps, larger ones ever larger volume queries",
            parse::readable(sigma),
            parse::readable(lo),
            parse::readable(hi),
            parse::readable(cell_size)
        );
    }
    Ok(())
}

/// Refuses the options that place or read a height field, or shade one, which an MLHM scene
/// does not take.
fn refuse_height_field_options(args: &SceneArgs) -> Result<()> {
    let input = &args.input;
    if let Some(option) = applies::safety_option_given(&args.safety) {
        return Err(applies::refuse(option, "the safety tracer of height fields", "MLHM scenes"));
    }
    let what = match () {
        _ if args.surface.is_some_and(|s| s != Surface::Boxes) => {
            "--surface triangles (an MLHM scene renders as boxes, see --mode)"
        }
        _ if input.spacing.is_some() => "--spacing (the scene's cell size places it)",
        _ if input.north_up => "--north-up",
        _ if input.z_scale != 1.0 => "--z-scale",
        _ if input.read.voids.is_some() => "--voids",
        _ if input.fbm_size.is_some() => "--fbm-size",
        _ if input.seed.is_some() => "--seed",
        _ if args.texture.is_some() => "--texture (an MLHM scene is coloured by its materials)",
        _ => return Ok(()),
    };
    Err(applies::refuse(what, "height fields", "MLHM scenes"))
}

/// `bounds` with its bottom, minus infinity for a scene's lowest columns, raised to the lowest
/// bedrock top: a finite box that holds every visible surface, for framing and colouring.
fn finite_bounds(bounds: &Aabb, map: &Mlhm) -> Result<Aabb> {
    let lowest = map.heights().bedrock_min;
    let finite = Aabb::new(DVec3::new(bounds.min.x, bounds.min.y, lowest), bounds.max);
    if !(finite.min.is_finite() && finite.max.is_finite() && lowest <= finite.max.z) {
        bail!("the scene has no finite bounds ({finite:?})");
    }
    Ok(finite)
}
