//! `relief view`: the interactive viewer (relief-viewer) over any scene `relief render`
//! takes (a tile store too), drawn by the live scenes of [`relief_viewer::live`] (an MLHM scene's
//! erosion simulation run, paused and stepped from the viewer).

pub mod args;

use super::check_frame;
use crate::args::{SceneArgs, TileRenderArgs};
use crate::opening::open_scene;
use crate::scene_checks::{check_input, drawn, Drawn};
use crate::{applies, memory, outputs, progress};
use anyhow::{bail, Result};
use args::ViewArgs;
use relief_core::Camera;
use relief_render::TracerChoice;
use relief_viewer::live::live_scene;
use relief_viewer::{SceneRenderer, Script, ViewSettings, ViewerConfig};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

/// Runs `relief view`: checks the outputs and the display, opens the scene, and runs the
/// window until it is closed (or `--frames` are done), then prints what the frames took.
/// Without a display, a `--frames` run draws the same frames headless, with no window.
/// The viewer flies pinhole cameras only: `--ortho` is refused.
pub fn run(args: &ViewArgs) -> Result<()> {
    for (given, option) in
        [(args.scene.ortho, "--ortho"), (args.scene.ortho_height.is_some(), "--ortho-height")]
    {
        if given {
            return Err(applies::refuse(option, "relief render", "relief view"));
        }
    }
    if let Some(path) = &args.scene.input.input {
        check_input(path, "relief view")?;
    }
    let script = args.script.as_deref().map(Script::parse).transpose()?.unwrap_or_default();
    let output_dir = check_outputs(args)?;
    let headless = args.frames.is_some() && relief_viewer::check_display().is_err();
    if !headless {
        relief_viewer::check_display()?;
    }
    let scene_args = &args.scene;
    let budget = memory::budget(scene_args.input.read.max_memory);
    check_frame(scene_args, &budget)?;
    let (renderer, camera, settings) = open(args)?;
    match headless {
        true => eprintln!(
            "viewing the {} headless (no display): {} frames, no window",
            renderer.describe(),
            args.frames.unwrap_or_default()
        ),
        false => eprintln!("viewing the {}; F1 in the window lists the keys", renderer.describe()),
    }
    std::fs::create_dir_all(&output_dir)
        .map_err(|e| anyhow::anyhow!("--output-dir {}: {e}", output_dir.display()))?;
    let config = ViewerConfig {
        size: scene_args.size,
        camera,
        settings,
        frames: args.frames,
        script,
        screenshot: args.screenshot.clone(),
        output_dir,
        stats: args.stats.clone(),
        frame_budget: Duration::from_millis(args.frame_budget),
    };
    let summary = match headless {
        true => relief_viewer::run_headless(renderer, config)?,
        false => relief_viewer::run(renderer, config)?,
    };
    for line in summary.report() {
        eprintln!("{line}");
    }
    if let Some(path) = &args.stats {
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// The scene's renderer, its starting camera and settings (the tile-store options refused
/// for any other input).
fn open(args: &ViewArgs) -> Result<(Arc<dyn SceneRenderer>, Camera, ViewSettings)> {
    let scene_args = &args.scene;
    if drawn(scene_args) != Drawn::Store {
        if let Some(option) = args.tiles.given() {
            let here = applies::input_kind(scene_args.input.input.as_deref());
            return Err(applies::refuse(option, "tile stores (made by relief tile)", &here));
        }
    }
    open_live_scene(scene_args, Some(&args.tiles), "relief view")
}

/// The renderer of the scene `scene_args` name (a tile store's options from `tiles`), drawn
/// as `relief render` draws it, with its starting camera and settings; an MLHM scene's
/// simulation may run. `command` names the command for the refusal of the hybrid and
/// clipmap renderers, which draw with `relief render` only.
pub(super) fn open_live_scene(
    scene_args: &SceneArgs,
    tiles: Option<&TileRenderArgs>,
    command: &str,
) -> Result<(Arc<dyn SceneRenderer>, Camera, ViewSettings)> {
    if drawn(scene_args) == Drawn::HeightField {
        if let Some(choice @ (TracerChoice::Hybrid | TracerChoice::Clipmap)) = &scene_args.tracer {
            bail!(
                "{command} draws with the naive, mipmap and safety tracers; the {choice} \
                 renderer draws with relief render and relief bench"
            );
        }
    }
    let opened = open_scene(scene_args, tiles, None)?;
    let live = live_scene(opened.scene, &progress::Bars::default())?;
    for note in &live.notes {
        eprintln!("{note}");
    }
    Ok((live.renderer, opened.camera, live.settings))
}

/// Refuses, before any work, a screenshot that is not a PNG, outputs in folders that do not
/// exist or that overwrite the input; the folder screenshots (P) and paths (R) go to
/// (made when the scene opens, if it does not exist).
fn check_outputs(args: &ViewArgs) -> Result<PathBuf> {
    let mut all = Vec::new();
    if let Some(path) = &args.screenshot {
        outputs::check_writable(path)?;
        if applies::extension(path).as_deref() != Some("png") {
            bail!("--screenshot {}: a screenshot is written as .png", path.display());
        }
        all.push(("--screenshot", path.as_path()));
    }
    if let Some(path) = &args.stats {
        outputs::check_writable(path)?;
        if applies::extension(path).as_deref() != Some("json") {
            bail!("--stats {}: the frame times are written as .json", path.display());
        }
        all.push(("--stats", path.as_path()));
    }
    let scene = &args.scene;
    let inputs: Vec<&Path> =
        [scene.input.input.as_deref(), scene.texture.as_deref()].into_iter().flatten().collect();
    outputs::check_distinct(&all, &inputs)?;
    let dir = args.output_dir.clone().unwrap_or_else(|| PathBuf::from("."));
    if dir.exists() && !dir.is_dir() {
        bail!("--output-dir {} is not a folder (a file is there)", dir.display());
    }
    Ok(dir)
}
