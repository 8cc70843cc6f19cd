//! `relief flythrough`: a camera path (docs/camera-path.md) rendered frame after frame into a
//! folder of PNGs. A tile store is flown with one streamer for the whole flight, its frames
//! not waiting for tiles (coarser ones in memory stand in); any other input `relief render`
//! takes is opened once as `relief view` opens it, and each frame traced and shaded as
//! `relief render` draws that camera.

pub mod args;
mod flight_plan;
mod log;

use super::check_frame;
use super::view::open_live_scene;
use crate::opening::open_scene;
use crate::scene_checks::{check_input, drawn, Drawn};
use crate::{applies, memory, outputs, progress};
use anyhow::{anyhow, bail, Context, Result};
use args::FlythroughArgs;
use flight_plan::plan;
use log::{FlightFrame, FlightLog};
use relief_core::Camera;
use relief_render::{Scene, StoreScene};
use relief_viewer::{Cancel, SceneRenderer, ViewSettings};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// Runs `relief flythrough`: every check first (outputs, options, the path and each frame's
/// camera), then the scene opened, then the frames, each written atomically.
pub fn run(args: &FlythroughArgs) -> Result<()> {
    let started = Instant::now();
    refuse_camera_options(args)?;
    if let Some(path) = &args.scene.input.input {
        check_input(path, "relief flythrough")?;
    }
    check_outputs(args)?;
    let flight = plan(args)?;
    let scene_args = &args.scene;
    let budget = memory::budget(scene_args.input.read.max_memory);
    check_frame(scene_args, &budget)?;
    let drawer = FrameDrawer::open(args)?;
    let load_ms = outputs::ms_since(started);
    let build_started = Instant::now();
    drawer.prepare(&flight.cameras[0])?;
    let build_ms = outputs::ms_since(build_started);
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("-o {}: cannot create the folder", args.output.display()))?;

    let digits = frame_digits(args.frames);
    let mut log = FlightLog::new(drawer.describe(), drawer.is_store());
    let bar = progress::bar(u64::from(args.frames), "flying");
    for (index, (camera, &time_s)) in flight.cameras.iter().zip(&flight.times).enumerate() {
        let frame_started = Instant::now();
        let drawn = drawer.draw(camera, index == 0, args.wait)?;
        let time_ms = outputs::ms_since(frame_started);
        let write_started = Instant::now();
        let file = args.output.join(format!("frame-{index:0digits$}.png"));
        outputs::write_picture(
            &file,
            camera.width(),
            camera.height(),
            drawn.rgb.as_flattened(),
            args.png_compression,
        )
        .with_context(|| format!("writing {}", file.display()))?;
        let frame = FlightFrame {
            frame: index as u32,
            time_s,
            time_ms,
            write_ms: outputs::ms_since(write_started),
            rss_bytes: memory::resident_bytes(),
            tiles: drawn.tiles,
            note: drawn.note,
        };
        bar.suspend(|| eprintln!("{}", frame.line()));
        log.push(frame);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let (w, h) = scene_args.size;
    eprintln!(
        "wrote {} frames ({w}x{h}) to {} as frame-{}.png: {}",
        args.frames,
        args.output.display(),
        "N".repeat(digits),
        log.summary_line()
    );
    let Some(stats_path) = &args.stats else { return Ok(()) };
    let stats = log.to_json(args, &flight, load_ms, build_ms, outputs::ms_since(started));
    outputs::write_stats(stats_path, &stats)
}

/// Digits of the frame numbers in the file names: five, or more when the last frame needs
/// them.
fn frame_digits(frames: u32) -> usize {
    frames.saturating_sub(1).to_string().len().max(5)
}

/// Refuses `relief render`'s camera options: a fly-through's cameras come from `--path`.
fn refuse_camera_options(args: &FlythroughArgs) -> Result<()> {
    let scene = &args.scene;
    let given = [
        (scene.eye.is_some(), "--eye"),
        (scene.target.is_some(), "--target"),
        (scene.up.is_some(), "--up"),
        (scene.view.is_some(), "--view"),
        (scene.fov.is_some(), "--fov"),
        (scene.ortho, "--ortho"),
        (scene.ortho_height.is_some(), "--ortho-height"),
    ];
    match given.into_iter().find_map(|(given, name)| given.then_some(name)) {
        Some(option) => Err(applies::refuse(
            option,
            "relief render",
            "relief flythrough (its cameras come from --path)",
        )),
        None => Ok(()),
    }
}

