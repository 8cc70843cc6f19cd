//! `relief render --tracer clipmap`: a height field drawn by geometry clipmaps (n = 511, 11
//! levels, as the hybrid paper compares them), then shaded as every renderer is (shadow rays
//! by the exact tracer).

use super::render::{input_name, write_outputs};
use crate::args::RenderArgs;
use crate::outputs;
use crate::scene::height_field::HeightFieldScene;
use anyhow::{bail, Result};
use relief_core::Surface;
use relief_mesh::ClipmapParams;
use relief_shade::{shade_to_srgb8, ClipmapRenderer, GBuffer};
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

    let shade_started = Instant::now();
    let (rgb, shadow) = shade_to_srgb8(&gbuffer, renderer.tracer(), camera, &scene.params)?;
    let shade_ms = outputs::ms_since(shade_started);

    let write_started = Instant::now();
    write_outputs(args, camera, &gbuffer, rgb.as_flattened())?;
    let write_ms = outputs::ms_since(write_started);
    let (w, h) = (camera.width(), camera.height());
    eprintln!(
        "wrote {} ({w}x{h}, geometry clipmaps: {} triangles)",
        args.output.display(),
        frame.triangles
    );
    if let Some(path) = &args.stats {
        let field = &scene.field;
        let hits = gbuffer.distance.iter().filter(|d| d.is_finite()).count();
        let stats = json!({
            "input": input_name(args),
            "kind": "height field",
            "terrain": [field.width(), field.height()],
            "surface": "triangles",
            "tracer": "clipmap",
            "width": w,
            "height": h,
            "threads": rayon::current_num_threads(),
            "rays": u64::from(w) * u64::from(h),
            "hits": hits,
            "shadow_rays": shadow.rays,
            "triangles": frame.triangles,
            "mesh_ms": frame.mesh_ms,
            "raster_ms": frame.raster_ms,
            "resolve_ms": frame.resolve_ms,
            "load_ms": load_ms,
            "build_ms": build_ms,
            "trace_ms": trace_ms,
            "shade_ms": shade_ms,
            "write_ms": write_ms,
            "total_ms": outputs::ms_since(started),
        });
        outputs::write_stats(path, &stats)?;
    }
    Ok(())
}
