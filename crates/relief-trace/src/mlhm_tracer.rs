//! What every MLHM box tracer offers besides the [`Tracer`] interface: hits with their material
//! and column, in any intersection mode.

use crate::{MlhmHit, MlhmMode, Tracer};
use relief_core::{DVec2, Mlhm, Ray};
use std::sync::Arc;

/// An exact tracer of an [`Mlhm`]'s boxes, in every [`MlhmMode`]: the naive 2D DDA
/// ([`MlhmNaiveTracer`](crate::MlhmNaiveTracer)) and the hierarchical traversal
/// ([`MlhmHierarchyTracer`](crate::MlhmHierarchyTracer)) give bit-identical hits.
///
/// Shading traces the visible surface, the solids alone (shadow rays) and, from under water,
/// the solids and the air through the same tracer.
pub trait MlhmTracer: Tracer {
    /// The map traced.
    fn map(&self) -> &Arc<Mlhm>;

    /// World `(x, y)` of the grid's south-west corner.
    fn origin(&self) -> DVec2;

    /// The first hit of `ray` with the boxes of `mode`, counting the nodes and cells visited
    /// into `steps`. Returns `None`, never panics, for rays with a non-finite origin or
    /// direction, a zero direction or an empty or NaN range.
    fn intersect_mode_counted(&self, ray: &Ray, mode: MlhmMode, steps: &mut u32)
        -> Option<MlhmHit>;

    /// The first hit of `ray` with the boxes of `mode`.
    fn intersect_mode(&self, ray: &Ray, mode: MlhmMode) -> Option<MlhmHit> {
        self.intersect_mode_counted(ray, mode, &mut 0)
    }

    /// Whether `ray` meets a box of `mode` within its range (for shadow rays).
    fn occluded_mode(&self, ray: &Ray, mode: MlhmMode) -> bool {
        self.intersect_mode(ray, mode).is_some()
    }

    /// How much of a distant light reaches the origin of the shadow ray `ray` past the solids,
    /// counting the nodes and cells visited into `steps`: 0 when the ray meets a solid, else
    /// 1 for a hard shadow. Tracers of a smooth surface may return values in between, a soft
    /// shadow's penumbra, but always 0 where the ray meets a solid.
    fn light_visibility(&self, ray: &Ray, steps: &mut u32) -> f64 {
        match self.intersect_mode_counted(ray, MlhmMode::Solids, steps) {
            Some(_) => 0.0,
            None => 1.0,
        }
    }
}
