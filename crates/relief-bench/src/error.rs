//! What can go wrong measuring, by cause. The messages are the ones `relief bench` shows.

use relief_core::CoreError;
use relief_render::RenderError;
use relief_shade::ShadeError;
use relief_sim::SimError;
use relief_trace::TraceError;

/// An error of a measurement.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The scene layer could not build a tracer.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A camera or a field that is not valid.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// A tracer could not be built or refused its rays.
    #[error(transparent)]
    Trace(#[from] TraceError),
    /// A renderer, the G-buffer or the shading failed.
    #[error(transparent)]
    Shade(#[from] ShadeError),
    /// A change of the field (a brush, a simulation step) failed.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// The ocean wave simulation could not start on the field.
    #[error("waves")]
    Waves(#[source] SimError),
    /// The erosion could not start on the field.
    #[error("erosion")]
    Erosion(#[source] SimError),
    /// Geometry clipmaps asked to draw the boxes surface.
    #[error("geometry clipmaps draw the triangles surface only (use --surfaces triangles)")]
    ClipmapBoxes,
}
