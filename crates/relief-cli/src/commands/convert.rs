//! `relief convert`: read a height file and write it in another format, or an MLHM in the
//! other MLHM file (`.json` scene <-> `.mlhm`).

use super::generate::write_mlhm;
use crate::args::{ConvertArgs, Voids};
use crate::{applies, input, outputs};
use anyhow::{bail, Result};

/// Runs `relief convert`.
pub fn run(args: &ConvertArgs) -> Result<()> {
    outputs::check_distinct(&[("OUT", &args.output)], &[&args.input])?;
    outputs::check_writable(&args.output)?;
    if input::is_mlhm_scene(&args.input) {
        return convert_mlhm(args);
    }
    if input::is_mlhm_scene(&args.output) {
        bail!(
            "{} is a height file; only an MLHM (.json scene or .mlhm) converts to {}",
            args.input.display(),
            args.output.display()
        );
    }
    outputs::check_height_file(&args.output, None)?;
    applies::check_read_args(&args.read, Some(&args.input))?;
    let (_, field, voids) = input::read(&args.input, &args.read, Voids::Hole)?;
    outputs::check_height_file(&args.output, Some((field.width(), field.height())))?;
    relief_io::write_height_field(&args.output, &field)?;
    eprintln!(
        "wrote {} ({} x {}, {voids} voids)",
        args.output.display(),
        field.width(),
        field.height()
    );
    Ok(())
}

/// Converts the MLHM at `args.input` to the MLHM file `args.output` names (`.json` or
/// `.mlhm`), at the input's precision. A `.mlhm` keeps only the map: a scene's simulation
/// state and settings are left out.
fn convert_mlhm(args: &ConvertArgs) -> Result<()> {
    if !input::is_mlhm_scene(&args.output) {
        bail!(
            "{} is an MLHM; it converts to a .json scene or a .mlhm file, not to {}",
            args.input.display(),
            args.output.display()
        );
    }
    if args.read.voids.is_some() {
        return Err(applies::refuse("--voids", "height files", "MLHM scenes"));
    }
    applies::check_read_args(&args.read, Some(&args.input))?;
    let scene = input::load_mlhm(&args.input, &args.read)?;
    write_mlhm(&args.output, &scene)?;
    let map = &scene.mlhm;
    eprintln!(
        "wrote {} ({} x {} cells of {} m, {} layers)",
        args.output.display(),
        map.width(),
        map.height(),
        map.cell_size(),
        map.max_layers()
    );
    Ok(())
}
