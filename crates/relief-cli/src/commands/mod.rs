//! One module per subcommand.

mod bench;
mod convert;
mod generate;
mod info;
mod render;

use crate::args::{Cli, Command, GenerateCommand};
use anyhow::{bail, Result};
use std::path::Path;

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Generate(GenerateCommand::Fbm(args)) => generate::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Convert(args) => convert::run(&args),
        Command::Bench(args) => bench::run(&args),
    }
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
