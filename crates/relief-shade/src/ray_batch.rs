//! A batch of rays handed to a tracer at once, with the answers and step counts it gets back.

use relief_core::Ray;
use relief_trace::{Hit, Tracer};

/// Rays traced together through [`Tracer::intersect_batch`] or [`Tracer::occluded_batch`]
/// (a tile of camera rays, the shadow rays of a tile); the buffers are kept between batches.
#[derive(Debug, Default)]
pub struct RayBatch {
    /// The rays to trace.
    pub rays: Vec<Ray>,
    /// After [`RayBatch::intersect`]: each ray's first hit.
    pub hits: Vec<Option<Hit>>,
    /// After [`RayBatch::occlude`]: whether each ray is blocked.
    pub occluded: Vec<bool>,
    /// Each ray's traversal steps.
    pub steps: Vec<u32>,
}

impl RayBatch {
    /// Empties the batch for the next rays.
    pub fn clear(&mut self) {
        self.rays.clear();
    }

    /// Traces the first hit of every ray with `tracer`.
    pub fn intersect(&mut self, tracer: &dyn Tracer) {
        // Only the length matters: the tracer writes every entry.
        self.hits.resize(self.rays.len(), None);
        self.reset_steps();
        tracer.intersect_batch(&self.rays, &mut self.hits, &mut self.steps);
    }

    /// Traces whether every ray is blocked within its range with `tracer`.
    pub fn occlude(&mut self, tracer: &dyn Tracer) {
        self.occluded.resize(self.rays.len(), false);
        self.reset_steps();
        tracer.occluded_batch(&self.rays, &mut self.occluded, &mut self.steps);
    }

    fn reset_steps(&mut self) {
        self.steps.clear();
        self.steps.resize(self.rays.len(), 0);
    }
}
