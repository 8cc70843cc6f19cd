//! `relief render --tracer clipmap`: a height field drawn by geometry clipmaps (n = 511, 11
//! levels, as the hybrid paper compares them), then shaded as every renderer is (shadow rays
//! by the exact tracer).

use super::render::{shade_and_write, Drawn};
use crate::args::RenderArgs;
use crate::outputs;
use crate::scene::height_field::HeightFieldScene;
use anyhow::{bail, Result};
use relief_core::Surface;
use relief_mesh::ClipmapParams;
use relief_shade::{ClipmapRenderer, GBuffer};
use serde_json::json;
use std::time::Instant;

/// Renders `scene` with geometry clipmaps and writes the outputs `args` ask for (and the stage
/// timings with `--stats`, `started` when the command began).
pub fn run(
    args: &RenderArgs,
    scene: &HeightFieldScene,
    started: Instant,
    load_ms: f64,
) -> Result<()> {
    if args.scene.surface == Some(Surface::Boxes) {
        bail!("geometry clipmaps draw the triangles surface only (use --surface triangles)");
    }
    let camera = &scene.camera;
    let build_started = Instant::now();
    let mut renderer = ClipmapRenderer::new(scene.field.clone(), ClipmapParams::default())?;
    let build_ms = outputs::ms_since(build_started);

    let trace_started = Instant::now();
    let mut gbuffer = GBuffer::new(camera.width() as usize, camera.height() as usize)?;
    let frame = renderer.render_into(camera, &scene.bounds(), &mut gbuffer)?;
    let trace_ms = outputs::ms_since(trace_started);

    let drawn =
        Drawn { gbuffer: &gbuffer, shadow_tracer: renderer.tracer(), load_ms, build_ms, trace_ms };
    let summary = format!("geometry clipmaps: {} triangles", frame.triangles);
    let extra = json!({
        "triangles": frame.triangles,
        "mesh_ms": frame.mesh_ms,
        "raster_ms": frame.raster_ms,
        "resolve_ms": frame.resolve_ms,
    });
    shade_and_write(args, scene, "clipmap", drawn, started, |_| {}, &summary, extra)
}
