//! `relief shade`: shade rasters of a DEM, aligned with it sample for sample, written with
//! its georeference, CRS and nodata.

pub mod args;
mod blocks;
pub mod when;

use crate::{applies, input, memory, outputs, progress};
use anyhow::{bail, Result};
use args::ShadeArgs;
use relief_io::{Layer, LayerRaster, RasterInfo};
use relief_shade::horizon::HorizonParams;
use relief_shade::shade_map::{shade_map, ShadeMap, ShadeMapParams, SunPosition};
use relief_shade::ShadeLayer;
use relief_trace::{build_tracer, TracerKind};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;
use when::SunTimes;

/// How `relief shade` writes its layers, by the output's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadeOutput {
    /// A float32 GeoTIFF, one band per layer.
    GeoTiff,
    /// A 16-bit grey PNG of one layer, with a world file.
    Png,
}

/// Runs `relief shade`.
pub fn run(args: &ShadeArgs) -> Result<()> {
    let format = check_outputs(args)?;
    let params = params(args)?;
    applies::check_read_args(&args.read, Some(&args.input))?;
    if input::is_mlhm_scene(&args.input) {
        bail!("{} is an MLHM scene; relief shade makes maps of height files", args.input.display());
    }
    let budget = memory::budget(args.read.max_memory);
    if args.input.is_dir() {
        return blocks::run(args, format, params, &budget, None);
    }
    // The field, the voids' mask, the tracer's pyramid (a third more than the field), the
    // bands, and each horizon engine (up, and down for negative openness): over the budget,
    // the raster is shaded block by block.
    let (width, height) = {
        let rows = relief_io::open_rows(&args.input, &input::read_options(&args.read))?;
        (rows.width(), rows.height())
    };
    let samples = width as u64 * height as u64;
    let bands = params.band_names().len() as u64;
    let engines = params.horizon_engines() as u64 * params.horizon.engine_bytes_per_sample();
    let needed = samples * (4 + 1 + 2 + 4 * bands + engines);
    if needed > budget.bytes {
        let store = blocks::temporary_store(&args.output);
        return blocks::run(args, format, params, &budget, Some(&store));
    }

    let start = Instant::now();
    let raster = relief_io::read_raster(&args.input, &input::read_options(&args.read))?;
    let (width, height) = (raster.width, raster.height);
    let input::MappedField { field, void, voids, info } =
        input::mapped_field(raster, &args.input, &args.read, args.spacing, args.z_scale)?;
    let mut params = params;
    match when::sun_samples(&args.when, info.georeference.as_ref(), width, height)? {
        SunTimes::NotAsked => {}
        SunTimes::Instant(sun) => params.suns = vec![sun],
        SunTimes::Period(suns) => params.insolation = suns,
    }
    params.validate()?;
    let read_ms = elapsed_ms(start);

    let start = Instant::now();
    let field = Arc::new(field);
    let tracer = build_tracer(field.clone(), args.surface, TracerKind::Mipmap);
    let build_ms = elapsed_ms(start);

    let start = Instant::now();
    let bar = progress::bar(field.height() as u64, "shading");
    let mask = (voids > 0).then_some(void.as_slice());
    let map = shade_map(&field, &*tracer, mask, &params, &|rows| bar.set_position(rows))?;
    bar.finish_and_clear();
    let trace_ms = elapsed_ms(start);

    let (width, height, rays) = (map.width, map.height, map.rays);
    let start = Instant::now();
    write(&args.output, format, map, &info, voids > 0)?;
    let write_ms = elapsed_ms(start);

    let names: Vec<&str> = params.layers.iter().map(|l| l.name()).collect();
    let horizon_directions = params.horizon_engines() * params.horizon.azimuths;
    let rays_per_s = rays as f64 / (trace_ms / 1e3).max(1e-9);
    eprintln!(
        "wrote {} ({} x {} samples, {}; {} rays in {:.2} s, {:.1} Mrays/s)",
        args.output.display(),
        width,
        height,
        names.join(", "),
        rays,
        trace_ms / 1e3,
        rays_per_s / 1e6
    );
    if let Some(path) = &args.stats {
        let stats = serde_json::json!({
            "samples": samples,
            "voids": voids,
            "layers": names,
            "rays": rays,
            "rays_per_s": rays_per_s,
            "horizon_directions": horizon_directions,
            "read_ms": read_ms,
            "build_ms": build_ms,
            "trace_ms": trace_ms,
            "write_ms": write_ms,
        });
        outputs::write_stats(path, &stats)?;
    }
    Ok(())
}

/// The format the output's extension asks for; refuses outputs that cannot be written
/// before any work.
fn check_outputs(args: &ShadeArgs) -> Result<ShadeOutput> {
    let output = &args.output;
    outputs::check_writable(output)?;
    let format = match applies::extension(output).as_deref() {
        Some("tif" | "tiff") => ShadeOutput::GeoTiff,
        Some("png") => ShadeOutput::Png,
        _ => bail!("-o {}: shade layers are written as .tif (GeoTIFF) or .png", output.display()),
    };
    if format == ShadeOutput::Png
        && (args.layers.len() > 1 || args.layers.contains(&ShadeLayer::Horizon))
    {
        bail!(
            "-o {}: a PNG holds one band, not {} ({}); write a .tif for several",
            output.display(),
            if args.layers.len() > 1 { "several layers" } else { "a band per direction" },
            args.layers.iter().map(|l| l.name()).collect::<Vec<_>>().join(", ")
        );
    }
    let mut all = vec![("-o", output.as_path())];
    if let Some(stats) = &args.stats {
        outputs::check_stats(stats)?;
        all.push(("--stats", stats.as_path()));
    }
    outputs::check_distinct(&all, &[&args.input])?;
    Ok(format)
}

