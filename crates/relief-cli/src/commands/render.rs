//! `relief render`: trace, shade and write a picture (and optionally depth and normals, and
//! the stage timings with `--stats`).

use super::{
    check_image_held, render_clipmap, render_hybrid, render_mesh, render_mlhm, render_tiles,
};
use crate::args::MlhmRenderMode;
use crate::args::RenderArgs;
use crate::memory::ImageHolding;
use crate::scene::height_field::{check_safety_view, HeightFieldScene};
use crate::scene::stacks::is_stacks_file;
use crate::tracers::{self, TracerChoice};
use crate::{input, memory, outputs, progress};
use anyhow::{bail, Context, Result};
use relief_core::Camera;
use relief_shade::{render_to_srgb8, shade_to_srgb8, sun_shadow_sweep, GBuffer, KeptHits};
use relief_trace::{Simd, Tracer};
use serde_json::{json, Value};
use std::path::Path;
use std::time::Instant;

/// Runs `relief render`: an MLHM scene (`.json`) takes [`render_mlhm`], any other input the
/// height-field path.
pub fn run(args: &RenderArgs) -> Result<()> {
    let started = Instant::now();
    if let Some(path) = &args.scene.input.input {
        crate::scene::check_input(path, "relief render")?;
    }
    check_outputs(args)?;
    let scene_args = &args.scene;
    let budget = memory::budget(scene_args.input.read.max_memory);
    let (w, h) = scene_args.size;
    check_image_held(w, h, image_holding(args), &budget)?;
    if let Some(path) = scene_args.input.input.as_deref().filter(|p| input::is_tile_store(p)) {
        return render_tiles::run(args, path, started);
    }
    if let Some(option) = args.tiles.given() {
        let here = crate::applies::input_kind(scene_args.input.input.as_deref());
        return Err(crate::applies::refuse(option, "tile stores (made by relief tile)", &here));
    }
    let stacks_file = scene_args.input.input.as_deref().is_some_and(is_stacks_file);
    if scene_args.mode == Some(MlhmRenderMode::Mesh) || stacks_file {
        return render_mesh::run(args, started);
    }
    for (given, option) in
        [(scene_args.tau.is_some(), "--tau"), (scene_args.voxel_height.is_some(), "--voxel-height")]
    {
        if given {
            return Err(crate::applies::refuse(option, "--mode mesh", "the ray-cast renderers"));
        }
    }
    if let Some(path) = scene_args.input.input.as_deref().filter(|p| input::is_mlhm_scene(p)) {
        if let Some(option) = args.hybrid.given() {
            let here = crate::applies::input_kind(Some(path));
            return Err(crate::applies::refuse(option, "height fields (--tracer hybrid)", &here));
        }
        return render_mlhm::run(args, path, started);
    }
    let scene = HeightFieldScene::open(scene_args)?;
    let load_ms = outputs::ms_since(started);
    if scene.choice == TracerChoice::Hybrid {
        return render_hybrid::run(args, &scene, started, load_ms);
    }
    if scene.choice == TracerChoice::Clipmap {
        if let Some(option) = args.hybrid.given() {
            return Err(crate::applies::refuse(option, "--tracer hybrid", "the clipmap renderer"));
        }
        return render_clipmap::run(args, &scene, started, load_ms);
    }
    if let Some(option) = args.hybrid.given() {
        let here = format!("the {} tracer", scene.choice);
        return Err(crate::applies::refuse(option, "--tracer hybrid", &here));
    }
    let build_started = Instant::now();
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
    let pixels = camera.width() as usize * camera.height() as usize;
    let sweep = sun_shadow_sweep(tracer.as_ref(), &scene.field, surface, &scene.params, pixels);
    let shadow_tracer: &dyn Tracer = match &sweep {
        Some(sweep) => sweep,
        None => tracer.as_ref(),
    };
    let build_ms = outputs::ms_since(build_started);

    let summary = format!("{surface} {choice} tracer");
    // Traced and shaded strip by strip, with no image-sized G-buffer.
    let bar = progress::bar(pixels as u64, "rendering");
    let keep = KeptHits { depth: args.depth.is_some(), normals: args.normals.is_some() };
    let bounds = scene.bounds();
    let drawn = render_to_srgb8(
        tracer.as_ref(),
        shadow_tracer,
        camera,
        &bounds,
        &scene.params,
        keep,
        &|n| bar.inc(n),
    )?;
    bar.finish_and_clear();
    let stats = &drawn.stats;
    let rendered = Rendered {
        rgb: drawn.rgb.as_flattened(),
        depth: drawn.depth.as_deref(),
        normals: drawn.normals.as_deref(),
        hits: stats.primary.hits,
        shadow_rays: stats.shadow.rays,
        load_ms,
        build_ms,
        trace_ms: stats.trace_ms,
        shade_ms: stats.shade_ms,
    };
    let extra = json!({ "mean_steps": stats.primary.mean_steps() });
    write_and_report(args, &scene, &choice.to_string(), rendered, started, &summary, extra)
}

