//! `relief render scene.json`: box ray tracing or smooth-surface ray marching of a
//! multi-layered height map scene, shaded as the MLHM paper does (Nilles & Müller 2025,
//! sections 4.6 and 5) at a quality preset.

use super::render::{camera, write_outputs};
use crate::args::{MlhmRenderMode, RenderArgs};
use crate::tracers::TracerChoice;
use crate::{applies, input, parse, progress};
use anyhow::{bail, Result};
use relief_core::{Aabb, DVec2, DVec3, Mlhm, Precision, Surface};
use relief_shade::mlhm::{render_mlhm, MlhmShading};
use relief_shade::{tonemap_reinhard_to_rgb8, Sun};
use relief_trace::{
    MlhmBacktrack, MlhmHierarchyTracer, MlhmMode, MlhmNaiveTracer, MlhmNormalScheme,
    MlhmSmoothOptions, MlhmSmoothTracer, MlhmTracer, TracerKind,
};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// The MLHM tracers `--tracer` may name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MlhmTracerChoice {
    Naive,
    Hierarchy(MlhmBacktrack, Precision),
}

/// Renders the MLHM scene at `path` as `args` say (outputs and image size already checked).
pub fn run(args: &RenderArgs, path: &Path) -> Result<()> {
    let mode = args.mode.unwrap_or(MlhmRenderMode::Boxes);
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

    let scene = input::load_mlhm(path, &args.input.read)?;
    let map = Arc::new(scene.mlhm);
    if let Some(sigma) = args.sigma {
        check_sigma(sigma, map.cell_size())?;
    }
    // The scene has no georeference: cell (x, y) covers [x s, (x + 1) s) x [y s, (y + 1) s).
    let origin = DVec2::ZERO;
    let naive = MlhmNaiveTracer::new(map.clone(), origin);
    let bounds = finite_bounds(&naive.world_bounds(MlhmMode::SolidsWater), &map)?;
    let camera = camera(args, &bounds)?;

    let started = Instant::now();
    let tracer: Box<dyn MlhmTracer> = match (mode, choice) {
        (MlhmRenderMode::Boxes, MlhmTracerChoice::Naive) => Box::new(naive),
        (MlhmRenderMode::Boxes, MlhmTracerChoice::Hierarchy(backtrack, bounds)) => Box::new(
            MlhmHierarchyTracer::new_with_precision(map.clone(), origin, bounds)
                .with_backtrack(backtrack),
        ),
        (MlhmRenderMode::Smooth, choice) => {
            let mut options =
                MlhmSmoothOptions { radius: args.sigma, ..MlhmSmoothOptions::default() };
            if shading.quality.central_differences {
                // Central differences at half the spacing follow the terrain more closely
                // (section 4.4).
                let sigma = args.sigma.unwrap_or(map.cell_size());
                options.normals = MlhmNormalScheme::Central;
                options.normal_spacing = Some(0.5 * sigma);
            }
            match choice {
                MlhmTracerChoice::Naive => options.hierarchy = false,
                MlhmTracerChoice::Hierarchy(backtrack, bounds) => {
                    (options.backtrack, options.precision) = (backtrack, bounds);
                }
            }
            Box::new(MlhmSmoothTracer::with_options(map.clone(), origin, options)?)
        }
    };
    let build_ms = started.elapsed().as_secs_f64() * 1e3;

    let (w, h) = (camera.width(), camera.height());
    let bar = progress::bar(w as u64 * h as u64, "rendering");
    let started = Instant::now();
    let image = render_mlhm(tracer.as_ref(), &camera, &shading, &|n| bar.inc(n))?;
    let render_ms = started.elapsed().as_secs_f64() * 1e3;
    bar.finish_and_clear();
    let rgb = tonemap_reinhard_to_rgb8(&image.radiance, shading.exposure)?;
    write_outputs(args, &camera, &image.gbuffer, &rgb)?;
    let how = match choice {
        MlhmTracerChoice::Naive if mode == MlhmRenderMode::Smooth => {
            "marching without the hierarchy".to_string()
        }
        MlhmTracerChoice::Naive => "naive tracer".to_string(),
        MlhmTracerChoice::Hierarchy(b, bounds) => {
            let bounds = match bounds {
                Precision::F32 => "f32",
                Precision::F16 => "f16",
            };
            format!(
                "hierarchy tracer, {b} backtracking, {bounds} bounds, built in {build_ms:.1} ms"
            )
        }
    };
    let rays_per_pixel = image.counts.rays() as f64 / (w as f64 * h as f64);
    let steps = image.counts.primary.mean_steps();
    let surface = match mode {
        MlhmRenderMode::Boxes => "boxes".to_string(),
        MlhmRenderMode::Smooth => {
            format!("a smooth surface (sigma {} m)", args.sigma.unwrap_or(map.cell_size()))
        }
    };
    eprintln!(
        "wrote {} ({w}x{h}, {}x{} MLHM scene as {surface}, preset {preset}, {how}; \
         rendered in {render_ms:.0} ms, {rays_per_pixel:.2} rays per pixel, \
         {steps:.1} steps per camera ray)",
        args.output.display(),
        map.width(),
        map.height()
    );
    Ok(())
}

/// The tracer `--tracer`, `--backtrack` and `--hierarchy-bounds` name for an MLHM scene
/// (default: the hierarchy, climbing by its exit stack, with f32 bounds).
fn tracer_choice(args: &RenderArgs) -> Result<MlhmTracerChoice> {
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
fn refuse_height_field_options(args: &RenderArgs) -> Result<()> {
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
