//! The hybrid renderer drawing a height field that changes every frame (Ammann et al. 2010,
//! section 5.3 and Figure 11): a brush stamping the ground, the ocean wave simulation or the
//! height-field erosion, each frame's update (the change and the renderer's own update) and
//! render (hybrid G-buffer, then shading with shadow rays) timed apart.

use crate::error::BenchError;
use relief_core::{Aabb, Camera, DVec2, HeightField, SampleRegion, Surface};
use relief_shade::hybrid::HybridParams;
use relief_shade::{shade_to_srgb8, FarField, GBuffer, HybridRenderer, ShadingParams};
use relief_sim::{
    stamp, Brush, BrushKind, ErosionParams, HeightFieldErosion, SimError, WaveParams,
    WaveSimulation,
};
use std::sync::Arc;
use std::time::Instant;

/// What changes the field every frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChangeKind {
    /// A brush raising and lowering the ground along a circle around the view's target.
    Stamp,
    /// The ocean wave simulation rewriting the whole field.
    Waves,
    /// The height-field erosion rewriting the whole field.
    Erosion,
}

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
    fn new(kind: ChangeKind, field: &HeightField, target: DVec2) -> Result<Self, BenchError> {
        let g = field.geometry();
        let size = (field.width() as f64 * g.dx).max(field.height() as f64 * g.dy);
        let relief = (field.max_sample() - field.min_sample()) as f64 * g.z_scale;
        Ok(match kind {
            ChangeKind::Stamp => Change::Stamp {
                centre: target,
                circle: size / 16.0,
                radius: size / 64.0,
                strength: relief.max(1e-3) / 50.0,
            },
            ChangeKind::Waves => Change::Waves(Box::new(
                WaveSimulation::new(field, WaveParams::for_field(field))
                    .map_err(BenchError::Waves)?,
            )),
            ChangeKind::Erosion => Change::Erosion(Box::new(
                HeightFieldErosion::new(field, ErosionParams::default())
                    .map_err(BenchError::Erosion)?,
            )),
        })
    }

    /// Changes the field of `renderer` for frame `frame`; returns the samples changed and the
    /// milliseconds the change itself took (the rest of the update is the renderer's).
    fn apply(
        &mut self,
        renderer: &mut HybridRenderer,
        frame: u32,
    ) -> Result<(usize, f64), BenchError> {
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

/// The times of one frame (milliseconds), or their medians.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameTimes {
    /// The samples the change wrote.
    pub samples: usize,
    /// The change itself.
    pub change_ms: f64,
    /// The update: the change and the renderer's own update.
    pub update_ms: f64,
    /// The hybrid G-buffer.
    pub render_ms: f64,
    /// The shading.
    pub shade_ms: f64,
    /// The whole frame: update, render and shading.
    pub frame_ms: f64,
}

impl FrameTimes {
    /// The median of each time over `frames` (the median samples too); zeros for none.
    pub fn median(frames: &[FrameTimes]) -> FrameTimes {
        if frames.is_empty() {
            return FrameTimes::default();
        }
        let median = |time: fn(&FrameTimes) -> f64| {
            let mut v: Vec<f64> = frames.iter().map(time).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let mut samples: Vec<usize> = frames.iter().map(|f| f.samples).collect();
        samples.sort_unstable();
        FrameTimes {
            samples: samples[samples.len() / 2],
            change_ms: median(|f| f.change_ms),
            update_ms: median(|f| f.update_ms),
            render_ms: median(|f| f.render_ms),
            shade_ms: median(|f| f.shade_ms),
            frame_ms: median(|f| f.frame_ms),
        }
    }
}

/// The hybrid renderer drawing one view of a field that `kind` changes every frame.
pub struct DynamicBench {
    renderer: HybridRenderer,
    change: Change,
    camera: Camera,
    bounds: Aabb,
    params: ShadingParams,
    gbuffer: GBuffer,
}

impl DynamicBench {
    /// The hybrid renderer (`hybrid`, `far`) over `surface` of `field`, seen by `camera`,
    /// shaded with shadow rays where `shadows`, the field changed by `kind`.
    pub fn new(
        kind: ChangeKind,
        field: Arc<HeightField>,
        surface: Surface,
        camera: Camera,
        (hybrid, far): (HybridParams, FarField),
        shadows: bool,
    ) -> Result<Self, BenchError> {
        let bounds = field.world_bounds(surface);
        let mut params = ShadingParams::for_terrain(&field.world_bounds(Surface::Boxes))?;
        params.shadows = shadows;
        let renderer = HybridRenderer::new(field.clone(), surface, hybrid, far)?;
        let target = camera.target();
        let change = Change::new(kind, &field, DVec2::new(target.x, target.y))?;
        drop(field);
        let gbuffer = GBuffer::new(camera.width() as usize, camera.height() as usize)?;
        Ok(DynamicBench { renderer, change, camera, bounds, params, gbuffer })
    }

    /// Whether the frames are shaded with shadow rays.
    pub fn shadows(&self) -> bool {
        self.params.shadows
    }

    /// Changes the field for frame `frame`, updates the renderer, draws and shades the view;
    /// the times each took.
    pub fn frame(&mut self, frame: u32) -> Result<FrameTimes, BenchError> {
        let timer = Instant::now();
        let (samples, change_ms) = self.change.apply(&mut self.renderer, frame)?;
        let update_ms = ms(timer);
        let timer = Instant::now();
        self.renderer.render_into(&self.camera, &self.bounds, &mut self.gbuffer, None)?;
        let render_ms = ms(timer);
        let timer = Instant::now();
        let tracer = self.renderer.tracer();
        let _shown = shade_to_srgb8(&self.gbuffer, tracer, &self.camera, &self.params)?;
        let shade_ms = ms(timer);
        let frame_ms = update_ms + render_ms + shade_ms;
        Ok(FrameTimes { samples, change_ms, update_ms, render_ms, shade_ms, frame_ms })
    }
}

/// Milliseconds since `start`.
fn ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}
