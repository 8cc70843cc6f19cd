//! What `relief bench` measures each view with: a tracer through the ray-casting render
//! pass, or a renderer that rasterizes.

use crate::args::BenchArgs;
use crate::progress;
use anyhow::{bail, Result};
use relief_core::{Camera, HeightField, Surface};
use relief_render::{BuiltTracer, TracerChoice, TracerSpec};
use relief_shade::{render_gbuffer_into, ClipmapRenderer, GBuffer, HybridRenderer, TraceStats};
use relief_trace::adapters::OneRayAtATime;
use relief_trace::{Simd, Tracer};
use std::sync::Arc;

/// What `relief bench` measures: a tracer through the ray-casting render pass, or a renderer
/// that rasterizes (the hybrid renderer, geometry clipmaps).
pub(super) enum Drawn {
    Tracer(Box<BuiltTracer>),
    Hybrid(Box<HybridRenderer>),
    Clipmap(Box<ClipmapRenderer>),
}

impl Drawn {
    pub(super) fn build(
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
                let spec = TracerSpec {
                    choice: tracer.clone(),
                    surface,
                    safety: crate::scene_options::safety_settings(&args.safety),
                    use_cache: false,
                    max_memory: limit,
                    simd,
                };
                let built = spec.build_reporting(field, &progress::Bars::default())?;
                Drawn::Tracer(Box::new(built))
            }
        })
    }

    /// Draws the view into `gbuffer`; the primary rays' statistics (for the rasterizing
    /// renderers, the pixels and hits only).
    pub(super) fn render(
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
    pub(super) fn tracer(&self) -> &dyn Tracer {
        match self {
            Drawn::Tracer(built) => built.tracer.as_ref(),
            Drawn::Hybrid(hybrid) => hybrid.tracer(),
            Drawn::Clipmap(clipmap) => clipmap.tracer(),
        }
    }
}
