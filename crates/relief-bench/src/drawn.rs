//! What a tracer measurement draws each view with: a tracer through the ray-casting render
//! pass, or a renderer that rasterizes.

use crate::error::BenchError;
use relief_core::{Aabb, Camera, HeightField, Surface};
use relief_render::{BuiltTracer, Progress, SafetySettings, TracerChoice, TracerSpec};
use relief_shade::hybrid::HybridParams;
use relief_shade::{
    render_gbuffer_into, ClipmapRenderer, FarField, GBuffer, HybridRenderer, TraceStats,
};
use relief_trace::adapters::OneRayAtATime;
use relief_trace::{Simd, Tracer};
use std::sync::Arc;

/// How a [`Drawn`] is built: the settings of every kind of tracer and renderer.
#[derive(Debug, Clone)]
pub struct DrawnSettings {
    /// The safety tracers' settings.
    pub safety: SafetySettings,
    /// The hybrid renderer's parameters.
    pub hybrid: HybridParams,
    /// The hybrid renderer's far field.
    pub far: FarField,
    /// The memory limit (bytes) of the tracers' builds.
    pub max_memory: u64,
    /// What the mipmap tracer's packet tests run on.
    pub simd: Simd,
}

/// What is measured: a tracer through the ray-casting render pass, or a renderer that
/// rasterizes (the hybrid renderer, geometry clipmaps).
pub enum Drawn {
    /// A tracer, built by the scene layer.
    Tracer(Box<BuiltTracer>),
    /// The hybrid renderer.
    Hybrid(Box<HybridRenderer>),
    /// Geometry clipmaps.
    Clipmap(Box<ClipmapRenderer>),
}

impl Drawn {
    /// Builds `tracer` over `surface` of `field`, reporting the build to `progress`.
    pub fn build(
        settings: &DrawnSettings,
        field: &Arc<HeightField>,
        surface: Surface,
        tracer: &TracerChoice,
        progress: &dyn Progress,
    ) -> Result<Self, BenchError> {
        Ok(match tracer {
            TracerChoice::Hybrid => {
                let (params, far) = (settings.hybrid, settings.far);
                Drawn::Hybrid(Box::new(HybridRenderer::new(field.clone(), surface, params, far)?))
            }
            TracerChoice::Clipmap if surface == Surface::Boxes => {
                return Err(BenchError::ClipmapBoxes);
            }
            TracerChoice::Clipmap => Drawn::Clipmap(Box::new(ClipmapRenderer::new(
                field.clone(),
                relief_mesh::ClipmapParams::default(),
            )?)),
            _ => {
                let spec = TracerSpec {
                    choice: tracer.clone(),
                    surface,
                    safety: settings.safety.clone(),
                    use_cache: false,
                    max_memory: settings.max_memory,
                    simd: settings.simd,
                };
                Drawn::Tracer(Box::new(spec.build_reporting(field, progress)?))
            }
        })
    }

    /// Draws the view into `gbuffer`, `traced(n)` told of every `n` pixels done; the primary
    /// rays' statistics (for the rasterizing renderers, the pixels and hits only).
    pub fn render(
        &mut self,
        single_rays: bool,
        camera: &Camera,
        bounds: &Aabb,
        gbuffer: &mut GBuffer,
        traced: &(dyn Fn(u64) + Sync),
    ) -> Result<TraceStats, BenchError> {
        let pixels = camera.width() as u64 * camera.height() as u64;
        match self {
            Drawn::Tracer(built) => {
                let one_at_a_time = OneRayAtATime(built.tracer.as_ref());
                let tracer: &dyn Tracer =
                    if single_rays { &one_at_a_time } else { built.tracer.as_ref() };
                return Ok(render_gbuffer_into(tracer, camera, bounds, gbuffer, traced)?);
            }
            Drawn::Hybrid(hybrid) => {
                hybrid.render_into(camera, bounds, gbuffer, None)?;
            }
            Drawn::Clipmap(clipmap) => {
                clipmap.render_into(camera, bounds, gbuffer)?;
            }
        }
        traced(pixels);
        let hits = gbuffer.distance.iter().filter(|d| d.is_finite()).count() as u64;
        Ok(TraceStats { rays: pixels, hits, ..TraceStats::default() })
    }

    /// The exact tracer that traces the shadow rays.
    pub fn tracer(&self) -> &dyn Tracer {
        match self {
            Drawn::Tracer(built) => built.tracer.as_ref(),
            Drawn::Hybrid(hybrid) => hybrid.tracer(),
            Drawn::Clipmap(clipmap) => clipmap.tracer(),
        }
    }
}
