//! The one shape of every renderer: a camera's view written into a [`GBuffer`], with the
//! time each stage of the frame took, for the one deferred shading pass to light.

use std::time::Instant;

use relief_core::{Aabb, Camera};
use relief_trace::Tracer;

use crate::render::render_gbuffer_into;
use crate::{GBuffer, ShadeError, TraceStats};

/// Named stages of one frame with the milliseconds each took, in the order they ran (the
/// `*_ms` keys of `--stats`: a stage named `trace` is `trace_ms`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StageTimings {
    stages: Vec<(&'static str, f64)>,
}

impl StageTimings {
    /// No stage yet.
    pub fn new() -> Self {
        StageTimings::default()
    }

    /// Appends stage `name`, which took `ms` milliseconds.
    pub fn push(&mut self, name: &'static str, ms: f64) {
        self.stages.push((name, ms));
    }

    /// Runs `work` as stage `name`, timing it.
    pub fn time<T>(&mut self, name: &'static str, work: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let result = work();
        self.push(name, start.elapsed().as_secs_f64() * 1e3);
        result
    }

    /// The milliseconds of stage `name` (summed if it ran more than once), or `None`.
    pub fn get(&self, name: &str) -> Option<f64> {
        let mut times = self.stages.iter().filter(|(n, _)| *n == name).map(|(_, ms)| ms);
        let first = times.next()?;
        Some(first + times.sum::<f64>())
    }

    /// Every stage with its milliseconds, in the order they ran.
    pub fn stages(&self) -> &[(&'static str, f64)] {
        &self.stages
    }

    /// The milliseconds of all stages together.
    pub fn total_ms(&self) -> f64 {
        self.stages.iter().map(|(_, ms)| ms).sum()
    }
}

/// Something that draws a camera's view of a terrain into a G-buffer: the ray caster
/// ([`RayCaster`]), the hybrid renderer ([`crate::HybridRenderer`]), geometry clipmaps
/// ([`crate::ClipmapRenderer`]), the stacks mesh ([`crate::StacksRenderer`]) and the MLHM
/// renderer of boxes or smooth surfaces ([`crate::mlhm::MlhmRenderer`]).
///
/// A renderer knows how it finds each pixel's surface; what it writes is the same for all,
/// so one deferred pass ([`crate::shade`], [`crate::mlhm::shade_mlhm`]) lights any of them.
/// A renderer may keep state across frames (mesh caches, raster targets), hence `&mut self`.
pub trait Renderer {
    /// Writes `camera`'s view into `gbuffer` (every pixel overwritten) and returns how long
    /// each stage took.
    ///
    /// Fails when the G-buffer's size is not the camera's image size, or when a stage fails.
    fn render_frame(
        &mut self,
        camera: &Camera,
        gbuffer: &mut GBuffer,
    ) -> Result<StageTimings, ShadeError>;
}

/// Ray casting: one ray per pixel through any [`Tracer`] ([`render_gbuffer_into`]).
pub struct RayCaster<'a> {
    tracer: &'a dyn Tracer,
    bounds: Aabb,
    stats: TraceStats,
}

impl<'a> RayCaster<'a> {
    /// The ray caster of `tracer`, texture coordinates spanning `bounds` (the terrain's world
    /// bounds).
    pub fn new(tracer: &'a dyn Tracer, bounds: Aabb) -> Self {
        RayCaster { tracer, bounds, stats: TraceStats::default() }
    }

    /// The camera rays of the last frame.
    pub fn last_stats(&self) -> TraceStats {
        self.stats
    }
}

impl Renderer for RayCaster<'_> {
    /// One stage, `trace`.
    fn render_frame(
        &mut self,
        camera: &Camera,
        gbuffer: &mut GBuffer,
    ) -> Result<StageTimings, ShadeError> {
        let mut timings = StageTimings::new();
        let (tracer, bounds) = (self.tracer, &self.bounds);
        self.stats = timings
            .time("trace", || render_gbuffer_into(tracer, camera, bounds, gbuffer, &|_| {}))?;
        Ok(timings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_keep_their_order_and_sum() {
        let mut t = StageTimings::new();
        t.push("mesh", 2.0);
        t.push("raster", 0.5);
        t.push("mesh", 1.0);
        assert_eq!(t.stages(), &[("mesh", 2.0), ("raster", 0.5), ("mesh", 1.0)]);
        assert_eq!((t.get("mesh"), t.get("raster"), t.get("far")), (Some(3.0), Some(0.5), None));
        assert_eq!(t.total_ms(), 3.5);
        let value = t.time("far", || 7);
        assert_eq!(value, 7);
        assert!(t.get("far").is_some_and(|ms| ms >= 0.0));
    }
}
