//! The horizon engine's speed: the shade layers built on the exact horizons of every sample
//! of a height field in N directions, and what they cost per sample and direction.
//!
//! It reads a height field (any file `relief shade` reads), places it at SPACING metres, and
//! times `shade_map` of LAYERS (comma-separated, as `relief shade --layers` takes them) RUNS
//! times, printing one JSON line with the median, fastest and slowest wall seconds, the median
//! CPU seconds of all threads, and nanoseconds of CPU per sample and direction.
//!
//! ```sh
//! cargo bench -p relief-bench --bench horizons -- dem.npy SPACING AZIMUTHS LAYERS RUNS
//! ```

use anyhow::{bail, Context, Result};
use relief_core::GridGeometry;
use relief_core::Surface;
use relief_io::{ReadOptions, VoidPolicy};
use relief_shade::horizon::HorizonParams;
use relief_shade::shade_map::{shade_map, ShadeLayer, ShadeMapParams};
use relief_trace::{build_tracer, TracerKind};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

#[path = "common/args.rs"]
mod args;
#[path = "common/process_clock.rs"]
mod process_clock;

fn main() -> Result<()> {
    let args = args::program_args();
    let [path, spacing, azimuths, layers, runs] = args.as_slice() else {
        bail!("usage: horizons DEM SPACING AZIMUTHS LAYERS RUNS");
    };
    let layers = layers
        .split(',')
        .map(|name| name.parse::<ShadeLayer>().map_err(anyhow::Error::msg))
        .collect::<Result<Vec<_>>>()?;
    let spacing: f64 = spacing.parse().context("SPACING")?;
    let azimuths: u32 = azimuths.parse().context("AZIMUTHS")?;
    let runs: usize = runs.parse().context("RUNS")?;
    let path = Path::new(path);
    let raster =
        relief_io::read_raster(path, &ReadOptions { max_memory: u64::MAX, ..Default::default() })?;
    let field = raster.into_height_field(path, VoidPolicy::Fill)?;
    let field =
        field.with_geometry(GridGeometry { dx: spacing, dy: spacing, ..GridGeometry::unit() })?;
    let field = Arc::new(field);
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    let params = ShadeMapParams {
        layers,
        horizon: HorizonParams { azimuths, ..HorizonParams::default() },
        ..ShadeMapParams::default()
    };
    let mut wall = Vec::new();
    let mut cpu = Vec::new();
    for _ in 0..runs {
        let (start, cpu_start) = (Instant::now(), process_clock::cpu_seconds());
        let map = shade_map(&field, &*tracer, None, &params, &|_| {})?;
        wall.push(start.elapsed().as_secs_f64());
        cpu.push(process_clock::cpu_seconds() - cpu_start);
        std::hint::black_box(map);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (fastest, slowest) = (
        wall.iter().cloned().fold(f64::INFINITY, f64::min),
        wall.iter().cloned().fold(0.0, f64::max),
    );
    let (wall_median, cpu_median) = (median(&mut wall), median(&mut cpu));
    let per = (field.width() * field.height()) as f64 * azimuths as f64;
    println!(
        "{{\"samples\": {}, \"azimuths\": {azimuths}, \"wall_s\": {wall_median:.3}, \"wall_min_s\": {fastest:.3}, \"wall_max_s\": {slowest:.3}, \"cpu_s\": {cpu_median:.3}, \"cpu_ns_per_sample_direction\": {:.1}}}",
        field.width() * field.height(),
        cpu_median * 1e9 / per
    );
    Ok(())
}
