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
//! ```
//! use relief_core::{Camera, DVec3, GridGeometry, HeightField, Surface};
//! use relief_trace::hybrid::{CellChoice, HybridCells, HybridHeuristic, HybridParams};
//! let samples = (0..64 * 64).map(|k| (k % 7) as f32).collect();
//! let field = HeightField::new(64, 64, samples, GridGeometry::unit()).unwrap();
//! let params = HybridParams { cell: 16, ..HybridParams::default() };
//! let cells = HybridCells::new(&field, Surface::Triangles, params.cell).unwrap();
//! let camera =
//!     Camera::look_at(DVec3::new(-5.0, -5.0, 12.0), DVec3::new(40.0, 40.0, 0.0), DVec3::Z, 60.0, 320, 200)
//!         .unwrap();
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
