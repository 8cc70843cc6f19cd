//! `relief info`: what a height file holds and what rendering it costs (an MLHM scene:
//! [`mlhm`]).

pub mod args;
mod mlhm;
mod stacks;
mod tiles;

use super::BYTES_PER_PIXEL;
use crate::{applies, input};
use anyhow::Result;
use args::InfoArgs;
use std::io::Write;

/// Runs `relief info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    if input::is_mlhm_scene(&args.input) {
        return mlhm::run(args);
    }
    if crate::input::is_stacks_file(&args.input) {
        return stacks::run(args);
    }
    if args.input.is_dir() {
        return tiles::run(args);
    }
    if args.read.voids.is_some() {
        // info counts the voids; how a render resolves them changes nothing it reports.
        let here = "relief info, which reports the voids as they are stored";
        return Err(applies::refuse("--voids", "render and convert", here));
    }
    applies::check_read_args(&args.read, Some(&args.input))?;
    let mut out = std::io::stdout().lock();
    let raster = relief_io::read_raster(&args.input, &input::read_options(&args.read))?;
    let info = &raster.info;
    let g = &raster.geometry;
    let samples = raster.samples.len() as f64;
    writeln!(out, "file:        {}", args.input.display())?;
    writeln!(out, "format:      {}", info.format)?;
    writeln!(
        out,
        "size:        {} x {} samples ({})",
        raster.width, raster.height, info.sample_type
    )?;
    let unit = if info.georeferenced { "m" } else { "grid units, set with --spacing" };
    match &info.from_degrees {
        Some(deg) => writeln!(
            out,
            "spacing:     {:.3} x {:.3} m (from {:.3}\" x {:.3}\" at latitude {:.3}°)",
            g.dx,
            g.dy,
            deg.dlon * 3600.0,
            deg.dlat * 3600.0,
            deg.latitude
        ),
        None => writeln!(out, "spacing:     {} x {} ({unit})", g.dx, g.dy),
    }?;
    writeln!(out, "origin:      {}, {} (south-west corner, {unit})", g.origin.x, g.origin.y)?;
    let crs = match &info.georeference {
        Some(g) => {
            let [x0, a, _, y0, _, e] = g.geotransform;
            format!("{} (corner {x0}, {y0}; pixel {a} x {})", g.crs_name(), -e)
        }
        None => "none (no georeference)".into(),
    };
    writeln!(out, "crs:         {crs}")?;
    let height_unit = &info.height_unit;
    writeln!(out, "heights:     in {height_unit}")?;
    let metres = |v: f32| f64::from(v) * g.z_scale;
    match raster.value_range() {
        Some((lo, hi)) if g.z_scale != 1.0 => writeln!(
            out,
            "values:      {lo} .. {hi} (in {}: {:.3} .. {:.3} m)",
            height_unit.unit,
            metres(lo),
            metres(hi)
        ),
        Some((lo, hi)) => writeln!(out, "values:      {lo} .. {hi}"),
        None => writeln!(out, "values:      none (every sample is a void)"),
    }?;
    let nodata = info.nodata.map_or("none declared".to_string(), |v| v.to_string());
    writeln!(out, "nodata:      {} voids (nodata value: {nodata})", raster.void_count())?;
    // Samples as f32 and the max mipmap (a third of them), plus a flag a sample for holes.
    let per_sample = 4.0 + 4.0 / 3.0 + if raster.void_count() > 0 { 1.0 } else { 0.0 };
    let render_mib = samples * per_sample / 1048576.0;
    writeln!(
        out,
        "to render:   about {render_mib:.1} MiB for the terrain, plus about 3.5 bytes a pixel and \
         a strip G-buffer a thread ({BYTES_PER_PIXEL} bytes a pixel in the hybrid, clipmap and mesh modes)"
    )?;
    Ok(())
}
