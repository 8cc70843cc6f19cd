//! `relief bench --dynamic`: the hybrid renderer drawing a height field that changes every
//! frame (Ammann et al. 2010, section 5.3 and Figure 11): a brush stamping the ground, the
//! ocean wave simulation or the height-field erosion, each frame's update (the simulation and
//! the renderer's own update) and render (hybrid G-buffer, then shading with shadow rays)
//! timed apart.

use crate::args::{BenchArgs, DynamicKind};
use anyhow::{Context, Result};
use relief_bench::benchmark_views;
use relief_core::{DVec2, HeightField, SampleRegion, Surface};
use relief_shade::{shade_to_srgb8, GBuffer, HybridRenderer, ShadingParams};
use relief_sim::{
    stamp, Brush, BrushKind, ErosionParams, HeightFieldErosion, SimError, WaveParams,
    WaveSimulation,
};
use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

/// What rewrites the field every frame.
enum Change {
    /// A brush circling the view's target, raising then lowering.
    Stamp { centre: DVec2, circle: f64, radius: f64, strength: f64 },
    /// The ocean waves.
    Waves(Box<WaveSimulation>),
    /// The erosion.
    Erosion(Box<HeightFieldErosion>),
}

impl Change {
    fn new(kind: DynamicKind, field: &HeightField, target: DVec2) -> Result<Self> {
        let g = field.geometry();
        let size = (field.width() as f64 * g.dx).max(field.height() as f64 * g.dy);
        let relief = (field.max_sample() - field.min_sample()) as f64 * g.z_scale;
        Ok(match kind {
            DynamicKind::Stamp => Change::Stamp {
                centre: target,
                circle: size / 16.0,
                radius: size / 64.0,
                strength: relief.max(1e-3) / 50.0,
            },
            DynamicKind::Waves => Change::Waves(Box::new(
                WaveSimulation::new(field, WaveParams::for_field(field)).context("waves")?,
            )),
            DynamicKind::Erosion => Change::Erosion(Box::new(
                HeightFieldErosion::new(field, ErosionParams::default()).context("erosion")?,
            )),
        })
    }

    /// Changes the field of `renderer` for frame `frame`; returns the samples changed and the
    /// milliseconds the change itself took (the rest of the update is the renderer's).
    fn apply(&mut self, renderer: &mut HybridRenderer, frame: u32) -> Result<(usize, f64)> {
        let mut change_ms = 0.0;
        // The change itself, timed inside the renderer's edit; it returns the region it wrote.
        let mut timed =
            |change: &mut dyn FnMut(&mut HeightField) -> Result<SampleRegion, SimError>| {
                renderer.edit(|field| {
                    let timer = Instant::now();
                    let region = change(field);
                    change_ms = ms(timer);
                    region
                })
            };
        let whole = |field: &HeightField| SampleRegion::whole(field.width(), field.height());
        let region = match self {
            Change::Stamp { centre, circle, radius, strength } => {
                let angle = frame as f64 * 0.4;
                let brush = Brush {
                    kind: if frame.is_multiple_of(2) { BrushKind::Raise } else { BrushKind::Lower },
                    centre: *centre + *circle * DVec2::new(angle.cos(), angle.sin()),
                    radius: *radius,
                    strength: *strength,
                };
                timed(&mut |field| stamp(field, &brush))?
            }
            Change::Waves(waves) => timed(&mut |field| waves.step(field).map(|()| whole(field)))?,
            Change::Erosion(erosion) => {
                timed(&mut |field| erosion.step(field).map(|_| whole(field)))?
            }
        };
        Ok((region.len(), change_ms))
    }
}

/// Runs `relief bench --dynamic KIND` on `field` (described by `source`).
pub fn run(
    args: &BenchArgs,
    kind: DynamicKind,
    field: Arc<HeightField>,
    source: &str,
    views: &[String],
    surfaces: &[Surface],
) -> Result<()> {
    let (w, h) = args.res;
    let (view, camera) = benchmark_views(&field, w, h)?
        .into_iter()
        .find(|(name, _)| views.first().is_some_and(|v| v == name))
        .context("the view to draw")?;
    let surface = surfaces[0];
    let bounds = field.world_bounds(surface);
    let mut params = ShadingParams::for_terrain(&field.world_bounds(Surface::Boxes))?;
    params.shadows = !args.no_shadows;
    let far = args.hybrid.far.unwrap_or_default();
    let mut renderer = HybridRenderer::new(field.clone(), surface, args.hybrid.params(), far)?;
    let target = camera.target();
    let mut change = Change::new(kind, &field, DVec2::new(target.x, target.y))?;
    drop(field);
    let mut gbuffer = GBuffer::new(w as usize, h as usize)?;
    let mut out = std::io::stdout().lock();
    let kind_name = format!("{kind:?}").to_lowercase();
    if !args.json {
        writeln!(
            out,
            "relief bench --dynamic {kind_name}: {source}, {view} view, {surface}, {w}x{h}, \
             hybrid renderer (far field {far}), shadows {}, {} threads",
            if params.shadows { "on" } else { "off" },
            rayon::current_num_threads()
        )?;
        writeln!(
            out,
            "{:>5} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
            "frame", "samples", "change ms", "update ms", "render ms", "shade ms", "frame ms"
        )?;
    }
    let mut frames = Vec::new();
    for frame in 0..args.frames {
        let timer = Instant::now();
        let (samples, change_ms) = change.apply(&mut renderer, frame)?;
        let update_ms = ms(timer);
        let timer = Instant::now();
        renderer.render_into(&camera, &bounds, &mut gbuffer, None)?;
        let render_ms = ms(timer);
        let timer = Instant::now();
        let _shown = shade_to_srgb8(&gbuffer, renderer.tracer(), &camera, &params)?;
        let shade_ms = ms(timer);
        let frame_ms = update_ms + render_ms + shade_ms;
        if args.json {
            writeln!(
                out,
                "{{\"dynamic\": \"{kind_name}\", \"frame\": {frame}, \"samples\": {samples}, \"change_ms\": {change_ms}, \"update_ms\": {update_ms}, \"render_ms\": {render_ms}, \"shade_ms\": {shade_ms}, \"frame_ms\": {frame_ms}}}"
            )?;
        } else {
            writeln!(
                out,
                "{frame:>5} {samples:>10} {change_ms:>10.1} {update_ms:>10.1} {render_ms:>10.1} {shade_ms:>10.1} {frame_ms:>10.1}"
            )?;
        }
        frames.push([update_ms, render_ms, shade_ms, frame_ms, change_ms]);
    }
    let median = |k: usize| {
        let mut v: Vec<f64> = frames.iter().map(|f| f[k]).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (update, render, shade, frame, changed) =
        (median(0), median(1), median(2), median(3), median(4));
    if args.json {
        writeln!(
            out,
            "{{\"dynamic\": \"{kind_name}\", \"view\": \"{view}\", \"surface\": \"{surface}\", \"width\": {w}, \"height\": {h}, \"far\": \"{far}\", \"shadows\": {}, \"frames\": {}, \"median_change_ms\": {changed}, \"median_update_ms\": {update}, \"median_render_ms\": {render}, \"median_shade_ms\": {shade}, \"median_frame_ms\": {frame}, \"frames_per_s\": {}}}",
            params.shadows,
            frames.len(),
            1e3 / frame
        )?;
    } else {
        writeln!(
            out,
            "median: update {update:.1} ms (the change {changed:.1} ms), render {render:.1} ms, shade {shade:.1} ms, frame {frame:.1} ms ({:.1} frames/s)",
            1e3 / frame
        )?;
    }
    Ok(())
}

fn ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}
