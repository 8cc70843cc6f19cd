//! What every MLHM box tracer offers besides the [`Tracer`] interface: hits with their material
//! and column ([`MlhmHit`]), in any intersection mode.

use crate::{medium_at, Hit, Medium, MlhmMaterial, MlhmMode, Tracer};
use relief_core::{DVec2, DVec3, Mlhm, Ray};
use std::sync::Arc;

/// The first hit of a ray with an MLHM's boxes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlhmHit {
    /// Parameter, world position and the unit normal of the face hit, facing against the ray
    /// (top `+z`, bottom `-z`, or a side `+-x`, `+-y`); a ray that starts inside gets the
    /// reversed, normalised ray direction and `t` = its `t_min`.
    pub hit: Hit,
    /// The material at the hit.
    pub material: MlhmMaterial,
    /// The cell `(x, y)` hit.
    pub cell: (usize, usize),
    /// The column of that cell the material belongs to (for air: the column whose air it is,
    /// the one below the air).
    pub column: usize,
}

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

    /// The medium at world point `p` as this tracer's surface sees it; for boxes, the column
    /// of the cell below `p` decides ([`medium_at`]).
    fn medium(&self, p: DVec3) -> Medium {
        medium_at(self.map(), self.origin(), p)
    }

    /// How far off a hit, along its normal, secondary rays must start at least so that they
    /// do not find the surface they leave: 0 for exact box faces; a smooth surface's hits
    /// are found only to a tolerance.
    fn surface_offset(&self) -> f64 {
        0.0
    }

    /// Whether the hits lie on the flat, axis-aligned faces of the boxes (true for the box
    /// tracers): faces and steps far smaller than a pixel, whose shading terms (normal,
    /// occlusion, hard shadows) the lighting filters over the pixel's footprint. A smooth
    /// surface's tracer returns false: its normals and soft shadows are smooth already.
    fn faceted(&self) -> bool {
        true
    }

    /// The radius σ over which the surface smooths the boxes (the half-size of the cube of
    /// [`MlhmSmoothTracer`](crate::MlhmSmoothTracer)), `None` for the boxes themselves.
    /// Shading measures the terrain near a smooth hit smoothed as much, since the boxes
    /// there may lie up to about σ off the surface.
    fn smoothing_radius(&self) -> Option<f64> {
        None
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