/// Refuses, before any work, an `-o` that is a file (not a folder) or the input, and a
/// `--stats` that is not a `.json` in an existing folder or that names an input.
fn check_outputs(args: &FlythroughArgs) -> Result<()> {
    if args.output.exists() && !args.output.is_dir() {
        bail!("-o {}: not a folder (the frames are written into a folder)", args.output.display());
    }
    let mut all = vec![("-o", args.output.as_path())];
    if let Some(path) = &args.stats {
        outputs::check_stats(path)?;
        all.push(("--stats", path.as_path()));
    }
    let scene = &args.scene;
    let inputs: Vec<&Path> =
        [scene.input.input.as_deref(), scene.texture.as_deref(), Some(args.path.as_path())]
            .into_iter()
            .flatten()
            .collect();
    outputs::check_distinct(&all, &inputs)
}

/// What draws the frames: a tile store's streamer, or the renderer `relief view` draws any
/// other input with.
enum FrameDrawer {
    /// A tile store, with one streamer (cache and loader) for the whole flight.
    Store(Box<StoreScene>),
    /// Any other input, opened once, drawn as `relief render` draws it.
    Scene {
        /// The scene's renderer.
        renderer: Arc<dyn SceneRenderer>,
        /// Its tracer, surface, light and exposure, as the command line set them.
        settings: ViewSettings,
    },
}

/// A frame as drawn: its pixels and what drawing it did.
struct DrawnFrame {
    /// sRGB pixels, rows from the top.
    rgb: Vec<[u8; 3]>,
    /// For a tile store, the tiles the frame asked for, drew and stood in.
    tiles: Option<relief_tiles::FrameStats>,
    /// What the renderer did other than asked, if anything.
    note: Option<String>,
}

impl FrameDrawer {
    /// Opens the input of `args`: a tile store (its options checked), or any other input
    /// (refusing `--wait` and the tile-store options, which do nothing for it).
    fn open(args: &FlythroughArgs) -> Result<Self> {
        let scene_args = &args.scene;
        if drawn(scene_args) == Drawn::Store {
            let opened = open_scene(scene_args, Some(&args.tiles), None)?;
            let Scene::Store(store) = opened.scene else { bail!("a tile store opens as a store") };
            return Ok(FrameDrawer::Store(Box::new(store)));
        }
        let here = applies::input_kind(scene_args.input.input.as_deref());
        let given = args.tiles.given().or(args.wait.then_some("--wait"));
        if let Some(option) = given {
            return Err(applies::refuse(option, "tile stores (made by relief tile)", &here));
        }
        let (renderer, _, settings) = open_live_scene(scene_args, None, "relief flythrough")?;
        Ok(FrameDrawer::Scene { renderer, settings })
    }

    /// Whether the frames come from a tile store.
    fn is_store(&self) -> bool {
        matches!(self, FrameDrawer::Store(_))
    }

    /// The input in a few words.
    fn describe(&self) -> String {
        match self {
            FrameDrawer::Store(scene) => scene.describe(),
            FrameDrawer::Scene { renderer, .. } => renderer.describe(),
        }
    }

    /// Builds what the first frame would otherwise build (a scene's tracer, an MLHM's
    /// hierarchy) by drawing a 1x1 picture of `camera`'s view, so that frame times are times
    /// of frames. A tile store has nothing to build: its first frame waits for its tiles.
    fn prepare(&self, camera: &Camera) -> Result<()> {
        let FrameDrawer::Scene { renderer, settings } = self else { return Ok(()) };
        let (eye, target, up) = (camera.eye(), camera.target(), camera.up());
        let dot = Camera::new(eye, target, up, camera.projection(), 1, 1)?;
        renderer.render(&dot, settings, &Cancel::new()).map_err(|e| anyhow!(e))?;
        Ok(())
    }

    /// Draws `camera`'s frame. A tile store's frame waits for its tiles when it is the
    /// `first` (so that it is not all stand-ins) or when `wait` says every frame waits.
    fn draw(&self, camera: &Camera, first: bool, wait: bool) -> Result<DrawnFrame> {
        match self {
            FrameDrawer::Store(scene) => {
                let frame =
                    relief_render::draw::store::frame(scene, camera, &scene.params, first || wait)?;
                Ok(DrawnFrame { rgb: frame.rgb, tiles: Some(frame.tiles), note: None })
            }
            FrameDrawer::Scene { renderer, settings } => {
                let frame =
                    renderer.render(camera, settings, &Cancel::new()).map_err(|e| anyhow!(e))?;
                Ok(DrawnFrame { rgb: frame.rgb, tiles: None, note: frame.note })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_numbers_fit_the_frame_count() {
        assert_eq!(frame_digits(1), 5);
        assert_eq!(frame_digits(100_000), 5);
        assert_eq!(frame_digits(100_001), 6);
    }
}
