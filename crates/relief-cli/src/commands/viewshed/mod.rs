//! `relief viewshed`: which samples of a DEM an observer sees, or how many of several
//! observers see each one, written on the DEM's grid with its georeference, CRS and nodata.

pub mod args;

use crate::{applies, input, memory, outputs, progress};
use anyhow::{bail, Result};
use args::ViewshedArgs;
use relief_core::HeightField;
use relief_io::{Georeference, Layer, LayerRaster};
use relief_shade::viewshed::{viewshed, Observer, ViewshedParams, DEFAULT_OBSERVER_HEIGHT};
use relief_trace::{build_tracer, TracerKind};
use std::sync::Arc;
use std::time::Instant;

/// Runs `relief viewshed`.
pub fn run(args: &ViewshedArgs) -> Result<()> {
    check_outputs(args)?;
    if args.observer.is_empty() {
        bail!("no observer: give at least one --observer X,Y[,HEIGHT]");
    }
    applies::check_read_args(&args.read, Some(&args.input))?;
    if input::is_mlhm_scene(&args.input) {
        bail!("{} is an MLHM scene; relief viewshed takes height files", args.input.display());
    }
    let budget = memory::budget(args.read.max_memory);

    let start = Instant::now();
    let raster = relief_io::read_raster(&args.input, &input::read_options(&args.read))?;
    let samples = raster.width as u64 * raster.height as u64;
    // The field, the voids' mask, the pyramid (a third more than the field), the counts (as
    // integers and as the output's floats) and the flags of the sweeps run side by side (one
    // per thread).
    let threads = rayon::current_num_threads() as u64;
    let needed = samples * (4 + 1 + 2 + 4 + 4 + threads);
    if needed > budget.bytes {
        bail!(
            "a viewshed of {} x {} samples needs {}, over the {} memory limit ({})",
            raster.width,
            raster.height,
            memory::format_bytes(needed),
            memory::format_bytes(budget.bytes),
            budget.origin
        );
    }
    let input::MappedField { field, void, voids, info } =
        input::mapped_field(raster, &args.input, &args.read, args.spacing, args.z_scale)?;
    let observers = args
        .observer
        .iter()
        .map(|&(x, y, eye)| {
            let (wx, wy) = world_point(&field, info.georeference.as_ref(), x, y)?;
            Ok(Observer::new(wx, wy, eye.unwrap_or(DEFAULT_OBSERVER_HEIGHT)))
        })
        .collect::<Result<Vec<_>>>()?;
    let read_ms = elapsed_ms(start);

    let start = Instant::now();
    let field = Arc::new(field);
    let tracer = build_tracer(field.clone(), args.surface, TracerKind::Mipmap);
    let build_ms = elapsed_ms(start);

    let start = Instant::now();
    let params =
        ViewshedParams { observers, target_height: args.target_height, radius: args.radius };
    let total_rows = field.height() as u64 * params.observers.len() as u64;
    let bar = progress::bar(total_rows, "viewshed");
    let mask = (voids > 0).then_some(void.as_slice());
    let result = viewshed(&field, &*tracer, mask, &params, &|rows| bar.set_position(rows));
    bar.finish_and_clear();
    let result = result?;
    let trace_ms = elapsed_ms(start);

    let start = Instant::now();
    let name = if params.observers.len() == 1 { "visible" } else { "observers" };
    let seen = result.counts.iter().filter(|&&c| c > 0.0).count();
    let raster = LayerRaster {
        width: result.width,
        height: result.height,
        layers: vec![Layer { name: name.to_string(), samples: result.counts }],
        georeference: info.georeference.clone(),
        nodata: info.nodata.or((voids > 0).then_some(f64::NAN)),
    };
    relief_io::write_layers_geotiff(&args.output, &raster)?;
    let write_ms = elapsed_ms(start);

    eprintln!(
        "wrote {} ({} x {} samples, {} observer{}; {} of them seen by at least one; {} lines \
         of sight in {:.2} s)",
        args.output.display(),
        result.width,
        result.height,
        params.observers.len(),
        if params.observers.len() == 1 { "" } else { "s" },
        seen,
        result.rays,
        trace_ms / 1e3
    );
    if let Some(path) = &args.stats {
        let stats = serde_json::json!({
            "samples": samples,
            "voids": voids,
            "observers": params.observers.len(),
            "seen": seen,
            "rays": result.rays,
            "read_ms": read_ms,
            "build_ms": build_ms,
            "trace_ms": trace_ms,
            "write_ms": write_ms,
        });
        outputs::write_stats(path, &stats)?;
    }
    Ok(())
}

/// Refuses outputs that cannot be written before any work.
fn check_outputs(args: &ViewshedArgs) -> Result<()> {
    let output = &args.output;
    outputs::check_writable(output)?;
    if !matches!(applies::extension(output).as_deref(), Some("tif" | "tiff")) {
        bail!("-o {}: a viewshed is written as a .tif (GeoTIFF)", output.display());
    }
    let mut all = vec![("-o", output.as_path())];
    if let Some(stats) = &args.stats {
        outputs::check_stats(stats)?;
        all.push(("--stats", stats.as_path()));
    }
    outputs::check_distinct(&all, &[&args.input])?;
    Ok(())
}

/// The world point of `field` at (`x`, `y`) in the DEM's own coordinates: through its
/// `georeference` (the file's geotransform) when it has one, else the field's own
/// coordinates. Refuses a point outside the DEM.
fn world_point(
    field: &HeightField,
    georeference: Option<&Georeference>,
    x: f64,
    y: f64,
) -> Result<(f64, f64)> {
    let (w, h) = (field.width() as f64, field.height() as f64);
    let g = field.geometry();
    let (col, row, extent) = match georeference {
        Some(georeference) => {
            let [x0, a, b, y0, d, e] = georeference.geotransform;
            let det = a * e - b * d;
            if det == 0.0 || !det.is_finite() {
                bail!("the DEM's geotransform {:?} cannot be inverted", georeference.geotransform);
            }
            // Pixel coordinates from the outer corner of the file's first pixel.
            let u = (e * (x - x0) - b * (y - y0)) / det;
            let v = (a * (y - y0) - d * (x - x0)) / det;
            let row = if georeference.is_south_up() { v } else { h - v };
            let corners = [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)]
                .map(|(u, v)| (x0 + u * a + v * b, y0 + u * d + v * e));
            let (xs, ys) = (corners.map(|c| c.0), corners.map(|c| c.1));
            let lo_hi = |v: [f64; 4]| {
                (
                    v.iter().copied().fold(f64::INFINITY, f64::min),
                    v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                )
            };
            (u, row, (lo_hi(xs), lo_hi(ys)))
        }
        None => {
            let (col, row) = ((x - g.origin.x) / g.dx, (y - g.origin.y) / g.dy);
            let x1 = g.origin.x + w * g.dx;
            let y1 = g.origin.y + h * g.dy;
            (col, row, ((g.origin.x, x1), (g.origin.y, y1)))
        }
    };
    if !((0.0..=w).contains(&col) && (0.0..=h).contains(&row)) {
        let ((x0, x1), (y0, y1)) = extent;
        bail!(
            "--observer {x},{y} lies outside the DEM, which spans x {x0} to {x1} and y {y0} to {y1}"
        );
    }
    Ok((g.origin.x + col * g.dx, g.origin.y + row * g.dy))
}

/// Milliseconds since `start`.
fn elapsed_ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}
