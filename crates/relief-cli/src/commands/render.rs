//! `relief render`: trace, shade and write a picture (and optionally depth and normals).

use super::{check_image, render_mlhm};
use crate::args::RenderArgs;
use crate::tracers::TracerChoice;
use crate::{applies, input, memory, outputs, progress, tracers};
use anyhow::{Context, Result};
use relief_core::{Aabb, Camera, DVec3, Surface};
use relief_shade::{
    render_gbuffer, shade_to_srgb8, sun_direction, Albedo, GBuffer, RgbTexture, ShadingParams, Sun,
};
use relief_trace::{Simd, TracerKind};
use std::path::Path;

/// Runs `relief render`: an MLHM scene (`.json`) takes [`render_mlhm`], any other input the
/// height-field path.
pub fn run(args: &RenderArgs) -> Result<()> {
    check_outputs(args)?;
    let budget = memory::budget(args.input.read.max_memory);
    check_image(args.size.0, args.size.1, &budget)?;
    if let Some(path) = args.input.input.as_deref().filter(|p| input::is_mlhm_scene(p)) {
        return render_mlhm::run(args, path);
    }
    refuse_mlhm_options(args)?;
    let surface = args.surface.unwrap_or(Surface::Triangles);
    let choice = args.tracer.clone().unwrap_or(TracerChoice::Plain(TracerKind::Mipmap));
    if !matches!(choice, TracerChoice::Safety(_)) {
        if let Some(option) = applies::safety_option_given(&args.safety) {
            return Err(applies::refuse(
                option,
                "the safety tracer",
                &format!("the {choice} tracer"),
            ));
        }
    }
    let field = input::load(&args.input)?;
    let camera = camera(args, &field.world_bounds(surface))?;
    let params = shading(args, &field.world_bounds(Surface::Boxes))?;
    let built =
        tracers::build(&field, surface, &choice, &args.safety, true, budget.bytes, Simd::detect())?;
    if let Some(safety) = &built.safety {
        let light = (!args.no_shadows).then(|| sun_direction(args.sun.0, args.sun.1));
        let (w, h) = (camera.width(), camera.height());
        let directions =
            (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).map(|(i, j)| camera.ray(i, j).dir);
        safety.check_view(camera.eye(), directions, light)?;
    }
    if !built.note.is_empty() {
        eprintln!("{}", built.note);
    }
    let tracer = built.tracer;

    let pixels = camera.width() as u64 * camera.height() as u64;
    let bar = progress::bar(pixels, "tracing");
    let bounds = field.world_bounds(surface);
    let (gbuffer, _) = render_gbuffer(tracer.as_ref(), &camera, &bounds, &|n| bar.inc(n))?;
    bar.finish_and_clear();
    let (rgb, _) = shade_to_srgb8(&gbuffer, tracer.as_ref(), &camera, &params)?;
    write_outputs(args, &camera, &gbuffer, rgb.as_flattened())?;
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
    let inputs: Vec<&Path> =
        [args.input.input.as_deref(), args.texture.as_deref()].into_iter().flatten().collect();
    outputs::check_distinct(&all, &inputs)
}

/// Refuses the options only an MLHM scene takes, for a height field.
fn refuse_mlhm_options(args: &RenderArgs) -> Result<()> {
    let what = if args.tracer == Some(TracerChoice::Hierarchy) {
        "--tracer hierarchy"
    } else if args.mode.is_some() {
        "--mode"
    } else if args.backtrack.is_some() {
        "--backtrack"
    } else if args.preset.is_some() {
        "--preset"
    } else if args.hierarchy_bounds.is_some() {
        "--hierarchy-bounds"
    } else if args.sigma.is_some() {
        "--sigma"
    } else if args.no_ao {
        "--no-ao"
    } else {
        return Ok(());
    };
    let here = applies::input_kind(args.input.input.as_deref());
    Err(applies::refuse(what, "MLHM scenes (.json, .mlhm)", &here))
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

/// The camera given on the command line, or a three-quarter view framing `bounds`. An up
/// vector parallel to the view (a camera looking straight down) is replaced by north, with a
/// note saying so.
pub(super) fn camera(args: &RenderArgs, bounds: &Aabb) -> Result<Camera> {
    let (w, h) = args.size;
    let camera = match (args.eye, args.target) {
        (Some(eye), Some(target)) => {
            let given = args.up.unwrap_or(DVec3::Z);
            let (up, replaced) = Camera::usable_up(eye, target, given);
            if replaced {
                eprintln!(
                    "note: up {},{},{} is parallel to the view; using {},{},{} (north at the top \
                     of the image; set --up to choose another)",
                    given.x, given.y, given.z, up.x, up.y, up.z
                );
            }
            Camera::look_at(eye, target, up, args.fov, w, h)?
        }
        _ => Camera::frame_from(bounds, 225.0, 30.0, args.fov, w, h)?,
    };
    Ok(camera)
}

/// Lights and materials from the command line, fitted to a terrain within `bounds`.
pub(super) fn shading(args: &RenderArgs, bounds: &Aabb) -> Result<ShadingParams> {
    let mut params = ShadingParams::for_terrain(bounds)?;
    let (azimuth_deg, elevation_deg) = args.sun;
    params.sun = Sun { azimuth_deg, elevation_deg, ..params.sun };
    params.shadows = !args.no_shadows;
    params.exposure = args.exposure;
    if let Some(path) = &args.texture {
        let image = relief_io::read_png_rgb(path)?;
        let rgb: Vec<u8> = image.pixels.iter().flatten().copied().collect();
        let texture = RgbTexture::from_srgb8(image.width as usize, image.height as usize, &rgb)
            .with_context(|| format!("texture {}", path.display()))?;
        params.albedo = Albedo::Texture(texture);
    }
    params.validate()?;
    Ok(params)
}
