//! What `relief render` and `relief view` draw, opened from the command line's [`SceneArgs`] (any
//! input they take: [`check_input`]): a height field or an MLHM scene with its tracer choice, its
//! shading and the starting camera. Both commands open scenes here, so that a view's frame at rest
//! is the picture `relief render` makes of the same camera.

pub mod height_field;
pub mod mlhm;
pub mod stacks;

use crate::applies;
use crate::args::SceneArgs;
use anyhow::Result;
use relief_core::{Aabb, Camera, DVec3, Framing, Lens, Projection};

/// Every input `relief render`, `relief view` and `relief flythrough` take, for messages.
pub const SCENE_INPUTS: &str = "a height file (.tif, .tiff, .hgt, .asc, .png, .npy or .npz), \
    an MLHM scene (.json with its .dat, or .mlhm), a material-stacks terrain (.stacks), or a \
    tile store (the folder relief tile makes)";

/// Refuses an input `command` cannot draw, naming every input it takes: a folder that is not
/// a tile store, a path that does not exist and names no format, or a file whose extension
/// names no format it reads.
pub fn check_input(path: &std::path::Path, command: &str) -> Result<()> {
    let shown = path.display();
    if path.is_dir() {
        if crate::input::is_tile_store(path) {
            return Ok(());
        }
        anyhow::bail!(
            "{shown} is a folder without an index.json, so not a tile store made by relief \
             tile; {command} takes {SCENE_INPUTS}"
        );
    }
    let known = ["tif", "tiff", "hgt", "asc", "png", "npy", "npz", "json", "mlhm", "stacks"];
    match applies::extension(path) {
        Some(e) if known.contains(&e.as_str()) => Ok(()),
        _ if !path.exists() => {
            anyhow::bail!("{shown}: no such file or folder; {command} takes {SCENE_INPUTS}")
        }
        _ => anyhow::bail!("{shown}: unsupported file type; {command} takes {SCENE_INPUTS}"),
    }
}

/// The vertical field of view when `--fov` is not given, in degrees.
pub const DEFAULT_FOV_DEG: f64 = 45.0;

/// The camera given on the command line: `--eye` and `--target`, or the framing of `bounds`
/// from `--view` (default: from the south-west, 30 degrees up), pinhole or (`--ortho`)
/// orthographic. An up vector parallel to the view (a camera looking straight down) is
/// replaced by north, with a note saying so. `--fov` with `--ortho`, and `--ortho-height`
/// without it, are refused: they would do nothing.
pub fn camera(args: &SceneArgs, bounds: &Aabb) -> Result<Camera> {
    let (w, h) = args.size;
    if args.ortho && args.fov.is_some() {
        return Err(applies::refuse("--fov", "perspective cameras", "--ortho"));
    }
    if !args.ortho && args.ortho_height.is_some() {
        return Err(applies::refuse("--ortho-height", "--ortho", "a perspective camera"));
    }
    let fov_deg = args.fov.unwrap_or(DEFAULT_FOV_DEG);
    let lens = match args.ortho {
        true => Lens::Orthographic { height: args.ortho_height },
        false => Lens::Perspective { fov_deg },
    };
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
            match lens {
                Lens::Perspective { fov_deg } => Camera::look_at(eye, target, up, fov_deg, w, h)?,
                Lens::Orthographic { height } => {
                    // Checks the eye, target and up before framing with them.
                    let probe = Projection::Orthographic { height: height.unwrap_or(1.0) };
                    let camera = Camera::new(eye, target, up, probe, w, h)?;
                    if height.is_some() {
                        camera
                    } else {
                        let framing = Framing {
                            towards_eye: eye - target,
                            up,
                            target: Some(target),
                            distance: Some((eye - target).length()),
                            lens,
                        };
                        let fitted = Camera::framed(bounds, &framing, w, h)?.projection();
                        Camera::new(eye, target, up, fitted, w, h)?
                    }
                }
            }
        }
        _ => match args.view {
            Some(view) => {
                let framing = Framing {
                    target: args.target,
                    distance: view.distance,
                    ..Framing::heading(view.azimuth_deg, view.elevation_deg, lens)
                };
                Camera::framed(bounds, &framing, w, h)?
            }
            None if args.ortho => {
                Camera::framed(bounds, &Framing::heading(45.0, 30.0, lens), w, h)?
            }
            None => Camera::frame_from(bounds, 225.0, 30.0, fov_deg, w, h)?,
        },
    };
    Ok(camera)
}
