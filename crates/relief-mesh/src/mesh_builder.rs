//! A mesh grown vertex by vertex and triangle by triangle, as the height-field, box and
//! clipmap meshes are made.

use crate::IndexedMesh;
use relief_core::DVec3;

/// Grows a mesh: vertices and triangles, skipping triangles with a repeated vertex (a wall of
/// zero height).
#[derive(Debug, Default)]
pub(crate) struct MeshBuilder {
    /// Vertex positions, world.
    pub(crate) positions: Vec<DVec3>,
    /// Triangles, indices into `positions`.
    pub(crate) triangles: Vec<[u32; 3]>,
}

impl MeshBuilder {
    /// Adds a vertex at `p`; returns its index.
    pub(crate) fn vertex(&mut self, p: DVec3) -> u32 {
        self.positions.push(p);
        (self.positions.len() - 1) as u32
    }

    /// Adds the triangle a-b-c, unless two of its corners are one vertex.
    pub(crate) fn triangle(&mut self, a: u32, b: u32, c: u32) {
        if a != b && b != c && a != c {
            self.triangles.push([a, b, c]);
        }
    }

    /// The quad a-b-c-d (in order around it) as two triangles split along a-c.
    pub(crate) fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.triangle(a, b, c);
        self.triangle(a, c, d);
    }

    /// The mesh grown.
    pub(crate) fn finish(self) -> IndexedMesh {
        // Indices are in range and positions finite by construction.
        IndexedMesh::new(self.positions, self.triangles).unwrap_or_default()
    }
}
