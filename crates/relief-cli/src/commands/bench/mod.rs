//! `relief bench`: tracer throughput on fixed views of the seeded fBm terrain.
//!
//! For every view, surface and tracer it prints the acceleration-structure build time, primary and
//! shadow rays per second, mean and maximum traversal steps per ray and the process's peak memory
//! so far. Over the triangles surface of a field without holes, shadow rays go through the sun's
//! shadow sweep ([`relief_trace::SunShadows`]) first, unless `--no-shadow-sweep`: its build time and the share of
//! shadow rays it decides without tracing are reported apart (elsewhere the sweep does not pay, and
//! is not built). Every view is traced `--repeat` times and the fastest run is reported.
//! Measurements, not assertions: run it on an otherwise idle machine.

pub mod args;
mod dynamic;

use crate::{applies, input, memory, progress};
use anyhow::{bail, Context, Result};
use args::BenchArgs;
use relief_bench::{
    benchmark_views, measure, DrawnSettings, MeasureSettings, Measurement, BENCHMARK_SUN,
    BENCHMARK_VIEWS,
};
use relief_core::DVec3;
use relief_render::TracerChoice;
use relief_shade::GBuffer;
use relief_trace::{Simd, TracerKind};
use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

/// Runs `relief bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    let (views, surfaces) = (args.views(), args.surfaces());
    if let Some(view) = views.iter().find(|v| !BENCHMARK_VIEWS.contains(&v.as_str())) {
        bail!("unknown view '{view}': expected {}", BENCHMARK_VIEWS.join(", "));
    }
    let budget = memory::budget(None);
    let limit = budget.bytes;
    super::check_image(args.res.0, args.res.1, &budget)?;
    refuse_unused_options(args)?;
    let simd = args.simd.unwrap_or_else(Simd::detect);
    let started = Instant::now();
    let (field, source) = match &args.input {
        Some(path) => {
            let read = crate::args::ReadArgs::default();
            (input::read(path, &read, crate::args::Voids::Fill)?.1, path.display().to_string())
        }
        None => {
            let (size, seed) = (args.size.unwrap_or(4096), args.seed.unwrap_or(1));
            (input::fbm(size, seed, &budget)?, format!("fBm {size}x{size} seed {seed}"))
        }
    };
    let field = Arc::new(field);
    let load_s = started.elapsed().as_secs_f64();
    if let Some(kind) = args.dynamic {
        return dynamic::run(args, kind, field, &source, &views, &surfaces);
    }
    if let Some(dir) = &args.depth_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let (w, h) = args.res;
    let threads = rayon::current_num_threads();
    let mut out = std::io::stdout().lock();
    if !args.json {
        writeln!(
            out,
            "relief bench: {source} (ready in {load_s:.2} s), {w}x{h} pixels, {threads} threads, \
             {}, fastest of {}",
            if args.single_rays {
                "one ray at a time".to_string()
            } else {
                format!("mipmap packet tests: {}", simd.effective())
            },
            args.repeat
        )?;
        writeln!(
            out,
            "{:<13} {:<9} {:<18} {:>9} {:>9} {:>6} {:>7} {:>6} {:>9} {:>7} {:>8} {:>8} {:>7}",
            "view",
            "surface",
            "tracer",
            "build ms",
            "prim Mr/s",
            "hit %",
            "steps",
            "max",
            "shad Mr/s",
            "steps",
            "peak MiB",
            "sweep ms",
            "swept %"
        )?;
    }
    let settings = MeasureSettings {
        drawn: DrawnSettings {
            safety: crate::scene_options::safety_settings(&args.safety),
            hybrid: args.hybrid.params(),
            far: args.hybrid.far.unwrap_or_default(),
            max_memory: limit,
            simd,
        },
        single_rays: args.single_rays,
        repeat: args.repeat,
        shadow_sweep: !args.no_shadow_sweep,
    };
    for (view, camera) in benchmark_views(&field, w, h)? {
        if !views.iter().any(|v| v == view) {
            continue;
        }
        for &surface in &surfaces {
            for tracer in &args.tracers {
                let mut gbuffer = GBuffer::new(w as usize, h as usize)?;
                let bars = progress::Bars::default();
                let m = measure(
                    &settings,
                    &field,
                    (view, &camera),
                    surface,
                    tracer,
                    &mut gbuffer,
                    &bars,
                )?;
                if let Some(dir) = &args.depth_dir {
                    let path = dir.join(format!("{view}-{surface}-{tracer}.npy"));
                    relief_io::write_npy_f32(
                        &path,
                        &[h as usize, w as usize],
                        &gbuffer.depth_hw(),
                    )?;
                }
                if args.json {
                    writeln!(out, "{}", json(&m, simd.effective(), args.single_rays, threads))?;
                } else {
                    writeln!(out, "{}", row(&m))?;
                }
            }
        }
    }
    Ok(())
}