/// How the renderer `args` choose holds its picture: strip by strip for a height field drawn
/// by the naive, mipmap and safety tracers, as the MLHM renderer does for an MLHM scene, a
/// whole-image G-buffer for any other.
fn image_holding(args: &RenderArgs) -> ImageHolding {
    let scene = &args.scene;
    let input = scene.input.input.as_deref();
    let mesh = scene.mode == Some(MlhmRenderMode::Mesh) || input.is_some_and(is_stacks_file);
    if input.is_some_and(input::is_mlhm_scene) && !mesh {
        return ImageHolding::Mlhm;
    }
    let whole = mesh
        || input.is_some_and(input::is_tile_store)
        || matches!(scene.tracer, Some(TracerChoice::Hybrid | TracerChoice::Clipmap));
    if whole {
        ImageHolding::WholeGBuffer
    } else {
        ImageHolding::Strips { depth: args.depth.is_some(), normals: args.normals.is_some() }
    }
}

/// A height field's G-buffer as a renderer drew it, with what shading and `--stats` need.
pub(super) struct Drawn<'a> {
    /// The primary hits.
    pub gbuffer: &'a GBuffer,
    /// The exact tracer the shadow rays take.
    pub shadow_tracer: &'a dyn Tracer,
    /// Milliseconds to read the input, build the renderer and fill the G-buffer.
    pub load_ms: f64,
    pub build_ms: f64,
    pub trace_ms: f64,
}

/// The end every height-field renderer shares: shades `drawn` (then `recolour` the pixels,
/// counted in the shading time), then [`write_and_report`]s.
#[allow(clippy::too_many_arguments)]
pub(super) fn shade_and_write(
    args: &RenderArgs,
    scene: &HeightFieldScene,
    tracer: &str,
    drawn: Drawn,
    started: Instant,
    recolour: impl FnOnce(&mut [[u8; 3]]),
    summary: &str,
    extra: Value,
) -> Result<()> {
    let shade_started = Instant::now();
    let (mut rgb, shadow) =
        shade_to_srgb8(drawn.gbuffer, drawn.shadow_tracer, &scene.camera, &scene.params)?;
    recolour(&mut rgb);
    let rendered = Rendered {
        rgb: rgb.as_flattened(),
        depth: Some(&drawn.gbuffer.distance),
        normals: Some(&drawn.gbuffer.normal),
        hits: drawn.gbuffer.distance.iter().filter(|d| d.is_finite()).count() as u64,
        shadow_rays: shadow.rays,
        load_ms: drawn.load_ms,
        build_ms: drawn.build_ms,
        trace_ms: drawn.trace_ms,
        shade_ms: outputs::ms_since(shade_started),
    };
    write_and_report(args, scene, tracer, rendered, started, summary, extra)
}

/// A height field's picture, shaded, with what `--stats` reports.
struct Rendered<'a> {
    /// The picture, 8-bit sRGB.
    rgb: &'a [u8],
    /// The distances to the primary hits, where the renderer kept them (for --depth).
    depth: Option<&'a [f32]>,
    /// The normals of the primary hits, where the renderer kept them (for --normals).
    normals: Option<&'a [[f32; 3]]>,
    hits: u64,
    shadow_rays: u64,
    load_ms: f64,
    build_ms: f64,
    trace_ms: f64,
    shade_ms: f64,
}

