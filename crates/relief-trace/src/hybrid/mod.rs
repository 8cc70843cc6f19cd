//! Hybrid rendering of dynamic height fields (Ammann et al. 2010): the per-cell machinery.
//!
//! - [`HybridCells`]: the terrain in square cells of n x n samples with their height bounds
//!   and proxy boxes, updated only where an edit touched them;
//! - [`HybridHeuristic`]: the choice per cell of section 4.2 (culled, mesh, or ray casting at
//!   a level of precision), from [`HybridParams`];
//! - [`lop_cast`]: the approximate linear-then-binary search inside one proxy box (section 3);
//! - [`exact_far_hit`]: relief's exact far field, the exact tracer between the nearest
//!   ray-cast box and the rasterized near field.
//!
//! A frame of the hybrid renderer, with these parts:
//!
//! 1. after an edit of the field, [`HybridCells::update`] over the edited region (and
//!    [`crate::MipmapTracer::edit`] for the exact far field);
//! 2. [`HybridHeuristic::choose`] for the camera; for a view from below the lowest sample
//!    ([`HybridCells::bottom_visible`]) first [`HybridCells::set_floor_everywhere`]; an eye
//!    inside the solid (an exact hit at distance 0) sees nothing else;
//! 3. the `Mesh` cells rasterized (with the walls of their cells), giving a depth per pixel;
//! 4. every `RayCast` cell's pixels from its projected proxy box ([`project_box`],
//!    [`BoxProjection::pixels`]): with levels of precision, [`lop_cast`] at the cell's
//!    level there, the nearest depth kept; with the exact far field, the nearest
//!    [`box_entry`] as `t0` and the rasterized depth as `t1` of [`exact_far_hits`]. Any
//!    lower bound works as `t0` (0 too): it only spares the exact tracer the part of the ray
//!    before the first ray-cast box; pixels no cell covers see no terrain.
//!
//! The property tests trace whole images this way (the rasterizer's part by the exact
//! tracer inside each mesh cell's box): with the exact far field every pixel equals the exact
//! tracer.
//!
//! ```
//! use relief_core::{Camera, DVec3, GridGeometry, HeightField, Surface};
//! use relief_trace::hybrid::{CellChoice, HybridCells, HybridHeuristic, HybridParams};
//! let samples = (0..64 * 64).map(|k| (k % 7) as f32).collect();
//! let field = HeightField::new(64, 64, samples, GridGeometry::unit()).unwrap();
//! let params = HybridParams { cell: 16, ..HybridParams::default() };
//! let cells = HybridCells::new(&field, Surface::Triangles, params.cell).unwrap();
//! let (eye, target) = (DVec3::new(-5.0, -5.0, 12.0), DVec3::new(40.0, 40.0, 0.0));
//! let camera = Camera::look_at(eye, target, DVec3::Z, 60.0, 320, 200).unwrap();
//! let choices = HybridHeuristic::new(params).unwrap().choose(&cells, &camera);
//! assert_eq!(choices.len(), cells.len());
//! assert!(choices.contains(&CellChoice::Mesh));
//! ```

mod cells;
mod far_exact;
mod heuristic;
mod lop;

pub use cells::{CellBounds, CellSpan, HybridCells};
pub use far_exact::{exact_far_hit, exact_far_hits};
pub use heuristic::{
    lop_steps, project_box, BoxProjection, CellChoice, HybridHeuristic, HybridParams, LopSteps,
    PixelRect, LEVEL_COUNTS, PAPER_LEVELS,
};
pub use lop::{box_entry, lop_cast};
