//! `relief bench`: tracer throughput on fixed views of the seeded fBm terrain.
//!
//! For every view, surface and tracer it prints the acceleration-structure build time, primary and
//! shadow rays per second, mean and maximum traversal steps per ray and the process's peak memory
//! so far. Over the triangles surface of a field without holes, shadow rays go through the sun's
//! shadow sweep ([`SunShadows`]) first, unless `--no-shadow-sweep`: its build time and the share of
//! shadow rays it decides without tracing are reported apart (elsewhere the sweep does not pay, and
//! is not built). Every view is traced `--repeat` times and the fastest run is reported.
//! Measurements, not assertions: run it on an otherwise idle machine.

use crate::args::BenchArgs;
use crate::tracers::{self, TracerChoice};
use crate::{applies, input, memory, progress};
use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use relief_core::{benchmark_views, Camera, DVec3, HeightField, Surface, BENCHMARK_VIEWS};
use relief_shade::{
    render_gbuffer_into, sun_direction, ClipmapRenderer, GBuffer, HybridRenderer, RayBatch, Tile,
    TraceStats, TILE_SIZE,
};
use relief_trace::{Hit, Simd, SunShadows, Tracer, TracerKind};
use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

/// The benchmark's sun: azimuth 315° (north-west), 35° above the horizon.
const SUN: (f64, f64) = (315.0, 35.0);

/// One line of results.
struct Measurement<'a> {
    view: &'a str,
    camera: &'a Camera,
    surface: Surface,
    tracer: &'a TracerChoice,
    build_ms: f64,
    primary: TraceStats,
    primary_s: f64,
    shadow: TraceStats,
    /// `None`: the tracer does not admit the sun's shadow rays.
    shadow_s: Option<f64>,
    /// The shadow sweep's build time and the share of shadow rays it decided without
    /// tracing; `None` without a sweep.
    sweep: Option<(f64, f64)>,
    peak_mib: f64,
    /// What the mipmap tracer's packet tests ran on.
    simd: Simd,
    /// Whether rays were traced one at a time rather than in batches.
    single_rays: bool,
}

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
        return super::bench_dynamic::run(args, kind, field, &source, &views, &surfaces);
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
    let sun = sun_direction(SUN.0, SUN.1);
    for (view, camera) in benchmark_views(&field, w, h)? {
        if !views.iter().any(|v| v == view) {
            continue;
        }
        for &surface in &surfaces {
            for tracer in &args.tracers {
                let bounds = field.world_bounds(surface);
                let repeat = args.repeat as u64;
                let bar = progress::bar(repeat * w as u64 * h as u64, &format!("{view}/{tracer}"));
                let mut gbuffer = GBuffer::new(w as usize, h as usize)?;
                let (mut primary, mut primary_s) = (TraceStats::default(), f64::INFINITY);
                let started = Instant::now();
                let mut drawn = Drawn::build(args, &field, surface, tracer, limit, simd)?;
                let build_ms = match &drawn {
                    Drawn::Tracer(built) => built.build_s * 1e3,
                    _ => started.elapsed().as_secs_f64() * 1e3,
                };
                let safety = match &drawn {
                    Drawn::Tracer(built) => built.safety.as_ref(),
                    _ => None,
                };
                if let Some(safety) = safety {
                    let (w, h) = (camera.width(), camera.height());
                    let directions = (0..h)
                        .flat_map(|j| (0..w).map(move |i| (i, j)))
                        .map(|(i, j)| camera.ray(i, j).dir);
                    safety.check_view(camera.eye(), directions, None)?;
                }
                // Shapes bounded by phi max may not admit the sun's shadow rays: skip those.
                let shadows = safety.is_none_or(|safety| {
                    safety.check_view(camera.eye(), std::iter::empty(), Some(sun)).is_ok()
                });
                for _ in 0..repeat {
                    let timer = Instant::now();
                    primary =
                        drawn.render(args.single_rays, &camera, &bounds, &mut gbuffer, &bar)?;
                    primary_s = primary_s.min(timer.elapsed().as_secs_f64());
                }
                // Shadow rays: the tracer's, or the exact tracer of a rasterizing renderer.
                let exact = drawn.tracer();
                let one_at_a_time = OneRayAtATime(exact);
                let traced: &dyn Tracer = if args.single_rays { &one_at_a_time } else { exact };
                bar.finish_and_clear();
                let (mut shadow, mut shadow_s) = (TraceStats::default(), None::<f64>);
                let mut sweep = None;
                if shadows {
                    let timer = Instant::now();
                    let swept = if !args.no_shadow_sweep
                        && SunShadows::<&dyn Tracer>::walks_batches_over(&field, surface)
                    {
                        Some(SunShadows::new(traced, field.clone(), sun)?)
                    } else {
                        None
                    };
                    let sweep_s = timer.elapsed().as_secs_f64();
                    let traced: &dyn Tracer = match &swept {
                        Some(swept) => swept,
                        None => traced,
                    };
                    for _ in 0..repeat {
                        let timer = Instant::now();
                        shadow = shadow_rays(traced, &camera, &gbuffer, sun);
                        let s = timer.elapsed().as_secs_f64();
                        shadow_s = Some(shadow_s.map_or(s, |best| best.min(s)));
                    }
                    if let Some(swept) = &swept {
                        sweep = Some((sweep_s, proven_share(swept, &camera, &gbuffer, sun)));
                    }
                }
                if let Some(dir) = &args.depth_dir {
                    let path = dir.join(format!("{view}-{surface}-{tracer}.npy"));
                    relief_io::write_npy_f32(
                        &path,
                        &[h as usize, w as usize],
                        &gbuffer.depth_hw(),
                    )?;
                }
                let peak_mib =
                    memory::peak_resident_bytes().map_or(f64::NAN, |b| b as f64 / 1048576.0);
                let m = Measurement {
                    view,
                    camera: &camera,
                    surface,
                    tracer,
                    build_ms,
                    primary,
                    primary_s,
                    shadow,
                    shadow_s,
                    sweep,
                    peak_mib,
                    simd: simd.effective(),
                    single_rays: args.single_rays,
                };
                if args.json {
                    writeln!(out, "{}", m.json(threads))?;
                } else {
                    writeln!(out, "{}", m.row())?;
                }
            }
        }
    }
    Ok(())
}

