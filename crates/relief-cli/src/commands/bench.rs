//! `relief bench`: tracer throughput on fixed views of the seeded fBm terrain.
//!
//! For every view, surface and tracer it prints the acceleration-structure build time, primary
//! and shadow rays per second, mean and maximum traversal steps per ray and the process's peak
//! memory so far. Measurements, not assertions: run it on an otherwise idle machine.

use crate::args::BenchArgs;
use crate::{input, memory, progress};
use anyhow::Result;
use rayon::prelude::*;
use relief_core::{Camera, DVec3, HeightField, Surface};
use relief_shade::{light_visibility, render_gbuffer, sun_direction, GBuffer, TraceStats};
use relief_trace::{build_tracer, Tracer};
use std::sync::Arc;
use std::time::Instant;

/// Runs `relief bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    let started = Instant::now();
    let field = Arc::new(input::fbm(args.size, args.seed)?);
    let generate_s = started.elapsed().as_secs_f64();
    let (w, h) = args.res;
    println!(
        "relief bench: fBm {n}x{n} (seed {}, generated in {generate_s:.2} s), {w}x{h} pixels, {} threads",
        args.seed,
        rayon::current_num_threads(),
        n = args.size
    );
    println!(
        "{:<13} {:<9} {:<6} {:>9} {:>9} {:>7} {:>8} {:>9} {:>7} {:>8} {:>9}",
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
        "peak MiB"
    );
    let sun = sun_direction(315.0, 35.0);
    for (view, camera) in views(&field, w, h)? {
        for &surface in &args.surfaces {
            for &kind in &args.tracers {
                let built = Instant::now();
                let tracer = build_tracer(field.clone(), surface, kind);
                let build_ms = built.elapsed().as_secs_f64() * 1e3;
                let bounds = field.world_bounds(surface);
                let bar = progress::bar(w as u64 * h as u64, &format!("{view}/{kind}"));
                let traced = Instant::now();
                let (gbuffer, primary) =
                    render_gbuffer(tracer.as_ref(), &camera, &bounds, &|n| bar.inc(n))?;
                let primary_s = traced.elapsed().as_secs_f64();
                bar.finish_and_clear();
                let shadowed = Instant::now();
                let shadow = shadow_rays(tracer.as_ref(), &camera, &gbuffer, sun);
                let shadow_s = shadowed.elapsed().as_secs_f64();
                let peak = memory::peak_resident_bytes().map_or(f64::NAN, |b| b as f64 / 1048576.0);
                println!(
                    "{view:<13} {surface:<9} {kind:<6} {build_ms:>9.1} {:>9.2} {:>7.1} {:>8.1} {:>9} {:>7.2} {:>8.1} {peak:>9.0}",
                    primary.rays as f64 / primary_s / 1e6,
                    100.0 * primary.hits as f64 / primary.rays.max(1) as f64,
                    primary.mean_steps(),
                    primary.max_steps,
                    shadow.rays as f64 / shadow_s / 1e6,
                    shadow.mean_steps(),
                );
            }
        }
    }
    Ok(())
}

/// The benchmark's views: a three-quarter overview, a low flight over the ground, top-down.
fn views(field: &HeightField, w: u32, h: u32) -> Result<Vec<(&'static str, Camera)>> {
    let bounds = field.world_bounds(Surface::Boxes);
    let size = bounds.max - bounds.min;
    let overview = Camera::frame_from(&bounds, 225.0, 30.0, 45.0, w, h)?;
    // Flight: from the south-west quarter towards the north-east, a little above the ground.
    let (col, row) = (field.width() / 5, field.height() / 5);
    let ground = field.sample(col, row) as f64 * field.geometry().z_scale;
    let eye = DVec3::new(
        bounds.min.x + 0.2 * size.x,
        bounds.min.y + 0.2 * size.y,
        ground + 0.03 * size.x.max(size.y),
    );
    let target = DVec3::new(bounds.min.x + 0.8 * size.x, bounds.min.y + 0.8 * size.y, ground);
    let flight = Camera::look_at(eye, target, DVec3::Z, 60.0, w, h)?;
    let centre = bounds.center();
    let above = DVec3::new(centre.x, centre.y, bounds.max.z + 1.2 * size.x.max(size.y));
    let top_down =
        Camera::look_at(above, DVec3::new(centre.x, centre.y, bounds.min.z), DVec3::Y, 45.0, w, h)?;
    Ok(vec![("three-quarter", overview), ("flight", flight), ("top-down", top_down)])
}

/// Traces a shadow ray towards `sun` from every hit of `gbuffer`, in parallel by rows.
fn shadow_rays(tracer: &dyn Tracer, camera: &Camera, gbuffer: &GBuffer, sun: DVec3) -> TraceStats {
    (0..gbuffer.height)
        .into_par_iter()
        .map(|j| {
            let mut stats = TraceStats::default();
            for i in 0..gbuffer.width {
                let k = i + j * gbuffer.width;
                let distance = gbuffer.distance[k] as f64;
                if distance.is_finite() {
                    let ray = camera.ray(i as u32, j as u32);
                    let position = ray.at(distance);
                    let normal = DVec3::from_array(gbuffer.normal[k].map(f64::from));
                    light_visibility(tracer, position, normal, distance, sun, &mut stats);
                }
            }
            stats
        })
        .reduce(TraceStats::default, TraceStats::merge)
}
