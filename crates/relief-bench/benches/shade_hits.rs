//! relief's shading of hits found elsewhere: the shading half of "native Embree plus the same
//! shading" in bench/native_anchor.py (issue 37's whole-render comparison).
//!
//! It reads one of `relief bench`'s views of a height field (an `.npy`) at `WIDTHxHEIGHT`, and
//! that view's per-pixel distances (`+inf` for a miss) and unit normals (three a pixel), raw
//! float32, row-major, row 0 the top row, as bench/embree_native.c finds them. They fill the
//! distance and normal of a `relief_shade::GBuffer`, the channels `relief render` fills for
//! its deferred pass. It then times, RUNS times each,
//!
//! - `shade`: `shade_to_srgb8` with the light `relief render` uses by default (its shading of
//!   the terrain's bounds, sun at 315, 35 degrees, exposure 1), without shadows;
//! - `png`: writing that picture as `relief render` writes its PNG (fast compression);
//!
//! and prints one JSON line with each stage's median, fastest and slowest wall seconds and
//! median CPU seconds of all threads.
//!
//! ```sh
//! cargo bench -p relief-bench --bench shade_hits -- \
//!     fbm-4096.npy three-quarter 1920x1080 hits.distance.f32 hits.normal.f32 5 /tmp/out.png
//! ```

use anyhow::{bail, Context, Result};
use relief_bench::benchmark_views;
use relief_core::Surface;
use relief_render::scenes::height_field::shading;
use relief_render::LightSettings;
use relief_shade::{shade_to_srgb8, GBuffer};
use relief_trace::adapters::NoOccluders;
use std::path::Path;
use std::time::Instant;

#[path = "common/args.rs"]
mod args;
#[path = "common/process_clock.rs"]
mod process_clock;
#[path = "common/raw_files.rs"]
mod raw_files;

/// The wall and CPU seconds (all threads) of each run of a stage.
#[derive(Default)]
struct StageTimes {
    wall: Vec<f64>,
    cpu: Vec<f64>,
}

impl StageTimes {
    /// Runs `stage` once, recording its times.
    fn time<T>(&mut self, stage: impl FnOnce() -> Result<T>) -> Result<T> {
        let (cpu_started, started) = (process_clock::cpu_seconds(), Instant::now());
        let value = stage()?;
        self.wall.push(started.elapsed().as_secs_f64());
        self.cpu.push(process_clock::cpu_seconds() - cpu_started);
        Ok(value)
    }

    /// Median, fastest and slowest wall seconds and the median CPU seconds, as JSON.
    fn json(mut self) -> String {
        self.wall.sort_by(f64::total_cmp);
        self.cpu.sort_by(f64::total_cmp);
        let (wall, cpu) = (&self.wall, &self.cpu);
        format!(
            "{{\"median_s\": {:.6}, \"min_s\": {:.6}, \"max_s\": {:.6}, \"cpu_median_s\": {:.6}}}",
            wall[wall.len() / 2],
            wall[0],
            wall[wall.len() - 1],
            cpu[cpu.len() / 2]
        )
    }
}

fn main() -> Result<()> {
    let args = args::program_args();
    let [terrain, view, size, distance, normal, runs, png] = &args[..] else {
        bail!(
            "usage: shade_hits TERRAIN.npy VIEW WIDTHxHEIGHT DISTANCE.f32 NORMAL.f32 RUNS OUT.png"
        );
    };
    let (width, height) = size.split_once('x').context("size as WIDTHxHEIGHT")?;
    let (width, height): (u32, u32) = (width.parse()?, height.parse()?);
    let runs: usize = runs.parse().with_context(|| format!("RUNS '{runs}'"))?;
    if runs == 0 {
        bail!("RUNS must be at least 1");
    }
    let field = relief_io::read_npy_height_field(terrain.as_ref())?;
    let camera = benchmark_views(&field, width, height)?
        .into_iter()
        .find(|(name, _)| name == view)
        .with_context(|| format!("no benchmark view '{view}'"))?
        .1;
    let light = LightSettings { no_shadows: true, ..LightSettings::default() };
    let params = shading(&light, &field.world_bounds(Surface::Triangles), 1.0)?;

    let mut gbuffer = GBuffer::new(width as usize, height as usize)?;
    let distances = raw_files::read_f32s(distance.as_ref())?;
    let normals = raw_files::read_f32s(normal.as_ref())?;
    if distances.len() != gbuffer.len() || normals.len() != 3 * gbuffer.len() {
        bail!("{distance} and {normal} do not hold one distance and one normal a pixel of {size}");
    }
    gbuffer.distance.copy_from_slice(&distances);
    for (pixel, n) in gbuffer.normal.iter_mut().zip(normals.chunks_exact(3)) {
        *pixel = [n[0], n[1], n[2]];
    }

    let (mut shade_times, mut png_times) = (StageTimes::default(), StageTimes::default());
    for _ in 0..runs {
        let shaded = || Ok(shade_to_srgb8(&gbuffer, &NoOccluders, &camera, &params)?.0);
        let rgb = shade_times.time(shaded)?;
        let written =
            || Ok(relief_io::write_png_rgb8(Path::new(png), width, height, rgb.as_flattened())?);
        png_times.time(written)?;
    }
    println!(
        "{{\"view\": \"{view}\", \"pixels\": {}, \"threads\": {}, \"shade\": {}, \"png\": {}}}",
        gbuffer.len(),
        rayon::current_num_threads(),
        shade_times.json(),
        png_times.json()
    );
    Ok(())
}