/// What `relief bench` measures: a tracer through the ray-casting render pass, or a renderer
/// that rasterizes (the hybrid renderer, geometry clipmaps).
enum Drawn {
    Tracer(Box<tracers::Built>),
    Hybrid(Box<HybridRenderer>),
    Clipmap(Box<ClipmapRenderer>),
}

impl Drawn {
    fn build(
        args: &BenchArgs,
        field: &Arc<HeightField>,
        surface: Surface,
        tracer: &TracerChoice,
        limit: u64,
        simd: Simd,
    ) -> Result<Self> {
        Ok(match tracer {
            TracerChoice::Hybrid => {
                let (params, far) = (args.hybrid.params(), args.hybrid.far.unwrap_or_default());
                Drawn::Hybrid(Box::new(HybridRenderer::new(field.clone(), surface, params, far)?))
            }
            TracerChoice::Clipmap if surface == Surface::Boxes => {
                bail!(
                    "geometry clipmaps draw the triangles surface only (use --surfaces triangles)"
                )
            }
            TracerChoice::Clipmap => Drawn::Clipmap(Box::new(ClipmapRenderer::new(
                field.clone(),
                relief_mesh::ClipmapParams::default(),
            )?)),
            _ => {
                let built =
                    tracers::build(field, surface, tracer, &args.safety, false, limit, simd)?;
                Drawn::Tracer(Box::new(built))
            }
        })
    }

    /// Draws the view into `gbuffer`; the primary rays' statistics (for the rasterizing
    /// renderers, the pixels and hits only).
    fn render(
        &mut self,
        single_rays: bool,
        camera: &Camera,
        bounds: &relief_core::Aabb,
        gbuffer: &mut GBuffer,
        bar: &indicatif::ProgressBar,
    ) -> Result<TraceStats> {
        let pixels = camera.width() as u64 * camera.height() as u64;
        match self {
            Drawn::Tracer(built) => {
                let one_at_a_time = OneRayAtATime(built.tracer.as_ref());
                let traced: &dyn Tracer =
                    if single_rays { &one_at_a_time } else { built.tracer.as_ref() };
                return Ok(render_gbuffer_into(traced, camera, bounds, gbuffer, &|n| bar.inc(n))?);
            }
            Drawn::Hybrid(hybrid) => {
                hybrid.render_into(camera, bounds, gbuffer, None)?;
            }
            Drawn::Clipmap(clipmap) => {
                clipmap.render_into(camera, bounds, gbuffer)?;
            }
        }
        bar.inc(pixels);
        let hits = gbuffer.distance.iter().filter(|d| d.is_finite()).count() as u64;
        Ok(TraceStats { rays: pixels, hits, ..TraceStats::default() })
    }

    /// The exact tracer that traces the shadow rays.
    fn tracer(&self) -> &dyn Tracer {
        match self {
            Drawn::Tracer(built) => built.tracer.as_ref(),
            Drawn::Hybrid(hybrid) => hybrid.tracer(),
            Drawn::Clipmap(clipmap) => clipmap.tracer(),
        }
    }
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

/// A tracer seen one ray at a time: its batch methods are the trait's loops over single rays.
struct OneRayAtATime<'a>(&'a dyn Tracer);

