//! `relief render`: open the scene, draw it from the camera, write the picture (and
//! optionally depth and normals, and the stage timings with `--stats`).

pub mod args;

use super::check_antialiased_image_held;
use crate::args::SceneArgs;
use crate::memory::ImageHolding;
use crate::opening::open_scene;
use crate::scene_checks::{check_input, drawn, Drawn};
use crate::{applies, memory, outputs, progress};
use anyhow::{bail, Context, Result};
use args::RenderArgs;
use relief_render::{KeptHits, Picture, TracerChoice};
use serde_json::{json, Value};
use std::path::Path;
use std::time::Instant;

/// Runs `relief render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    let started = Instant::now();
    if let Some(path) = &args.scene.input.input {
        check_input(path, "relief render")?;
    }
    check_outputs(args)?;
    let scene_args = &args.scene;
    let budget = memory::budget(scene_args.input.read.max_memory);
    let (w, h) = scene_args.size;
    check_antialiased_image_held(w, h, image_holding(args), args.aa, &budget)?;
    refuse_renderer_options(args)?;
    let opened = open_scene(scene_args, Some(&args.tiles), Some(&args.hybrid))?;
    let furniture = args.furniture.furniture();
    let colours = opened.scene.height_colours();
    furniture.check(&opened.camera, colours.as_ref())?;
    let load_ms = outputs::ms_since(started);

    let keep = KeptHits { depth: args.depth.is_some(), normals: args.normals.is_some() };
    let bars = progress::Bars::default();
    let mut picture = opened.scene.render(&opened.camera, keep, args.aa, &bars)?;
    furniture.draw(&mut picture, &opened.camera, colours.as_ref())?;
    for note in &picture.notes {
        eprintln!("{note}");
    }
    let write_started = Instant::now();
    write_picture_and_arrays(args, &picture)?;
    let write_ms = outputs::ms_since(write_started);
    let (w, h) = (picture.width, picture.height);
    eprintln!("wrote {} ({w}x{h}, {})", args.output.display(), picture.summary);
    let Some(path) = &args.stats else { return Ok(()) };
    let mut stats = picture.stats;
    stats.insert("input".into(), input_name(scene_args));
    stats.insert("load_ms".into(), json!(load_ms));
    stats.insert("write_ms".into(), json!(write_ms));
    stats.insert("total_ms".into(), json!(outputs::ms_since(started)));
    outputs::write_stats(path, &Value::Object(stats))
}

/// Refuses the hybrid renderer's options for any other renderer, and the tile stores' for
/// any other input.
fn refuse_renderer_options(args: &RenderArgs) -> Result<()> {
    let scene = &args.scene;
    let path = scene.input.input.as_deref();
    let drawn = drawn(scene);
    if drawn != Drawn::Store {
        if let Some(option) = args.tiles.given() {
            let here = applies::input_kind(path);
            return Err(applies::refuse(option, "tile stores (made by relief tile)", &here));
        }
    }
    let Some(option) = args.hybrid.given() else { return Ok(()) };
    let shown = path.map(Path::display);
    match drawn {
        Drawn::Store => {
            let here = format!("a tile store ({})", shown.expect("a store has a path"));
            Err(applies::refuse(option, "--tracer hybrid", &here))
        }
        Drawn::Mesh => bail!("{option} applies to --tracer hybrid, not to --mode mesh"),
        Drawn::Mlhm => {
            let here = applies::input_kind(path);
            Err(applies::refuse(option, "height fields (--tracer hybrid)", &here))
        }
        Drawn::HeightField => match &scene.tracer {
            Some(TracerChoice::Hybrid) => Ok(()),
            Some(TracerChoice::Clipmap) => {
                Err(applies::refuse(option, "--tracer hybrid", "the clipmap renderer"))
            }
            choice => {
                let choice =
                    choice.clone().unwrap_or(TracerChoice::Plain(relief_trace::TracerKind::Mipmap));
                let here = format!("the {choice} tracer");
                Err(applies::refuse(option, "--tracer hybrid", &here))
            }
        },
    }
}

/// How the renderer `args` choose holds its picture: strip by strip for a height field drawn
/// by the naive, mipmap and safety tracers, as the MLHM renderer does for an MLHM scene, a
/// whole-image G-buffer for any other.
fn image_holding(args: &RenderArgs) -> ImageHolding {
    let scene = &args.scene;
    match drawn(scene) {
        Drawn::Mlhm => ImageHolding::Mlhm,
        Drawn::Store | Drawn::Mesh => ImageHolding::WholeGBuffer,
        Drawn::HeightField
            if matches!(scene.tracer, Some(TracerChoice::Hybrid | TracerChoice::Clipmap)) =>
        {
            ImageHolding::WholeGBuffer
        }
        Drawn::HeightField => {
            ImageHolding::Strips { depth: args.depth.is_some(), normals: args.normals.is_some() }
        }
    }
}

/// The input `relief render` drew, for `--stats`: its path, or the fBm terrain it generated.
fn input_name(scene: &SceneArgs) -> Value {
    match &scene.input.input {
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

/// The picture (compressed as `--png-compression` says), and the depth and normals where
/// asked for (row-major images from the top).
fn write_picture_and_arrays(args: &RenderArgs, picture: &Picture) -> Result<()> {
    let png = args.png_compression.unwrap_or_default();
    let (w, h) = (picture.width, picture.height);
    outputs::write_picture(&args.output, w, h, picture.rgb_bytes(), png)?;
    let (h, w) = (h as usize, w as usize);
    for (path, array, shape) in [
        (&args.depth, picture.depth.as_deref(), vec![h, w]),
        (&args.normals, picture.normals.as_deref().map(<[[f32; 3]]>::as_flattened), vec![h, w, 3]),
    ] {
        if let Some(path) = path {
            let array = array.context("the renderer kept no such array")?;
            relief_io::write_npy_f32(path, &shape, array)?;
        }
    }
    Ok(())
}