/// Writes the outputs `args` asks for, says `wrote PATH (WxH, summary)`, and with `--stats`
/// writes the keys every renderer has (input, terrain, surface, `tracer`, image, rays, hits,
/// shadow rays and the stage timings) and those of `extra`.
#[allow(clippy::too_many_arguments)]
fn write_and_report(
    args: &RenderArgs,
    scene: &HeightFieldScene,
    tracer: &str,
    rendered: Rendered,
    started: Instant,
    summary: &str,
    extra: Value,
) -> Result<()> {
    let camera = &scene.camera;
    let write_started = Instant::now();
    write_pictures_and_arrays(args, camera, rendered.rgb, rendered.depth, rendered.normals)?;
    let write_ms = outputs::ms_since(write_started);
    let (w, h) = (camera.width(), camera.height());
    eprintln!("wrote {} ({w}x{h}, {summary})", args.output.display());
    let Some(path) = &args.stats else { return Ok(()) };
    let field = &scene.field;
    let mut stats = json!({
        "input": input_name(args),
        "kind": "height field",
        "terrain": [field.width(), field.height()],
        "surface": scene.surface.to_string(),
        "tracer": tracer,
        "width": w,
        "height": h,
        "threads": rayon::current_num_threads(),
        "rays": u64::from(w) * u64::from(h),
        "hits": rendered.hits,
        "shadow_rays": rendered.shadow_rays,
        "load_ms": rendered.load_ms,
        "build_ms": rendered.build_ms,
        "trace_ms": rendered.trace_ms,
        "shade_ms": rendered.shade_ms,
        "write_ms": write_ms,
        "total_ms": outputs::ms_since(started),
    });
    if let (Some(all), Value::Object(extra)) = (stats.as_object_mut(), extra) {
        all.extend(extra);
    }
    outputs::write_stats(path, &stats)
}

/// The input `relief render` drew, for `--stats`: its path, or the fBm terrain it generated.
pub(super) fn input_name(args: &RenderArgs) -> Value {
    match &args.scene.input.input {
        Some(path) => json!(path.display().to_string()),
        None => json!("fbm"),
    }
}

/// Refuses, before any work, outputs whose format or folder is wrong, and two outputs (or an
/// output and the input) that are one file.
fn check_outputs(args: &RenderArgs) -> Result<()> {
    outputs::check_writable(&args.output)?;
    let format = outputs::picture_format("-o", &args.output)?;
    if args.png_compression.is_some() && format != outputs::PictureFormat::Png {
        bail!("--png-compression: -o {} is not a .png picture", args.output.display());
    }
    let mut all = vec![("-o", args.output.as_path())];
    for (option, path) in [("--depth", &args.depth), ("--normals", &args.normals)] {
        if let Some(path) = path {
            outputs::check_writable(path)?;
            outputs::check_npy(option, path)?;
            all.push((option, path.as_path()));
        }
    }
    if let Some(path) = &args.stats {
        outputs::check_stats(path)?;
        all.push(("--stats", path.as_path()));
    }
    let scene = &args.scene;
    let inputs: Vec<&Path> =
        [scene.input.input.as_deref(), scene.texture.as_deref()].into_iter().flatten().collect();
    outputs::check_distinct(&all, &inputs)
}

/// The picture of the tone-mapped `rgb`, and the depth and normals of `gbuffer` where asked
/// for.
pub(super) fn write_outputs(
    args: &RenderArgs,
    camera: &Camera,
    gbuffer: &GBuffer,
    rgb: &[u8],
) -> Result<()> {
    write_pictures_and_arrays(args, camera, rgb, Some(&gbuffer.distance), Some(&gbuffer.normal))
}

/// The picture of the tone-mapped `rgb` (compressed as `--png-compression` says), and the
/// depth and normals where asked for (the renderer must have kept them: row-major images from
/// the top).
fn write_pictures_and_arrays(
    args: &RenderArgs,
    camera: &Camera,
    rgb: &[u8],
    depth: Option<&[f32]>,
    normals: Option<&[[f32; 3]]>,
) -> Result<()> {
    let png = args.png_compression.unwrap_or_default();
    outputs::write_picture(&args.output, camera.width(), camera.height(), rgb, png)?;
    let (h, w) = (camera.height() as usize, camera.width() as usize);
    for (path, array, shape) in [
        (&args.depth, depth, vec![h, w]),
        (&args.normals, normals.map(<[[f32; 3]]>::as_flattened), vec![h, w, 3]),
    ] {
        if let Some(path) = path {
            let array = array.context("the renderer kept no such array")?;
            relief_io::write_npy_f32(path, &shape, array)?;
        }
    }
    Ok(())
}