impl Tracer for OneRayAtATime<'_> {
    fn name(&self) -> &'static str {
        self.0.name()
    }

    fn surface(&self) -> Surface {
        self.0.surface()
    }

    fn bounds(&self) -> relief_core::Aabb {
        self.0.bounds()
    }

    fn intersect_counted(&self, ray: &relief_core::Ray, steps: &mut u32) -> Option<Hit> {
        self.0.intersect_counted(ray, steps)
    }

    fn occluded_counted(&self, ray: &relief_core::Ray, steps: &mut u32) -> bool {
        self.0.occluded_counted(ray, steps)
    }
}

impl Measurement<'_> {
    fn primary_mrays(&self) -> f64 {
        self.primary.rays as f64 / self.primary_s / 1e6
    }

    fn shadow_mrays(&self) -> Option<f64> {
        self.shadow_s.map(|s| self.shadow.rays as f64 / s / 1e6)
    }

    fn row(&self) -> String {
        format!(
            "{:<13} {:<9} {:<18} {:>9.1} {:>9.2} {:>6.1} {:>7.1} {:>6} {:>9} {:>7.1} {:>8.0} {:>8} {:>7}",
            self.view,
            self.surface,
            self.tracer.to_string(),
            self.build_ms,
            self.primary_mrays(),
            100.0 * self.primary.hits as f64 / self.primary.rays.max(1) as f64,
            self.primary.mean_steps(),
            self.primary.max_steps,
            self.shadow_mrays().map_or("-".into(), |m| format!("{m:.2}")),
            self.shadow.mean_steps(),
            self.peak_mib,
            self.sweep.map_or("-".into(), |(s, _)| format!("{:.1}", s * 1e3)),
            self.sweep.map_or("-".into(), |(_, share)| format!("{:.1}", share * 100.0))
        )
    }

    fn json(&self, threads: usize) -> String {
        let v = |d: DVec3| format!("[{}, {}, {}]", d.x, d.y, d.z);
        let c = self.camera;
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
            self.view,
            self.surface,
            self.tracer,
            self.simd,
            self.single_rays,
            threads,
            self.build_ms,
            self.primary.rays,
            self.primary_s,
            self.primary.hits,
            self.primary.mean_steps(),
            self.primary.max_steps,
            self.shadow.rays,
            self.shadow_s.map_or("null".into(), |s| s.to_string()),
            self.shadow.mean_steps(),
            self.sweep.map_or("null".into(), |(s, _)| s.to_string()),
            self.sweep.map_or("null".into(), |(_, share)| share.to_string()),
            self.peak_mib,
            v(c.eye()),
            v(c.target()),
            v(c.up()),
            c.fov_deg().map_or("null".into(), |f| f.to_string()),
            c.width(),
            c.height(),
            SUN.0,
            SUN.1
        )
    }
}

/// Traces a shadow ray towards `sun` from every hit of `gbuffer`, in parallel by strips of
/// tiles, each tile's rays as one batch.
fn shadow_rays(tracer: &dyn Tracer, camera: &Camera, gbuffer: &GBuffer, sun: DVec3) -> TraceStats {
    let (width, height) = (gbuffer.width, gbuffer.height);
    (0..height.div_ceil(TILE_SIZE))
        .into_par_iter()
        .map(|strip| {
            let mut stats = TraceStats::default();
            let mut batch = RayBatch::default();
            let rows = strip * TILE_SIZE..((strip + 1) * TILE_SIZE).min(height);
            for tile_x in (0..width).step_by(TILE_SIZE) {
                batch.clear();
                let tile = Tile::new(tile_x, rows.start, width, rows.end);
                tile.shadow_rays(camera, gbuffer, sun, &mut batch.rays);
                batch.occlude(tracer);
                for (&s, &o) in batch.steps.iter().zip(&batch.occluded) {
                    stats.record(s, o);
                }
            }
            stats
        })
        .reduce(TraceStats::default, TraceStats::merge)
}

/// The share of the shadow rays towards `sun` from the hits of `gbuffer` that `sweep`
/// decides (proves lit or occluded) without tracing.
fn proven_share(
    sweep: &SunShadows<&dyn Tracer>,
    camera: &Camera,
    gbuffer: &GBuffer,
    sun: DVec3,
) -> f64 {
    let (width, height) = (gbuffer.width, gbuffer.height);
    let (proven, rays) = (0..height.div_ceil(TILE_SIZE))
        .into_par_iter()
        .map(|strip| {
            let mut rays = Vec::new();
            let rows = strip * TILE_SIZE..((strip + 1) * TILE_SIZE).min(height);
            for tile_x in (0..width).step_by(TILE_SIZE) {
                let tile = Tile::new(tile_x, rows.start, width, rows.end);
                tile.shadow_rays(camera, gbuffer, sun, &mut rays);
            }
            (rays.iter().filter(|r| sweep.decide(r, &mut 0).is_some()).count(), rays.len())
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    proven as f64 / rays.max(1) as f64
}
