//! `relief convert`: read a height file and write it in another format.

use super::check_output;
use crate::args::{ConvertArgs, Voids};
use crate::input;
use anyhow::Result;

/// Runs `relief convert`.
pub fn run(args: &ConvertArgs) -> Result<()> {
    check_output(&args.output)?;
    let (_, field, voids) = input::read(&args.input, &args.read, Voids::Hole)?;
    relief_io::write_height_field(&args.output, &field)?;
    eprintln!(
        "wrote {} ({} x {}, {voids} voids)",
        args.output.display(),
        field.width(),
        field.height()
    );
    Ok(())
}
