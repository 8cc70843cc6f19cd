//! One measurement of `relief bench`: a tracer (or a renderer) built over a surface, a view
//! traced with it `repeat` times, the sun's shadow rays from its hits, the fastest runs kept.

use crate::drawn::{Drawn, DrawnSettings};
use crate::error::BenchError;
use rayon::prelude::*;
use relief_core::{Camera, DVec3, HeightField, Surface};
use relief_render::{memory, Progress, TracerChoice};
use relief_shade::{sun_direction, GBuffer, RayBatch, Tile, TraceStats, TILE_SIZE};
use relief_trace::adapters::OneRayAtATime;
use relief_trace::{SunShadows, Tracer};
use std::sync::Arc;
use std::time::Instant;

/// The benchmark's sun: azimuth 315° (north-west), 35° above the horizon (degrees).
pub const BENCHMARK_SUN: (f64, f64) = (315.0, 35.0);

/// How every tracer measurement is made.
#[derive(Debug, Clone)]
pub struct MeasureSettings {
    /// How the tracers and renderers are built.
    pub drawn: DrawnSettings,
    /// Whether rays are traced one at a time rather than in batches.
    pub single_rays: bool,
    /// Runs of each view; the fastest is reported.
    pub repeat: u32,
    /// Whether the sun's shadow sweep decides shadow rays first, where it pays (the
    /// triangles surface of a field without holes).
    pub shadow_sweep: bool,
}

/// The sun's shadow sweep as measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepMeasurement {
    /// Seconds its build took.
    pub build_s: f64,
    /// The share of the shadow rays it decided without tracing (0 to 1).
    pub decided: f64,
}

/// The results of one measurement: a view, a surface, a tracer.
#[derive(Debug, Clone)]
pub struct Measurement {
    /// The view's name.
    pub view: &'static str,
    /// The view's camera.
    pub camera: Camera,
    /// The surface traced.
    pub surface: Surface,
    /// The tracer (or renderer) measured.
    pub tracer: TracerChoice,
    /// Milliseconds its build took.
    pub build_ms: f64,
    /// The primary rays' statistics.
    pub primary: TraceStats,
    /// Seconds the fastest primary run took.
    pub primary_s: f64,
    /// The shadow rays' statistics.
    pub shadow: TraceStats,
    /// Seconds the fastest shadow run took; `None`: the tracer does not admit the sun's
    /// shadow rays.
    pub shadow_s: Option<f64>,
    /// The shadow sweep; `None` without one.
    pub sweep: Option<SweepMeasurement>,
    /// The process's peak resident memory so far (MiB; NaN where not known).
    pub peak_mib: f64,
}

impl Measurement {
    /// Primary rays per second, in millions.
    pub fn primary_mrays(&self) -> f64 {
        self.primary.rays as f64 / self.primary_s / 1e6
    }

    /// Shadow rays per second, in millions; `None` without shadow rays.
    pub fn shadow_mrays(&self) -> Option<f64> {
        self.shadow_s.map(|s| self.shadow.rays as f64 / s / 1e6)
    }

    /// The share of primary rays that hit (0 to 1).
    pub fn hit_share(&self) -> f64 {
        self.primary.hits as f64 / self.primary.rays.max(1) as f64
    }
}

/// Measures `tracer` over `surface` of `field` on the view `view` (`camera`): builds it,
/// traces the view into `gbuffer` (of the camera's size) `settings.repeat` times, then the
/// sun's shadow rays from the hits as often. `progress` is told of the build's stages and of
/// the primary rays traced.
pub fn measure(
    settings: &MeasureSettings,
    field: &Arc<HeightField>,
    (view, camera): (&'static str, &Camera),
    surface: Surface,
    tracer: &TracerChoice,
    gbuffer: &mut GBuffer,
    progress: &dyn Progress,
) -> Result<Measurement, BenchError> {
    let sun = sun_direction(BENCHMARK_SUN.0, BENCHMARK_SUN.1);
    let bounds = field.world_bounds(surface);
    let repeat = settings.repeat as u64;
    let (mut primary, mut primary_s) = (TraceStats::default(), f64::INFINITY);
    let started = Instant::now();
    let mut drawn = Drawn::build(&settings.drawn, field, surface, tracer, progress)?;
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
        let directions =
            (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).map(|(i, j)| camera.ray(i, j).dir);
        safety.check_view(camera.eye(), directions, None)?;
    }
    // Shapes bounded by phi max may not admit the sun's shadow rays: skip those.
    let shadows = safety.is_none_or(|safety| {
        safety.check_view(camera.eye(), std::iter::empty(), Some(sun)).is_ok()
    });
    let pixels = camera.width() as u64 * camera.height() as u64;
    progress.begin(&format!("{view}/{tracer}"), Some(repeat * pixels));
    for _ in 0..repeat {
        let timer = Instant::now();
        primary = drawn
            .render(settings.single_rays, camera, &bounds, gbuffer, &|n| progress.advance(n))?;
        primary_s = primary_s.min(timer.elapsed().as_secs_f64());
    }
    // Shadow rays: the tracer's, or the exact tracer of a rasterizing renderer.
    let exact = drawn.tracer();
    let one_at_a_time = OneRayAtATime(exact);
    let traced: &dyn Tracer = if settings.single_rays { &one_at_a_time } else { exact };
    progress.end();
    let (mut shadow, mut shadow_s) = (TraceStats::default(), None::<f64>);
    let mut sweep = None;
    if shadows {
        let timer = Instant::now();
        let swept = if settings.shadow_sweep
            && SunShadows::<&dyn Tracer>::walks_batches_over(field, surface)
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
            shadow = shadow_rays(traced, camera, gbuffer, sun);
            let s = timer.elapsed().as_secs_f64();
            shadow_s = Some(shadow_s.map_or(s, |best| best.min(s)));
        }
        if let Some(swept) = &swept {
            let decided = decided_share(swept, camera, gbuffer, sun);
            sweep = Some(SweepMeasurement { build_s: sweep_s, decided });
        }
    }
    let peak_mib = memory::peak_resident_bytes().map_or(f64::NAN, |b| b as f64 / 1048576.0);
    Ok(Measurement {
        view,
        camera: *camera,
        surface,
        tracer: tracer.clone(),
        build_ms,
        primary,
        primary_s,
        shadow,
        shadow_s,
        sweep,
        peak_mib,
    })
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
fn decided_share(
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
