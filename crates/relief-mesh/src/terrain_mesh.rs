//! The meshes the material-stack pipeline makes and relief exports: named parts (`solid`,
//! `water`) of quads and triangles with per-vertex normals and colours ([`TerrainMesh`]).

use crate::{IndexedMesh, MeshError};
use relief_core::DVec3;

/// One named part of a [`TerrainMesh`]: an indexed mesh of quads and triangles (a quad whose
/// stitching collapsed one corner), with a unit normal and a linear-RGB colour per vertex.
///
/// Quads list their corners in order around the face, and every face is wound
/// counter-clockwise seen from outside the part's volume (its normal points out).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshPart {
    /// Name of the part: `solid` or `water` for stacks meshes.
    pub name: String,
    /// Vertex positions, world coordinates (metres).
    pub positions: Vec<DVec3>,
    /// Unit vertex normals pointing out of the volume.
    pub normals: Vec<[f32; 3]>,
    /// Vertex colours, linear RGB in `[0, 1]`.
    pub colors: Vec<[f32; 3]>,
    /// Quad faces as four vertex indices, counter-clockwise seen from outside.
    pub quads: Vec<[u32; 4]>,
    /// Triangle faces as three vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Base colour of the part's material, linear RGBA.
    pub base_color: [f32; 4],
}

impl MeshPart {
    /// An empty part named `name` with the material colour `base_color` (linear RGBA).
    pub fn new(name: &str, base_color: [f32; 4]) -> Self {
        MeshPart { name: name.to_string(), base_color, ..Default::default() }
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Whether the part has no faces.
    pub fn is_empty(&self) -> bool {
        self.quads.is_empty() && self.triangles.is_empty()
    }

    /// Every face as triangles: each quad split along its shorter diagonal (its corners
    /// `0, 1, 2, 3` into `0, 1, 2` and `0, 2, 3`, or `0, 1, 3` and `1, 2, 3`), then the
    /// triangles; the winding is kept.
    pub fn triangulated(&self) -> Vec<[u32; 3]> {
        let mut out = Vec::with_capacity(self.quads.len() * 2 + self.triangles.len());
        for &[a, b, c, d] in &self.quads {
            let p = |v: u32| self.positions[v as usize];
            if p(a).distance_squared(p(c)) <= p(b).distance_squared(p(d)) {
                out.push([a, b, c]);
                out.push([a, c, d]);
            } else {
                out.push([a, b, d]);
                out.push([b, c, d]);
            }
        }
        out.extend_from_slice(&self.triangles);
        out
    }

    /// The part as an [`IndexedMesh`] for the rasterizer, with the colour (3 floats) then
    /// the normal (3 floats) as per-vertex attributes.
    pub fn to_indexed_mesh(&self) -> Result<IndexedMesh, MeshError> {
        let mut attributes = Vec::with_capacity(self.positions.len() * 6);
        for (color, normal) in self.colors.iter().zip(&self.normals) {
            attributes.extend_from_slice(color);
            attributes.extend_from_slice(normal);
        }
        IndexedMesh::new(self.positions.clone(), self.triangulated())?
            .with_attributes(6, attributes)
    }
}

/// A terrain mesh: its named parts, e.g. `solid` and `water`, each with its own material.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TerrainMesh {
    /// The parts, in the order they are exported.
    pub parts: Vec<MeshPart>,
}

impl TerrainMesh {
    /// The part named `name`, if any.
    pub fn part(&self, name: &str) -> Option<&MeshPart> {
        self.parts.iter().find(|p| p.name == name)
    }

    /// Total number of quads and triangles over all parts.
    pub fn face_count(&self) -> usize {
        self.parts.iter().map(|p| p.quads.len() + p.triangles.len()).sum()
    }
}
