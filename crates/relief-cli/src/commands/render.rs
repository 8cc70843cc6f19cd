//! `relief render`: trace, shade and write a picture (and optionally depth and normals).

use super::{check_image, render_mlhm};
use crate::args::RenderArgs;
use crate::scene::height_field::{check_safety_view, HeightFieldScene};
use crate::{input, memory, outputs, progress, tracers};
use anyhow::Result;
use relief_core::Camera;
use relief_shade::{render_gbuffer, shade_to_srgb8, GBuffer};
use relief_trace::Simd;
use std::path::Path;

/// Runs `relief render`: an MLHM scene (`.json`) takes [`render_mlhm`], any other input the
/// height-field path.
pub fn run(args: &RenderArgs) -> Result<()> {
    check_outputs(args)?;
    let scene_args = &args.scene;
    let budget = memory::budget(scene_args.input.read.max_memory);
    check_image(scene_args.size.0, scene_args.size.1, &budget)?;
    if let Some(path) = scene_args.input.input.as_deref().filter(|p| input::is_mlhm_scene(p)) {
        return render_mlhm::run(args, path);
    }
    let scene = HeightFieldScene::open(scene_args)?;
    let (surface, choice, camera) = (scene.surface, &scene.choice, &scene.camera);
    let built = tracers::build(
        &scene.field,
        surface,
        choice,
        &scene_args.safety,
        true,
        budget.bytes,
        Simd::detect(),
    )?;
    if let Some(safety) = &built.safety {
        check_safety_view(safety, camera, &scene.params)?;
    }
    if !built.note.is_empty() {
        eprintln!("{}", built.note);
    }
    let tracer = built.tracer;

    let pixels = camera.width() as u64 * camera.height() as u64;
    let bar = progress::bar(pixels, "tracing");
    let (gbuffer, _) = render_gbuffer(tracer.as_ref(), camera, &scene.bounds(), &|n| bar.inc(n))?;
    bar.finish_and_clear();
    let (rgb, _) = shade_to_srgb8(&gbuffer, tracer.as_ref(), camera, &scene.params)?;
    write_outputs(args, camera, &gbuffer, rgb.as_flattened())?;
    let (w, h) = (camera.width(), camera.height());
    eprintln!("wrote {} ({w}x{h}, {surface} {choice} tracer)", args.output.display());
    Ok(())
}

/// Refuses, before any work, outputs whose format or folder is wrong, and two outputs (or an
/// output and the input) that are one file.
fn check_outputs(args: &RenderArgs) -> Result<()> {
    outputs::check_writable(&args.output)?;
    outputs::picture_format("-o", &args.output)?;
    let mut all = vec![("-o", args.output.as_path())];
    for (option, path) in [("--depth", &args.depth), ("--normals", &args.normals)] {
        if let Some(path) = path {
            outputs::check_writable(path)?;
            outputs::check_npy(option, path)?;
            all.push((option, path.as_path()));
        }
    }
    let scene = &args.scene;
    let inputs: Vec<&Path> =
        [scene.input.input.as_deref(), scene.texture.as_deref()].into_iter().flatten().collect();
    outputs::check_distinct(&all, &inputs)
}

/// The PNG of the tone-mapped `rgb`, and the depth and normals of `gbuffer` where asked for.
pub(super) fn write_outputs(
    args: &RenderArgs,
    camera: &Camera,
    gbuffer: &GBuffer,
    rgb: &[u8],
) -> Result<()> {
    outputs::write_picture(&args.output, camera.width(), camera.height(), rgb)?;
    let (h, w) = (camera.height() as usize, camera.width() as usize);
    if let Some(path) = &args.depth {
        relief_io::write_npy_f32(path, &[h, w], &gbuffer.depth_hw())?;
    }
    if let Some(path) = &args.normals {
        relief_io::write_npy_f32(path, &[h, w, 3], &gbuffer.normals_hw3())?;
    }
    Ok(())
}
