//! Which of the scene options apply to the input given: every input `relief render`, `relief
//! view` and `relief flythrough` take, and the options that would do nothing for it, refused
//! before any work with the messages of [`applies`].

use crate::applies;
use crate::args::{MlhmRenderMode, SceneArgs};
use crate::input;
use anyhow::Result;
use relief_core::Surface;
use relief_render::{InputKind, TracerChoice};
use relief_shade::{ColourMap, NormalStyle};
use std::path::Path;

/// Every input `relief render`, `relief view` and `relief flythrough` take, for messages.
pub const SCENE_INPUTS: &str = "a height file (.tif, .tiff, .hgt, .asc, .png, .npy or .npz), \
    an MLHM scene (.json with its .dat, or .mlhm), a material-stacks terrain (.stacks), or a \
    tile store (the folder relief tile makes)";

/// Refuses an input `command` cannot draw, naming every input it takes: a folder that is not
/// a tile store, a path that does not exist and names no format, or a file whose extension
/// names no format it reads.
pub fn check_input(path: &Path, command: &str) -> Result<()> {
    let shown = path.display();
    if path.is_dir() {
        if input::is_tile_store(path) {
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

/// How the scene `args` name is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drawn {
    /// A tile store, its tiles streamed.
    Store,
    /// Material stacks, meshed (a .stacks file, or `--mode mesh`).
    Mesh,
    /// An MLHM scene, ray cast.
    Mlhm,
    /// A height field, ray cast (or by the hybrid or clipmap renderer).
    HeightField,
}

/// How the scene `args` name is drawn.
pub fn drawn(args: &SceneArgs) -> Drawn {
    let kind = InputKind::of(args.input.input.as_deref());
    match kind {
        InputKind::TileStore => Drawn::Store,
        InputKind::Stacks => Drawn::Mesh,
        _ if args.mode == Some(MlhmRenderMode::Mesh) => Drawn::Mesh,
        InputKind::Mlhm => Drawn::Mlhm,
        _ => Drawn::HeightField,
    }
}

/// Refuses the options of `args` that do nothing for the scene it names, drawn as `drawn`.
pub fn check_scene_args(args: &SceneArgs, drawn: Drawn) -> Result<()> {
    let path = args.input.input.as_deref();
    if drawn != Drawn::Mesh && drawn != Drawn::Store {
        for (given, option) in [
            (args.tau.is_some(), "--tau"),
            (args.voxel_height.is_some(), "--voxel-height"),
            (args.node_budget.is_some(), "--node-budget"),
        ] {
            if given {
                return Err(applies::refuse(option, "--mode mesh", "the ray-cast renderers"));
            }
        }
    }
    check_colour_args(args, drawn)?;
    check_shading_normals(args, drawn)?;
    match (drawn, path) {
        (Drawn::Store, Some(path)) => refuse_store_options(args, path),
        (Drawn::Mesh, _) => refuse_mesh_options(args, "--mode mesh"),
        (Drawn::Mlhm, Some(path)) => refuse_mlhm_scene_options(args, path),
        _ => refuse_height_field_scene_options(args),
    }
}

/// The first colour option `args` give, if any.
pub fn colour_option_given(args: &SceneArgs) -> Option<&'static str> {
    [
        (args.colormap.is_some(), "--colormap"),
        (args.height_range.is_some(), "--height-range"),
        (args.sea_level.is_some(), "--sea-level"),
    ]
    .into_iter()
    .find_map(|(given, name)| given.then_some(name))
}

/// Refuses the colour options where they would do nothing: for MLHM scenes and stacks
/// meshes (coloured by their materials), with `--texture`, and `--sea-level` for a map
/// without a sea.
fn check_colour_args(args: &SceneArgs, drawn: Drawn) -> Result<()> {
    let Some(option) = colour_option_given(args) else { return Ok(()) };
    let here = match drawn {
        Drawn::Mlhm => Some("MLHM scenes (coloured by their materials)".to_string()),
        Drawn::Mesh => Some("--mode mesh (coloured by the materials)".to_string()),
        _ if args.texture.is_some() => Some("--texture (which colours the terrain)".to_string()),
        _ => None,
    };
    if let Some(here) = here {
        return Err(applies::refuse(option, "height fields and tile stores", &here));
    }
    let map = args.colormap.unwrap_or(ColourMap::Terrain);
    if args.sea_level.is_some() && !map.has_sea_level() {
        return Err(applies::refuse(
            "--sea-level",
            "--colormap bathymetry",
            &format!("the {map} colour map"),
        ));
    }
    Ok(())
}

/// Refuses `--shading-normals` where it would do nothing: for MLHM scenes (which shade
/// their own surfaces; stacks meshes refuse it with [`refuse_mesh_options`]), and smooth
/// normals for the boxes surface (always faceted).
fn check_shading_normals(args: &SceneArgs, drawn: Drawn) -> Result<()> {
    let Some(style) = args.shading_normals else { return Ok(()) };
    let here = match drawn {
        Drawn::Mlhm => "MLHM scenes",
        Drawn::Mesh => return Ok(()),
        Drawn::HeightField | Drawn::Store => {
            if style == NormalStyle::Smooth && args.surface == Some(Surface::Boxes) {
                return Err(applies::refuse(
                    "--shading-normals smooth",
                    "--surface triangles",
                    "--surface boxes (always faceted)",
                ));
            }
            return Ok(());
        }
    };
    Err(applies::refuse("--shading-normals", "height fields and tile stores", here))
}

/// Refuses the options of `args` that do nothing for a tile store (at `path`).
fn refuse_store_options(args: &SceneArgs, path: &Path) -> Result<()> {
    let here = format!("a tile store ({})", path.display());
    let input = &args.input;
    let given = [
        (args.tracer.is_some(), "--tracer"),
        (args.mode.is_some(), "--mode"),
        (args.preset.is_some(), "--preset"),
        (input.read.voids.is_some(), "--voids"),
        (input.spacing.is_some(), "--spacing"),
        (input.north_up, "--north-up"),
    ];
    match given.into_iter().find_map(|(given, name)| given.then_some(name)) {
        Some(option) => Err(applies::refuse(option, "height files", &here)),
        None => Ok(()),
    }
}

/// Refuses the options of tracers and MLHM rendering that do nothing for a stacks mesh;
/// `here` names the command, and the reading options that do nothing for the input.
pub fn refuse_mesh_options(args: &SceneArgs, here: &str) -> Result<()> {
    if let Some(option) = colour_option_given(args) {
        return Err(applies::refuse(option, "height fields and tile stores", here));
    }
    if args.shading_normals.is_some() {
        return Err(applies::refuse("--shading-normals", "height fields and tile stores", here));
    }
    for (given, option) in [
        (args.tracer.is_some(), "--tracer"),
        (args.surface.is_some(), "--surface"),
        (args.preset.is_some(), "--preset"),
        (args.hierarchy_bounds.is_some(), "--hierarchy-bounds"),
        (args.backtrack.is_some(), "--backtrack"),
        (args.texture.is_some(), "--texture"),
        (args.no_ao, "--no-ao"),
        (applies::safety_option_given(&args.safety).is_some(), "the safety options"),
    ] {
        if given {
            return Err(applies::refuse(option, "the ray-cast renderers", here));
        }
    }
    match args.input.input.as_deref() {
        Some(path) if input::is_stacks_file(path) => {
            applies::check_read_args(&args.input.read, Some(path))
        }
        Some(path) if input::is_mlhm_scene(path) => Ok(()),
        _ => input::check_input_args(&args.input),
    }
}

/// Refuses the options that do nothing for the MLHM scene at `path`: the smoothing radius of
/// boxes, and those that place or read a height field, or shade one.
fn refuse_mlhm_scene_options(args: &SceneArgs, path: &Path) -> Result<()> {
    let boxes = args.mode.unwrap_or(MlhmRenderMode::Boxes) == MlhmRenderMode::Boxes;
    if args.sigma.is_some() && boxes {
        return Err(applies::refuse("--sigma", "--mode smooth", "--mode boxes"));
    }
    let input = &args.input;
    if let Some(option) = applies::safety_option_given(&args.safety) {
        return Err(applies::refuse(option, "the safety tracer of height fields", "MLHM scenes"));
    }
    let what = match () {
        _ if args.surface.is_some_and(|s| s != Surface::Boxes) => {
            "--surface triangles (an MLHM scene renders as boxes, see --mode)"
        }
        _ if input.spacing.is_some() => "--spacing (the scene's cell size places it)",
        _ if input.north_up => "--north-up",
        _ if input.z_scale != 1.0 => "--z-scale",
        _ if input.read.voids.is_some() => "--voids",
        _ if input.fbm_size.is_some() => "--fbm-size",
        _ if input.seed.is_some() => "--seed",
        _ if args.texture.is_some() => "--texture (an MLHM scene is coloured by its materials)",
        _ => return applies::check_read_args(&args.input.read, Some(path)),
    };
    Err(applies::refuse(what, "height fields", "MLHM scenes"))
}

/// Refuses the options only an MLHM scene takes, and the safety tracer's for another tracer,
/// for a height field.
fn refuse_height_field_scene_options(args: &SceneArgs) -> Result<()> {
    let what = if args.tracer == Some(TracerChoice::Hierarchy) {
        Some("--tracer hierarchy")
    } else if args.mode.is_some() {
        Some("--mode")
    } else if args.backtrack.is_some() {
        Some("--backtrack")
    } else if args.preset.is_some() {
        Some("--preset")
    } else if args.hierarchy_bounds.is_some() {
        Some("--hierarchy-bounds")
    } else if args.sigma.is_some() {
        Some("--sigma")
    } else if args.no_ao {
        Some("--no-ao")
    } else {
        None
    };
    if let Some(what) = what {
        let here = applies::input_kind(args.input.input.as_deref());
        return Err(applies::refuse(what, "MLHM scenes (.json, .mlhm)", &here));
    }
    let choice =
        args.tracer.clone().unwrap_or(TracerChoice::Plain(relief_trace::TracerKind::Mipmap));
    if !matches!(choice, TracerChoice::Safety(_)) {
        if let Some(option) = applies::safety_option_given(&args.safety) {
            let here = format!("the {choice} tracer");
            return Err(applies::refuse(option, "the safety tracer", &here));
        }
    }
    input::check_input_args(&args.input)
}
