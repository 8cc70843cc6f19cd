//! What the deferred shading pass costs per frame, in `f64` and in `f32` lanes at each width:
//! the figures of "Shading in f32 lanes" in docs/performance.md.
//!
//! On `relief bench`'s views of a terrain (an `.npy` from `relief generate fbm`) at 1920x1080,
//! the G-buffer is traced once (mipmap tracer, triangles), then shaded on ONE thread with the
//! terrain's default parameters (hypsometric ramp, GGX, fog; no shadows unless said):
//!
//! - `f64 pass`: `shade_to_srgb8` with `precise` (the pass as it was);
//! - `f32 pass`: `shade_to_srgb8` as it is, the kernel at the width the processor gets;
//! - `portable`, `avx2`, `avx512`: the kernel alone at that width, row by row over the
//!   G-buffer (a width this processor lacks is skipped, and says so);
//! - `f64 pass, shadows` and `f32 pass, shadows`: both passes with shadow rays, which they
//!   trace alike (the mipmap tracer's packets).
//!
//! Variants run in turn, seven rounds; each figure is the median, in milliseconds per frame on
//! one thread, with the fastest and slowest run.
//!
//! ```sh
//! relief generate fbm --size 4096 -o fbm-4096.npy
//! cargo bench -p relief-bench --bench shading_lanes -- fbm-4096.npy
//! ```

use anyhow::{Context, Result};
use relief_bench::benchmark_views;
use relief_core::Surface;
use relief_shade::{
    render_gbuffer, shade_to_srgb8, GBuffer, LaneWidth, ShadingKernel, ShadingParams,
};
use relief_trace::MipmapTracer;
use std::sync::Arc;
use std::time::Instant;

#[path = "common/args.rs"]
mod args;

/// Rounds of every variant.
const ROUNDS: usize = 7;

/// One way to shade the frame, timed.
type Variant<'a> = (String, Box<dyn Fn() + Send + Sync + 'a>);

fn main() -> Result<()> {
    let args = args::program_args();
    let path = args.first().context("usage: shading_lanes FILE.npy")?;
    let field = Arc::new(relief_io::read_npy_height_field(path.as_ref())?);
    let tracer = MipmapTracer::new(field.clone(), Surface::Triangles);
    let bounds = field.world_bounds(Surface::Triangles);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    println!("one thread; median (min-max) ms per 1920x1080 frame, {ROUNDS} rounds in turn");
    for (view, camera) in benchmark_views(&field, 1920, 1080)? {
        let (gbuffer, _) = render_gbuffer(&tracer, &camera, &bounds, &|_| {})?;
        let params = ShadingParams { shadows: false, ..ShadingParams::for_terrain(&bounds)? };
        let precise = ShadingParams { precise: true, ..params.clone() };
        let shadows = ShadingParams { shadows: true, ..params.clone() };
        let precise_shadows = ShadingParams { shadows: true, ..precise.clone() };
        let kernel = ShadingKernel::new(&camera, &params).context("the kernel covers it")?;
        let mut variants: Vec<Variant> = Vec::new();
        let pass = |name: &str, p: ShadingParams| -> Variant {
            let (g, t, c) = (&gbuffer, &tracer, &camera);
            (name.to_string(), Box::new(move || drop(shade_to_srgb8(g, t, c, &p).unwrap())))
        };
        variants.push(pass("f64 pass", precise));
        variants.push(pass(&format!("f32 pass ({})", kernel.width().name()), params.clone()));
        for width in LaneWidth::ALL {
            match kernel.clone().with_width(width) {
                Ok(k) => {
                    let g = &gbuffer;
                    variants.push((width.name().to_string(), Box::new(move || rows(&k, g))));
                }
                Err(why) => println!("{view}: {} skipped: {why}", width.name()),
            }
        }
        variants.push(pass("f64 pass, shadows", precise_shadows));
        variants.push(pass("f32 pass, shadows", shadows));
        let mut times = vec![Vec::new(); variants.len()];
        for _ in 0..ROUNDS {
            for (k, (_, run)) in variants.iter().enumerate() {
                let started = Instant::now();
                pool.install(run);
                times[k].push(started.elapsed().as_secs_f64() * 1e3);
            }
        }
        for ((name, _), mut t) in variants.iter().zip(times) {
            t.sort_by(f64::total_cmp);
            let (min, median, max) = (t[0], t[t.len() / 2], t[t.len() - 1]);
            println!("{view:>14}  {name:<24} {median:8.1} ({min:.1}-{max:.1})");
        }
    }
    Ok(())
}

/// The kernel over every row of `gbuffer`, the sun seen everywhere (no shadows).
fn rows(kernel: &ShadingKernel, gbuffer: &GBuffer) {
    let width = gbuffer.width;
    let visibility = vec![1.0f32; width];
    let mut out = vec![[0u8; 3]; width];
    for row in 0..gbuffer.height {
        let k = row * width..(row + 1) * width;
        let (distance, normal) = (&gbuffer.distance[k.clone()], &gbuffer.normal[k]);
        kernel.shade_row(row, 0, distance, normal, &visibility, &mut out);
        std::hint::black_box(&out);
    }
}
