//! Opening the scene the command line names: its options checked against its input, the
//! scene opened by the scene layer, its camera placed, and what the user should know said.

use crate::applies;
use crate::args::{HybridArgs, SceneArgs, TileRenderArgs};
use crate::scene_checks::{check_scene_args, drawn, refuse_mesh_options};
use crate::scene_options::{camera_options, scene_options};
use anyhow::Result;
use relief_core::Camera;
use relief_render::{place_camera, Scene, StacksScene};

/// A scene opened from the command line, with the camera it names.
pub struct Opened {
    /// The scene.
    pub scene: Scene,
    /// The camera of `--eye`/`--target`, or the framing of `--view`.
    pub camera: Camera,
}

/// Opens the scene `args` name (a tile store's options from `tiles`, the hybrid renderer's
/// from `hybrid`, where the command takes them), refusing the options that do nothing for
/// it, and places its camera; its warnings and the camera's notes go to stderr.
pub fn open_scene(
    args: &SceneArgs,
    tiles: Option<&TileRenderArgs>,
    hybrid: Option<&HybridArgs>,
) -> Result<Opened> {
    check_scene_args(args, drawn(args))?;
    let camera_options = camera_options(args)?;
    let path = args.input.input.as_deref();
    let scene = Scene::open(path, &scene_options(args, tiles, hybrid))?;
    if let (Scene::Store(store), Some(tiles), Some(path)) = (&scene, tiles, path) {
        if let Some(option) = tiles.texture_given().filter(|_| store.texture.is_none()) {
            let here = match args.texture {
                Some(_) => "--texture, which drapes its own picture".to_string(),
                None => format!("a tile store without a texture ({})", path.display()),
            };
            let what = "textured tile stores (relief tile --texture)";
            return Err(applies::refuse(option, what, &here));
        }
    }
    for warning in scene.warnings() {
        eprintln!("{warning}");
    }
    let placed = scene.camera(&camera_options)?;
    if let Some(note) = &placed.note {
        eprintln!("{note}");
    }
    if let Some(warning) = scene.camera_warning(&placed.camera) {
        eprintln!("{warning}");
    }
    Ok(Opened { scene, camera: placed.camera })
}

/// Opens the input `args` name as material stacks (for `here`, the command, in refusals of
/// the options that do nothing for a mesh) and places its camera; its warnings and the
/// camera's notes go to stderr.
pub fn open_stacks(args: &SceneArgs, here: &str) -> Result<(StacksScene, Camera)> {
    refuse_mesh_options(args, here)?;
    let camera_options = camera_options(args)?;
    let path = args.input.input.as_deref();
    let scene = StacksScene::open(path, &scene_options(args, None, None))?;
    for warning in &scene.warnings {
        eprintln!("{warning}");
    }
    let placed = place_camera(&camera_options, &scene.bounds)?;
    if let Some(note) = &placed.note {
        eprintln!("{note}");
    }
    if let Some(warning) = scene.camera_warning(&placed.camera) {
        eprintln!("{warning}");
    }
    Ok((scene, placed.camera))
}