/// The shade map's parameters; refuses options that do nothing for the layers asked for.
fn params(args: &ShadeArgs) -> Result<ShadeMapParams> {
    let defaults = ShadeMapParams::default();
    let layers = &args.layers;
    let names = layers.iter().map(|l| l.name()).collect::<Vec<_>>().join(", ");
    let here = format!("--layers {names}");
    let needs_suns = layers.iter().any(|l| l.needs_suns());
    let needs_sun_rays = layers.iter().any(|l| l.needs_sun_rays());
    let needs_horizons = layers.iter().any(|l| l.builds_on_horizons());
    let needs_period = layers.iter().any(|l| l.needs_insolation_suns());
    let when = &args.when;
    if let Some(days) = when.date {
        let day = days.first;
        if !args.sun.is_empty() {
            bail!("--sun and --date both say where the sun is: give one");
        }
        match (when.time.is_some(), needs_period) {
            (true, true) => bail!(
                "--time asks for the sun of one instant, but {here} sums the sun over a period: \
                 leave --time out (insolation and sun-hours take --date {day} alone, or a range \
                 FROM..TO)"
            ),
            (true, false) if !needs_suns => {
                return Err(applies::refuse(
                    "--date with --time",
                    "the layers lit by the sun",
                    &here,
                ))
            }
            (false, false) => bail!(
                "--date without --time is a period for the insolation and sun-hours layers, not \
                 in {here}: add --time HH:MM for the sun of one instant"
            ),
            _ => {}
        }
    } else if needs_period {
        bail!("{here}: insolation and sun-hours need a period of days, --date YYYY-MM-DD[..YYYY-MM-DD]");
    }
    if !needs_suns && !args.sun.is_empty() {
        return Err(applies::refuse(
            "--sun",
            "the shadow, hillshade, combined and sky-illumination layers",
            &here,
        ));
    }
    if !needs_sun_rays && args.sun_radius.is_some() {
        return Err(applies::refuse(
            "--sun-radius",
            "the shadow, combined and sky-illumination layers",
            &here,
        ));
    }
    if args.sun_rays.is_some() && !args.sun_radius.is_some_and(|r| r > 0.0) {
        return Err(applies::refuse(
            "--sun-rays",
            "a sun with --sun-radius above 0",
            "a point sun",
        ));
    }
    let horizon_layers = "the layers built on horizons (sky, combined, horizon, sky-aniso, openness-pos, openness-neg, sky-illumination, insolation, sun-hours)";
    for (option, given) in [
        ("--azimuths", args.azimuths.is_some()),
        ("--observer-height", args.observer_height.is_some()),
        ("--radius", args.radius.is_some()),
        ("--earth-curvature", args.earth_curvature.is_some()),
    ] {
        if given && !needs_horizons {
            return Err(applies::refuse(option, horizon_layers, &here));
        }
    }
    if args.sky_model.is_some() && !layers.contains(&ShadeLayer::SkyIllumination) {
        return Err(applies::refuse("--sky-model", "the sky-illumination layer", &here));
    }
    let suns = if args.sun.is_empty() {
        defaults.suns.clone()
    } else {
        args.sun
            .iter()
            .map(|&(azimuth_deg, elevation_deg)| SunPosition { azimuth_deg, elevation_deg })
            .collect()
    };
    let params = ShadeMapParams {
        layers: layers.clone(),
        suns: if needs_suns { suns } else { Vec::new() },
        sun_radius_deg: args.sun_radius.unwrap_or(defaults.sun_radius_deg),
        sun_rays: args.sun_rays.unwrap_or(defaults.sun_rays),
        horizon: HorizonParams {
            azimuths: args.azimuths.unwrap_or(defaults.horizon.azimuths),
            observer_height: args.observer_height.unwrap_or(defaults.horizon.observer_height),
            radius: args.radius,
            refraction: args.earth_curvature,
        },
        sky_model: args.sky_model.unwrap_or(defaults.sky_model),
        ..defaults.clone()
    };
    params.check_surface(args.surface)?;
    // With --date, the suns are placed once the DEM's georeference is read.
    if when.date.is_none() {
        params.validate()?;
    }
    Ok(params)
}

/// Writes `map` to `path` on the input's grid: its georeference and CRS, and its nodata (NaN
/// when it declared none but had voids, which are NaN samples in a float file).
fn write(
    path: &Path,
    format: ShadeOutput,
    map: ShadeMap,
    info: &RasterInfo,
    has_voids: bool,
) -> Result<()> {
    let georeference = info.georeference.clone();
    match format {
        ShadeOutput::Png => {
            relief_io::write_layer_png(
                path,
                &map.bands[0].values,
                map.width,
                map.height,
                georeference.as_ref(),
            )?;
        }
        ShadeOutput::GeoTiff => {
            let nodata = info.nodata.or(has_voids.then_some(f64::NAN));
            let layers = map
                .bands
                .into_iter()
                .map(|band| Layer { name: band.name, samples: band.values })
                .collect();
            let raster =
                LayerRaster { width: map.width, height: map.height, layers, georeference, nodata };
            relief_io::write_layers_geotiff(path, &raster)?;
        }
    }
    Ok(())
}

/// Milliseconds since `start`.
fn elapsed_ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}