/// Refuses the options that would do nothing: the fBm terrain's with `--input`, the safety
/// shapes' when no safety tracer is measured, `--simd` when no mipmap packets are traced.
fn refuse_unused_options(args: &BenchArgs) -> Result<()> {
    if let Some(path) = &args.input {
        let here = format!("--input {}", path.display());
        for (given, option) in [(args.size.is_some(), "--size"), (args.seed.is_some(), "--seed")] {
            if given {
                return Err(applies::refuse(option, "the generated fBm terrain", &here));
            }
        }
    }
    let safety_measured = args.tracers.iter().any(|t| matches!(t, TracerChoice::Safety(_)));
    if let Some(option) = applies::safety_option_given(&args.safety).filter(|_| !safety_measured) {
        return Err(applies::refuse(option, "the safety tracers", "the tracers measured"));
    }
    let hybrid_measured = args.dynamic.is_some() || args.tracers.contains(&TracerChoice::Hybrid);
    if let Some(option) = args.hybrid.given().filter(|_| !hybrid_measured) {
        return Err(applies::refuse(option, "the hybrid renderer", "the tracers measured"));
    }
    if args.hybrid.show_lop {
        return Err(applies::refuse("--show-lop", "relief render", "relief bench"));
    }
    if args.dynamic.is_some() {
        for (given, option) in
            [(args.shadow_sweep, "--shadow-sweep"), (args.no_shadow_sweep, "--no-shadow-sweep")]
        {
            if given {
                return Err(applies::refuse(option, "the tracers' shadow rays", "--dynamic"));
            }
        }
    }
    if args.dynamic.is_none() && args.frames != 20 {
        return Err(applies::refuse("--frames", "--dynamic", "the tracers measured"));
    }
    if args.simd.is_some() {
        let mipmap = TracerChoice::Plain(TracerKind::Mipmap);
        if args.single_rays {
            return Err(applies::refuse("--simd", "ray packets", "--single-rays"));
        }
        if !args.tracers.contains(&mipmap) {
            return Err(applies::refuse("--simd", "the mipmap tracer", "the tracers measured"));
        }
    }
    Ok(())
}

/// One line of the results table.
fn row(m: &Measurement) -> String {
    format!(
        "{:<13} {:<9} {:<18} {:>9.1} {:>9.2} {:>6.1} {:>7.1} {:>6} {:>9} {:>7.1} {:>8.0} {:>8} {:>7}",
        m.view,
        m.surface,
        m.tracer.to_string(),
        m.build_ms,
        m.primary_mrays(),
        100.0 * m.hit_share(),
        m.primary.mean_steps(),
        m.primary.max_steps,
        m.shadow_mrays().map_or("-".into(), |r| format!("{r:.2}")),
        m.shadow.mean_steps(),
        m.peak_mib,
        m.sweep.map_or("-".into(), |s| format!("{:.1}", s.build_s * 1e3)),
        m.sweep.map_or("-".into(), |s| format!("{:.1}", s.decided * 100.0))
    )
}

/// One measurement as a JSON object (with its camera and sun), traced with `simd` packet
/// tests (or `single_rays`) on `threads` threads.
fn json(m: &Measurement, simd: Simd, single_rays: bool, threads: usize) -> String {
    let v = |d: DVec3| format!("[{}, {}, {}]", d.x, d.y, d.z);
    let c = &m.camera;
    format!(
        concat!(
            "{{\"view\": \"{}\", \"surface\": \"{}\", \"tracer\": \"{}\", \"simd\": \"{}\", \"single_rays\": {}, \"threads\": {}, ",
            "\"build_ms\": {}, \"primary_rays\": {}, \"primary_s\": {}, \"primary_hits\": {}, ",
            "\"primary_mean_steps\": {}, \"primary_max_steps\": {}, \"shadow_rays\": {}, ",
            "\"shadow_s\": {}, \"shadow_mean_steps\": {}, \"shadow_sweep_build_s\": {}, ",
            "\"shadow_sweep_decided\": {}, \"peak_mib\": {}, ",
            "\"camera\": {{\"eye\": {}, \"target\": {}, \"up\": {}, \"fov_deg\": {}, ",
            "\"width\": {}, \"height\": {}}}, \"sun\": {{\"azimuth_deg\": {}, \"elevation_deg\": {}}}}}"
        ),
        m.view,
        m.surface,
        m.tracer,
        simd,
        single_rays,
        threads,
        m.build_ms,
        m.primary.rays,
        m.primary_s,
        m.primary.hits,
        m.primary.mean_steps(),
        m.primary.max_steps,
        m.shadow.rays,
        m.shadow_s.map_or("null".into(), |s| s.to_string()),
        m.shadow.mean_steps(),
        m.sweep.map_or("null".into(), |s| s.build_s.to_string()),
        m.sweep.map_or("null".into(), |s| s.decided.to_string()),
        m.peak_mib,
        v(c.eye()),
        v(c.target()),
        v(c.up()),
        c.fov_deg().map_or("null".into(), |f| f.to_string()),
        c.width(),
        c.height(),
        BENCHMARK_SUN.0,
        BENCHMARK_SUN.1
    )
}
