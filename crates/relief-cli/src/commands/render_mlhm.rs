//! `relief render scene.json`: box ray tracing or smooth-surface ray marching of a
//! multi-layered height map scene, shaded as the MLHM paper does (Nilles & Müller 2025,
//! sections 4.6 and 5) at a quality preset.

use super::render::{input_name, write_outputs};
use crate::args::{MlhmRenderMode, RenderArgs};
use crate::scene::mlhm::{LayeredScene, MlhmTracerChoice};
use crate::{outputs, progress};
use anyhow::Result;
use relief_core::Precision;
use relief_shade::mlhm::render_mlhm;
use relief_shade::tonemap_reinhard_to_rgb8;
use serde_json::json;
use std::path::Path;
use std::time::Instant;

/// Renders the MLHM scene at `path` as `args` say (outputs and image size already checked;
/// the command `started` then, for `--stats`).
///
/// The renderer traces and shades each pixel in one pass: `--stats` puts that pass in
/// `trace_ms` and the tone mapping in `shade_ms`.
pub fn run(args: &RenderArgs, path: &Path, started: Instant) -> Result<()> {
    let scene = LayeredScene::open(&args.scene, path)?;
    let load_ms = outputs::ms_since(started);
    let (mode, choice, shading, camera) = (scene.mode, scene.choice, &scene.shading, &scene.camera);
    let build_started = Instant::now();
    let tracer = scene.tracer(mode, choice, shading.quality.central_differences)?;
    let build_ms = build_started.elapsed().as_secs_f64() * 1e3;

    let (w, h) = (camera.width(), camera.height());
    let bar = progress::bar(w as u64 * h as u64, "rendering");
    let render_started = Instant::now();
    let image = render_mlhm(tracer.as_ref(), camera, shading, &|n| bar.inc(n))?;
    let render_ms = render_started.elapsed().as_secs_f64() * 1e3;
    bar.finish_and_clear();
    let tonemap_started = Instant::now();
    let rgb = tonemap_reinhard_to_rgb8(&image.radiance, shading.exposure)?;
    let shade_ms = outputs::ms_since(tonemap_started);
    let write_started = Instant::now();
    write_outputs(args, camera, &image.gbuffer, &rgb)?;
    let write_ms = outputs::ms_since(write_started);
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
        MlhmRenderMode::Smooth => format!("a smooth surface (sigma {} m)", scene.sigma_or_cell()),
        MlhmRenderMode::Mesh => "a mesh".to_string(),
    };
    eprintln!(
        "wrote {} ({w}x{h}, {}x{} MLHM scene as {surface}, preset {}, {how}; \
         rendered in {render_ms:.0} ms, {rays_per_pixel:.2} rays per pixel, \
         {steps:.1} steps per camera ray)",
        args.output.display(),
        scene.map.width(),
        scene.map.height(),
        scene.preset
    );
    if let Some(path) = &args.stats {
        let primary = &image.counts.primary;
        let stats = json!({
            "input": input_name(args),
            "kind": "mlhm",
            "terrain": [scene.map.width(), scene.map.height()],
            "surface": match mode {
                MlhmRenderMode::Boxes => "boxes",
                MlhmRenderMode::Smooth => "smooth",
                MlhmRenderMode::Mesh => "mesh",
            },
            "tracer": how,
            "preset": scene.preset.to_string(),
            "width": w,
            "height": h,
            "threads": rayon::current_num_threads(),
            "rays": image.counts.rays(),
            "primary_rays": primary.rays,
            "hits": primary.hits,
            "mean_steps": steps,
            "load_ms": load_ms,
            "build_ms": build_ms,
            "trace_ms": render_ms,
            "shade_ms": shade_ms,
            "write_ms": write_ms,
            "total_ms": outputs::ms_since(started),
            "shading_in_trace": true,
        });
        outputs::write_stats(path, &stats)?;
    }
    Ok(())
}
