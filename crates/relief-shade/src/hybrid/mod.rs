//! Hybrid rendering of dynamic height fields (Ammann et al. 2010) into relief's G-buffer: the
//! cells near the camera rasterized as meshes at full resolution, the others ray cast inside
//! their proxy boxes, at a level of precision (the paper's far field) or exactly (relief's
//! `--far exact`).
//!
//! Per frame ([`HybridRenderer::render_into`]):
//! 1. the heuristic of section 4.2 chooses, per cell, culled, mesh or ray casting at a level;
//! 2. the mesh cells (meshes cached across frames, rebuilt where an edit touched them) are
//!    rasterized by relief-mesh's [`relief_mesh::Rasterizer`] with exact ray-plane distances;
//! 3. the far field: with levels of precision, every ray-cast cell's pixels (its projected
//!    proxy box) are searched front to back, depth-tested against what is drawn;
//!    exactly, from the nearest entry `t0` into a ray-cast proxy box per pixel, the exact
//!    tracer searches `[t0, near depth]`;
//! 4. every pixel's hit is written into the G-buffer as the other renderers write it.
//!
//! Edits ([`HybridRenderer::edit`]) update the field, the exact tracer's pyramid, the cells'
//! bounds and the mesh cache only where the samples changed.

mod far_field;
mod heuristic;
mod near_field;
mod projection;
mod renderer;

pub use far_field::{FarField, PixelSource};
pub use heuristic::{CellChoice, HybridHeuristic, HybridParams, LEVEL_COUNTS};
pub(crate) use near_field::mesh_hit;
pub use projection::{bottom_visible, project_box, BoxProjection, PixelRect};
pub use renderer::{HybridRenderer, HybridStats};
