//! The hybrid renderer's near field: the meshes of the cells it rasterizes, cached across
//! frames and rebuilt where an edit changed their samples.

use super::heuristic::CellChoice;
use crate::ShadeError;
use rayon::prelude::*;
use relief_core::Ray;
use relief_core::{HeightField, SampleRegion};
use relief_mesh::{height_field_mesh, IndexedMesh};
use relief_trace::hybrid::HybridCells;
use relief_trace::Hit;

/// Per cell, its mesh once a frame has drawn it as a mesh (until an edit touches it).
pub(super) struct NearField {
    meshes: Vec<Option<IndexedMesh>>,
}

impl NearField {
    /// An empty cache for `cells` cells.
    pub(super) fn new(cells: usize) -> Self {
        NearField { meshes: vec![None; cells] }
    }

    /// Forgets the meshes of the cells holding a sample of `region` (or a neighbour of one:
    /// the walls around holes look at neighbouring samples).
    pub(super) fn invalidate(&mut self, cells: &HybridCells, region: SampleRegion) {
        if self.meshes.len() != cells.len() {
            *self = NearField::new(cells.len());
            return;
        }
        let (cells_x, cells_y) = cells.cells();
        let region = SampleRegion::new(
            region.col0.saturating_sub(1),
            region.row0.saturating_sub(1),
            region.col1 + 1,
            region.row1 + 1,
        );
        for j in 0..cells_y {
            for i in 0..cells_x {
                let s = cells.span(i, j);
                let overlaps = s.col0 < region.col1
                    && region.col0 <= s.col1
                    && s.row0 < region.row1
                    && region.row0 <= s.row1;
                if overlaps {
                    self.meshes[cells.index(i, j)] = None;
                }
            }
        }
    }

    /// Forgets every mesh.
    pub(super) fn invalidate_all(&mut self) {
        self.meshes.iter_mut().for_each(|m| *m = None);
    }

    /// One mesh of every cell `choices` rasterizes, in cell order (deterministic), building
    /// the missing ones in parallel.
    pub(super) fn frame_mesh(
        &mut self,
        field: &HeightField,
        cells: &HybridCells,
        choices: &[CellChoice],
    ) -> Result<IndexedMesh, ShadeError> {
        if self.meshes.len() != cells.len() {
            *self = NearField::new(cells.len());
        }
        let wanted: Vec<usize> =
            (0..choices.len()).filter(|&k| choices[k] == CellChoice::Mesh).collect();
        let missing: Vec<usize> =
            wanted.iter().copied().filter(|&k| self.meshes[k].is_none()).collect();
        let built: Vec<(usize, IndexedMesh)> = missing
            .par_iter()
            .map(|&k| Ok((k, height_field_mesh(field, cells.surface(), mesh_region(cells, k))?)))
            .collect::<Result<_, relief_mesh::MeshError>>()
            .map_err(|e| ShadeError::Limits(e.to_string()))?;
        for (k, mesh) in built {
            self.meshes[k] = Some(mesh);
        }
        let mut frame = IndexedMesh::default();
        for &k in &wanted {
            if let Some(mesh) = &self.meshes[k] {
                frame.append(mesh).map_err(|e| ShadeError::Limits(e.to_string()))?;
            }
        }
        Ok(frame)
    }
}

/// The samples (`triangles`) or texels (`boxes`) cell `index` meshes: its span. Neighbouring
/// cells share a line of samples: for triangles the squares between a cell's samples are its
/// own; for boxes the shared texels are meshed by both cells (identical triangles, at equal
/// distances, so the depth test keeps one), since a vertical face of a shared texel can reach
/// below one cell's box and lie in the other's only.
fn mesh_region(cells: &HybridCells, index: usize) -> SampleRegion {
    let (cells_x, _) = cells.cells();
    let s = cells.span(index % cells_x, index / cells_x);
    SampleRegion::new(s.col0, s.row0, s.col1 + 1, s.row1 + 1)
}

/// The hit of `ray` on triangle `triangle` of `mesh` (the rasterized pixel's), as a tracer's.
pub(crate) fn mesh_hit(mesh: &IndexedMesh, triangle: u32, ray: &Ray) -> Option<Hit> {
    mesh.hit(triangle, ray).map(|h| Hit { t: h.t, position: h.position, normal: h.normal })
}
