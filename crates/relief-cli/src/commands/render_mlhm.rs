//! `relief render scene.json`: box ray tracing of a multi-layered height map scene through the
//! G-buffer and deferred shading of the height-field path.

use super::render::{camera, shading, write_outputs};
use crate::args::{MlhmRenderMode, RenderArgs};
use crate::tracers::TracerChoice;
use crate::{input, progress};
use anyhow::{bail, Result};
use relief_core::{Aabb, DVec2, DVec3, Mlhm, Surface};
use relief_shade::{render_gbuffer, shade};
use relief_trace::{
    MlhmBacktrack, MlhmHierarchyTracer, MlhmMode, MlhmNaiveTracer, Tracer, TracerKind,
};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// What primary rays, depth and shadow rays intersect: the visible surface, solids and water.
const MODE: MlhmMode = MlhmMode::SolidsWater;

/// The MLHM tracers `--tracer` may name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MlhmTracer {
    Naive,
    Hierarchy(MlhmBacktrack),
}

/// Renders the MLHM scene at `path` as `args` say (outputs and image size already checked).
pub fn run(args: &RenderArgs, path: &Path) -> Result<()> {
    // Boxes is the only mode so far (the parser refuses smooth): a match once there are more.
    let MlhmRenderMode::Boxes = args.mode.unwrap_or(MlhmRenderMode::Boxes);
    let choice = tracer_choice(args)?;
    refuse_height_field_options(args)?;
    let scene = input::load_mlhm(path, &args.input.read)?;
    let map = Arc::new(scene.mlhm);
    // The scene has no georeference: cell (x, y) covers [x s, (x + 1) s) x [y s, (y + 1) s).
    let origin = DVec2::ZERO;
    let naive = MlhmNaiveTracer::new(map.clone(), origin).with_mode(MODE);
    let bounds = finite_bounds(&naive.world_bounds(MODE), &map)?;
    let camera = camera(args, &bounds)?;
    let params = shading(args, &bounds)?;

    let started = Instant::now();
    let tracer: Box<dyn Tracer> = match choice {
        MlhmTracer::Naive => Box::new(naive),
        MlhmTracer::Hierarchy(backtrack) => Box::new(
            MlhmHierarchyTracer::new(map.clone(), origin).with_mode(MODE).with_backtrack(backtrack),
        ),
    };
    let build_ms = started.elapsed().as_secs_f64() * 1e3;

    let pixels = camera.width() as u64 * camera.height() as u64;
    let bar = progress::bar(pixels, "tracing");
    let (gbuffer, _) = render_gbuffer(tracer.as_ref(), &camera, &bounds, &|n| bar.inc(n))?;
    bar.finish_and_clear();
    let (radiance, _) = shade(&gbuffer, tracer.as_ref(), &camera, &params)?;
    write_outputs(args, &camera, &gbuffer, &radiance, params.exposure)?;
    let (w, h) = (camera.width(), camera.height());
    let how = match choice {
        MlhmTracer::Naive => "naive tracer".to_string(),
        MlhmTracer::Hierarchy(b) => {
            format!("hierarchy tracer, {b} backtracking, built in {build_ms:.1} ms")
        }
    };
    eprintln!(
        "wrote {} ({w}x{h}, {}x{} MLHM scene as boxes, {how})",
        args.output.display(),
        map.width(),
        map.height()
    );
    Ok(())
}

/// The tracer `--tracer` and `--backtrack` name for an MLHM scene (default: the hierarchy,
/// climbing by its exit stack).
fn tracer_choice(args: &RenderArgs) -> Result<MlhmTracer> {
    match (&args.tracer, args.backtrack) {
        (None | Some(TracerChoice::Hierarchy), backtrack) => {
            Ok(MlhmTracer::Hierarchy(backtrack.unwrap_or_default()))
        }
        (Some(TracerChoice::Plain(TracerKind::Naive)), None) => Ok(MlhmTracer::Naive),
        (Some(TracerChoice::Plain(TracerKind::Naive)), Some(_)) => {
            bail!("--backtrack applies to the hierarchy tracer only, not to --tracer naive")
        }
        (Some(other), _) => bail!(
            "the {other} tracer renders height fields only; MLHM scenes (.json) take --tracer naive or hierarchy"
        ),
    }
}

/// Refuses the options that place or read a height field, which an MLHM scene does not take.
fn refuse_height_field_options(args: &RenderArgs) -> Result<()> {
    let input = &args.input;
    let what = match () {
        _ if args.surface.is_some_and(|s| s != Surface::Boxes) => {
            "--surface triangles (an MLHM scene renders as boxes, see --mode)"
        }
        _ if input.spacing.is_some() => "--spacing (the scene's cell size places it)",
        _ if input.north_up => "--north-up",
        _ if input.z_scale != 1.0 => "--z-scale",
        _ if input.read.voids.is_some() => "--voids",
        _ if input.read.array.is_some() => "--array",
        _ => return Ok(()),
    };
    bail!("{what} applies to height fields only, not to MLHM scenes")
}

/// `bounds` with its bottom, minus infinity for a scene's lowest columns, raised to the lowest
/// bedrock top: a finite box that holds every visible surface, for framing and colouring.
fn finite_bounds(bounds: &Aabb, map: &Mlhm) -> Result<Aabb> {
    let lowest = (0..map.height())
        .flat_map(|y| (0..map.width()).map(move |x| (x, y)))
        .map(|(x, y)| map.column(x, y, 0).bedrock)
        .fold(f32::INFINITY, f32::min) as f64;
    let finite = Aabb::new(DVec3::new(bounds.min.x, bounds.min.y, lowest), bounds.max);
    if !(finite.min.is_finite() && finite.max.is_finite() && lowest <= finite.max.z) {
        bail!("the scene has no finite bounds ({finite:?})");
    }
    Ok(finite)
}
