//! `relief render scene.json`: box ray tracing or smooth-surface ray marching of a
//! multi-layered height map scene, shaded as the MLHM paper does (Nilles & Müller 2025,
//! sections 4.6 and 5) at a quality preset.

use super::render::write_outputs;
use crate::args::{MlhmRenderMode, RenderArgs};
use crate::progress;
use crate::scene::mlhm::{LayeredScene, MlhmTracerChoice};
use anyhow::Result;
use relief_core::Precision;
use relief_shade::mlhm::render_mlhm;
use relief_shade::tonemap_reinhard_to_rgb8;
use std::path::Path;
use std::time::Instant;

/// Renders the MLHM scene at `path` as `args` say (outputs and image size already checked).
pub fn run(args: &RenderArgs, path: &Path) -> Result<()> {
    let scene = LayeredScene::open(&args.scene, path)?;
    let (mode, choice, shading, camera) = (scene.mode, scene.choice, &scene.shading, &scene.camera);
    let started = Instant::now();
    let tracer = scene.tracer(mode, choice, shading.quality.central_differences)?;
    let build_ms = started.elapsed().as_secs_f64() * 1e3;

    let (w, h) = (camera.width(), camera.height());
    let bar = progress::bar(w as u64 * h as u64, "rendering");
    let started = Instant::now();
    let image = render_mlhm(tracer.as_ref(), camera, shading, &|n| bar.inc(n))?;
    let render_ms = started.elapsed().as_secs_f64() * 1e3;
    bar.finish_and_clear();
    let rgb = tonemap_reinhard_to_rgb8(&image.radiance, shading.exposure)?;
    write_outputs(args, camera, &image.gbuffer, &rgb)?;
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
    Ok(())
}
