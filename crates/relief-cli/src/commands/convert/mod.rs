//! `relief convert`: read a height file and write it in another format, or an MLHM in the
//! other MLHM file (`.json` scene <-> `.mlhm`).
//!
//! A height file keeps its CRS, its placement (in the CRS's own units) and its heights as
//! stored, in their own unit, in every format that can hold them (see
//! [`relief_io::write_height_field_georeferenced`]); what could not be kept is said.

pub mod args;

use super::generate::write_mlhm;
use crate::args::Voids;
use crate::{applies, input, outputs};
use anyhow::{bail, Result};
use args::ConvertArgs;
use relief_core::GridGeometry;
use relief_io::VoidPolicy;

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
    let raster = relief_io::read_raster(&args.input, &input::read_options(&args.read))?;
    let (info, voids) = (raster.info.clone(), raster.void_count());
    let policy = match args.read.voids.unwrap_or(Voids::Hole) {
        Voids::Fill => VoidPolicy::Fill,
        Voids::Hole => VoidPolicy::Hole,
    };
    let field = raster.into_height_field(&args.input, policy)?;
    outputs::check_height_file(&args.output, Some((field.width(), field.height())))?;
    // The heights as stored, in their own unit: the writer records the unit where the format
    // can, and converts them to metres where it cannot.
    let stored = GridGeometry { z_scale: 1.0, ..*field.geometry() };
    let field = field.with_geometry(stored)?;
    let unit = &info.height_unit;
    let notes = relief_io::write_height_field_georeferenced(
        &args.output,
        &field,
        info.georeference.as_ref(),
        unit.unit,
    )?;
    let crs = info.georeference.as_ref().map_or("no georeference".into(), |g| g.crs_name());
    eprintln!(
        "wrote {} ({} x {}, {voids} voids; {crs}; heights in {unit})",
        args.output.display(),
        field.width(),
        field.height()
    );
    for note in notes {
        eprintln!("  {note}");
    }
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
