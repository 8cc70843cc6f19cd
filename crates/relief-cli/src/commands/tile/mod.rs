//! `relief tile`: a tile pyramid of a raster or mosaic, built in bounded memory and resumable.

pub mod args;

use crate::{outputs, progress};
use anyhow::{bail, Context, Result};
use args::TileArgs;
use relief_io::{ReadOptions, RowSource};
use relief_tiles::{
    build_textured_store, place_ortho, precision_name, BuildOptions, DemPlacement, SourceFile,
    TextureInput,
};
use std::path::{Path, PathBuf};

/// The build's memory limit where `--max-memory` gives none.
const DEFAULT_MAX_MEMORY: u64 = 1 << 30;

/// Runs `relief tile`.
pub fn run(args: &TileArgs) -> Result<()> {
    check_output(args)?;
    let max_memory = args.max_memory.unwrap_or(DEFAULT_MAX_MEMORY);
    let sources = args.inputs.iter().map(|p| source_file(p)).collect::<Result<Vec<_>>>()?;
    let mut rows = open_rows(&args.inputs, max_memory, args.z_unit)?;
    let options = BuildOptions {
        tile: args.tile,
        precision: args.precision.unwrap_or_default(),
        max_memory,
        fail_after: None,
    };
    let mut ortho = args.texture.as_deref().map(relief_io::open_ortho).transpose()?;
    let texture = match (&mut ortho, &args.texture) {
        (Some(photo), Some(path)) => {
            let info = rows.info();
            let dem = DemPlacement {
                width: rows.width() as u64,
                height: rows.height() as u64,
                geometry: rows.geometry(),
                georeference: info.georeference.as_ref(),
            };
            let placement = place_ortho(&dem, photo.info())?;
            Some(TextureInput { rows: photo.as_mut(), placement, source: source_file(path)? })
        }
        _ => None,
    };
    let bar = progress::bar(0, "tiling");
    let report = build_textured_store(
        rows.as_mut(),
        sources,
        texture,
        &args.output,
        &options,
        &|done, total| {
            bar.set_length(total);
            bar.set_position(done);
        },
    )?;
    bar.finish_and_clear();
    let (out, precision) = (args.output.display(), precision_name(options.precision));
    let store = format!(
        "{} x {} samples, {} tiles of {}^2 {precision}",
        rows.width(),
        rows.height(),
        report.tiles,
        args.tile
    );
    if report.built == 0 && report.texture_built == 0 && report.resumed > 0 {
        eprintln!("{out} is complete ({store}): nothing to do");
        return Ok(());
    }
    let mb = report.samples_read as f64 * 4.0 / 1e6;
    let resumed = match report.resumed {
        0 => String::new(),
        n => format!(", {n} kept from the interrupted build"),
    };
    let texture = match report.texture_tiles {
        0 => String::new(),
        n => format!(", {n} of them the texture's, built in {:.1} s", report.texture_seconds),
    };
    eprintln!(
        "wrote {out} ({store}{texture}{resumed}) in {:.1} s, {:.0} MB/s of input samples",
        report.seconds,
        mb / (report.seconds - report.texture_seconds).max(1e-9),
    );
    Ok(())
}

/// Refuses an output that is a file, or one of the inputs.
fn check_output(args: &TileArgs) -> Result<()> {
    let out = &args.output;
    if out.is_file() {
        bail!("-o {}: a file is there; a tile store is a folder", out.display());
    }
    let inputs: Vec<&Path> =
        args.inputs.iter().chain(&args.texture).map(PathBuf::as_path).collect();
    outputs::check_distinct(&[("-o", out.as_path())], &inputs)
}

/// The input as rows read on request: one raster (streamed for GeoTIFF, .hgt and .npy), or
/// a mosaic of several (.hgt tiles by their names, GeoTIFFs by their georeference), its
/// heights in `z_unit` when given.
fn open_rows(
    paths: &[PathBuf],
    max_memory: u64,
    z_unit: Option<relief_io::LengthUnit>,
) -> Result<Box<dyn RowSource>> {
    let options = ReadOptions { max_memory, z_unit, ..ReadOptions::default() };
    match paths {
        [one] => Ok(relief_io::open_rows(one, &options)?),
        _ => Ok(relief_io::open_mosaic(paths, &options)?),
    }
}

/// What the build records of an input file, so that a resumed build can tell it changed.
pub(crate) fn source_file(path: &Path) -> Result<SourceFile> {
    let meta = std::fs::metadata(path).with_context(|| format!("{}", path.display()))?;
    let modified_ns = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_nanos());
    Ok(SourceFile { path: path.display().to_string(), bytes: meta.len(), modified_ns })
}
