//! One module per subcommand.

mod bench;
mod convert;
mod generate;
mod info;
mod render;
mod render_mlhm;

use crate::args::{Cli, Command};
use anyhow::{bail, Result};
use std::path::Path;

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Generate(command) => generate::run(&command),
        Command::Info(args) => info::run(&args),
        Command::Convert(args) => convert::run(&args),
        Command::Bench(args) => bench::run(&args),
    }
}

/// Bytes an image takes per pixel while it is rendered: the G-buffer (56), the linear radiance
/// (12) and the 8-bit output (3).
const BYTES_PER_PIXEL: u64 = 71;

/// Refuses an image of `width x height` pixels that would not fit the memory budget;
/// `limit_origin` says where the budget comes from.
fn check_image(width: u32, height: u32, max_memory: u64, limit_origin: &str) -> Result<()> {
    let needed = width as u64 * height as u64 * BYTES_PER_PIXEL;
    if needed > max_memory {
        bail!(
            "a {width}x{height} image needs {} MiB, over the {} MiB memory limit ({limit_origin})",
            needed >> 20,
            max_memory >> 20
        );
    }
    Ok(())
}

/// Refuses an output path whose folder does not exist or that names a folder, before any work.
fn check_output(path: &Path) -> Result<()> {
    if path.is_dir() {
        bail!("output {} is a directory", path.display());
    }
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        bail!("output folder {} does not exist", parent.display());
    }
    Ok(())
}
