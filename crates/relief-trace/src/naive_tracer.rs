//! The reference tracer: visits every cell the ray crosses, in order (Amanatides & Woo).

use crate::cell_grid::CellGrid;
use crate::{Hit, Tracer};
use relief_core::{Aabb, HeightField, Ray, Surface};
use std::sync::Arc;

/// Cell-by-cell traversal of a height field: for `boxes` a texel DDA, for `triangles` the
/// inter-texel traversal with the two-triangle test (Baboud et al. 2011, 5.2.1).
///
/// Exact, with no precomputation; its cost grows linearly with the distance travelled.
#[derive(Debug, Clone)]
pub struct NaiveTracer {
    field: Arc<HeightField>,
    grid: CellGrid,
}

impl NaiveTracer {
    /// A naive tracer of `surface` over `field`.
    pub fn new(field: Arc<HeightField>, surface: Surface) -> Self {
        let grid = CellGrid::new(&field, surface);
        NaiveTracer { field, grid }
    }
}

impl Tracer for NaiveTracer {
    fn name(&self) -> &'static str {
        "naive"
    }

    fn surface(&self) -> Surface {
        self.grid.surface()
    }

    fn bounds(&self) -> Aabb {
        self.grid.world_bounds()
    }

    fn intersect_counted(&self, world_ray: &Ray, steps: &mut u32) -> Option<Hit> {
        let ray = self.grid.to_cell_space(world_ray);
        let clip = self.grid.clip(&ray)?;
        let samples = self.field.samples();
        let (mut cx, mut cy) = self.grid.cell_at(&ray, clip.t_enter);
        let (step_x, step_y) = (ray.dir.x.signum() as isize, ray.dir.y.signum() as isize);
        loop {
            *steps += 1;
            let seg = self.grid.segment(&ray, &clip, cx, cy);
            if let Some((t, normal)) = self.grid.intersect_cell(samples, &ray, cx, cy, &seg) {
                return Some(self.grid.world_hit(world_ray, t, normal));
            }
            let t_next = seg.t_next_x.min(seg.t_next_y);
            if t_next >= clip.t_exit {
                return None;
            }
            // Through a corner, step both axes at once.
            if seg.t_next_x == t_next {
                cx = cx.checked_add_signed(step_x).filter(|&c| c < self.grid.cells_x())?;
            }
            if seg.t_next_y == t_next {
                cy = cy.checked_add_signed(step_y).filter(|&c| c < self.grid.cells_y())?;
            }
        }
    }
}
