//! `relief render --mode mesh`: a material-stack terrain's LOD mesh for the camera rasterized
//! into the G-buffer and shaded by the deferred pass like every other renderer.

use super::render::write_outputs;
use crate::args::RenderArgs;
use crate::scene::stacks::{self, StacksScene};
use crate::{outputs, progress};
use anyhow::{bail, Result};
use relief_shade::{GBuffer, StacksRenderer};
use serde_json::json;
use std::time::Instant;

/// Runs `relief render --mode mesh` on any input.
pub fn run(args: &RenderArgs, started: Instant) -> Result<()> {
    if let Some(option) = args.hybrid.given() {
        bail!("{option} applies to --tracer hybrid, not to --mode mesh");
    }
    let scene = StacksScene::open(&args.scene, "--mode mesh")?;
    let load_ms = outputs::ms_since(started);
    let camera = scene.camera;
    let tau = args.scene.tau.unwrap_or(super::mesh::DEFAULT_TAU_PX);
    let mut renderer = StacksRenderer::new(scene.mesher, tau)?;
    let mut gbuffer = GBuffer::new(camera.width() as usize, camera.height() as usize)?;
    let bar = progress::spinner("meshing");
    let trace_started = Instant::now();
    let frame = renderer.render_into(&camera, &scene.bounds, &mut gbuffer)?;
    let frame_ms = outputs::ms_since(trace_started);
    bar.finish_and_clear();

    let shade_started = Instant::now();
    let rgb = stacks::shade(&gbuffer, &camera, &scene.bounds, args.scene.sun, args.scene.exposure)?;
    let shade_ms = outputs::ms_since(shade_started);
    let write_started = Instant::now();
    write_outputs(args, &camera, &gbuffer, rgb.as_flattened())?;
    let write_ms = outputs::ms_since(write_started);
    let (w, h) = (camera.width(), camera.height());
    eprintln!(
        "wrote {} ({w}x{h}, stacks mesh of {} octree nodes, {} triangles, tau {tau} px)",
        args.output.display(),
        frame.mesh.nodes,
        frame.triangles
    );
    if let Some(path) = &args.stats {
        let stats = json!({
            "input": super::render::input_name(args),
            "kind": "stacks mesh",
            "width": w,
            "height": h,
            "nodes": frame.mesh.nodes,
            "triangles": frame.triangles,
            "load_ms": load_ms,
            "build_ms": frame.mesh_ms,
            "trace_ms": frame.raster_ms + frame.resolve_ms,
            "frame_ms": frame_ms,
            "mesh_ms": frame.mesh_ms,
            "raster_ms": frame.raster_ms,
            "resolve_ms": frame.resolve_ms,
            "shade_ms": shade_ms,
            "write_ms": write_ms,
            "total_ms": outputs::ms_since(started),
        });
        outputs::write_stats(path, &stats)?;
    }
    Ok(())
}
