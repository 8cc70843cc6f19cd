//! One module per subcommand.

pub mod bench;
pub mod compare;
pub mod convert;
pub mod flythrough;
pub mod generate;
pub mod info;
pub mod mesh;
pub mod render;
pub mod shade;
pub mod simulate;
pub mod tile;
pub mod view;
pub mod viewshed;

use crate::cli::{Cli, Command};
use crate::memory::{format_bytes, Budget, ImageHolding};
use anyhow::{bail, Result};
use relief_render::Antialiasing;

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Generate(command) => generate::run(&command),
        Command::Info(args) => info::run(&args),
        Command::Convert(args) => convert::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::View(args) => view::run(&args),
        Command::Shade(args) => shade::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Tile(args) => tile::run(&args),
        Command::Flythrough(args) => flythrough::run(&args),
        Command::Mesh(args) => mesh::run(&args),
        Command::Viewshed(args) => viewshed::run(&args),
    }
}

/// Bytes a pixel takes while a whole-image G-buffer renderer draws it (what `relief info`
/// quotes).
const BYTES_PER_PIXEL: u64 = crate::memory::GBUFFER_BYTES_PER_PIXEL;

/// Refuses an image of `width x height` pixels that a whole-image G-buffer renderer (bench's
/// frames) could not hold within the memory `budget`.
fn check_image(width: u32, height: u32, budget: &Budget) -> Result<()> {
    check_image_held(width, height, ImageHolding::WholeGBuffer, budget)
}

/// Refuses a frame of the scene `scene` names (at its `--size`) that the viewer's and
/// flythrough's renderers could not hold within the memory `budget`: an MLHM scene's, or a
/// whole-image G-buffer.
fn check_frame(scene: &crate::args::SceneArgs, budget: &Budget) -> Result<()> {
    let input = scene.input.input.as_deref();
    let mesh = scene.mode == Some(crate::args::MlhmRenderMode::Mesh);
    let holding = if input.is_some_and(crate::input::is_mlhm_scene) && !mesh {
        ImageHolding::Mlhm
    } else {
        ImageHolding::WholeGBuffer
    };
    check_image_held(scene.size.0, scene.size.1, holding, budget)
}

/// Refuses an image of `width x height` pixels that would not fit the memory `budget` held
/// as `holding` says.
fn check_image_held(width: u32, height: u32, holding: ImageHolding, budget: &Budget) -> Result<()> {
    check_antialiased_image_held(width, height, holding, Antialiasing::Off, budget)
}

/// [`check_image_held`] for a picture anti-aliased as `aa` says.
fn check_antialiased_image_held(
    width: u32,
    height: u32,
    holding: ImageHolding,
    aa: Antialiasing,
    budget: &Budget,
) -> Result<()> {
    let threads = rayon::current_num_threads();
    let needed = crate::memory::image_bytes(width, height, holding, threads)
        + crate::memory::antialiasing_bytes(width, height, aa);
    if needed > budget.bytes {
        bail!(
            "a {width}x{height} image needs {}, over the {} memory limit ({})",
            format_bytes(needed),
            format_bytes(budget.bytes),
            budget.origin
        );
    }
    Ok(())
}
