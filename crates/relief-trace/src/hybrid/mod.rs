//! Hybrid rendering of dynamic height fields (Ammann et al. 2010): the per-cell machinery a
//! tracer owns, which knows no camera and no pixel.
//!
//! - [`HybridCells`]: the terrain in square cells of n x n samples with their height bounds
//!   and proxy boxes, updated only where an edit touched them;
//! - [`LopSteps`]: the linear and binary search steps of a level of precision
//!   ([`lop_steps`], the paper's [`PAPER_LEVELS`]);
//! - [`lop_cast`]: the approximate linear-then-binary search inside one proxy box (section 3);
//! - [`exact_far_hit`]: relief's exact far field, the exact tracer between the nearest
//!   ray-cast box and the rasterized near field.
//!
//! The renderer that puts them together for a camera (the heuristic of section 4.2 choosing
//! per cell, the projection of proxy boxes onto pixels, the rasterized near field) is
//! relief-shade's `HybridRenderer`. Its frame, with these parts:
//!
//! 1. after an edit of the field, [`HybridCells::update`] over the edited region (and
//!    [`crate::MipmapTracer::edit`] for the exact far field);
//! 2. the choice per cell for the camera; for a view from below the lowest sample first
//!    [`HybridCells::set_floor_everywhere`]; an eye inside the solid (an exact hit at
//!    distance 0) sees nothing else;
//! 3. the `Mesh` cells rasterized (with the walls of their cells), giving a depth per ray;
//! 4. every ray-cast cell's rays: with levels of precision, [`lop_cast`] at the cell's
//!    level, the nearest depth kept; with the exact far field, the nearest [`box_entry`] as
//!    `t0` and the rasterized depth as `t1` of [`exact_far_hits`]. Any lower bound works as
//!    `t0` (0 too): it only spares the exact tracer the part of the ray before the first
//!    ray-cast box; rays no cell covers see no terrain.
//!
//! ```
//! use relief_core::{DVec3, GridGeometry, HeightField, Ray, Surface};
//! use relief_trace::hybrid::{box_entry, lop_cast, HybridCells, PAPER_LEVELS};
//! let samples = (0..64 * 64).map(|k| (k % 7) as f32).collect();
//! let field = HeightField::new(64, 64, samples, GridGeometry::unit()).unwrap();
//! let cells = HybridCells::new(&field, Surface::Triangles, 16).unwrap();
//! let ray = Ray::new(DVec3::new(8.0, 8.0, 20.0), DVec3::new(0.0, 0.0, -1.0));
//! let (enter, _exit) = box_entry(&cells, &field, 0, &ray).unwrap();
//! let hit = lop_cast(&field, &cells, 0, &ray, PAPER_LEVELS[0]).unwrap();
//! assert!(hit.t >= enter);
//! ```

mod cells;
mod far_exact;
mod levels;
mod lop;

pub use cells::{CellBounds, CellSpan, HybridCells};
pub use far_exact::{exact_far_hit, exact_far_hits};
pub use levels::{lop_steps, LopSteps, PAPER_LEVELS};
pub use lop::{box_entry, lop_cast};
