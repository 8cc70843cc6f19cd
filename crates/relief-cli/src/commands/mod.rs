//! One module per subcommand.

mod bench;
mod bench_dynamic;
mod compare;
mod convert;
mod flythrough;
mod flythrough_log;
mod generate;
mod info;
mod info_mlhm;
mod info_stacks;
mod info_tiles;
mod mesh;
mod render;
mod render_clipmap;
mod render_hybrid;
mod render_mesh;
mod render_mlhm;
mod render_tiles;
mod shade;
mod simulate;
mod simulate_frames;
mod tile;
mod view;

pub(crate) use simulate::{scene_params, start_state};

use crate::args::{Cli, Command};
use crate::memory::Budget;
use anyhow::{bail, Result};

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
    }
}

/// Bytes an image takes per pixel while it is rendered: the G-buffer (56), the linear radiance
/// (12) and the 8-bit output (3).
const BYTES_PER_PIXEL: u64 = 71;

/// Refuses an image of `width x height` pixels that would not fit the memory `budget`.
fn check_image(width: u32, height: u32, budget: &Budget) -> Result<()> {
    let needed = width as u64 * height as u64 * BYTES_PER_PIXEL;
    if needed > budget.bytes {
        bail!(
            "a {width}x{height} image needs {} MiB, over the {} MiB memory limit ({})",
            needed >> 20,
            budget.bytes >> 20,
            budget.origin
        );
    }
    Ok(())
}
