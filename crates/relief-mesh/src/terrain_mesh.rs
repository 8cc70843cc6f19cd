//! The meshes the material-stack pipeline makes and relief exports: named parts (`solid`,
//! `water`) of quads and triangles with per-vertex normals and colours ([`TerrainMesh`]).

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
        for quad in &self.quads {
            out.extend(split_quad(*quad, |v| self.positions[v as usize]));
        }
        out.extend_from_slice(&self.triangles);
        out
    }
}

/// The two triangles of quad `[a, b, c, d]` split along its shorter diagonal (`a, b, c` and
/// `a, c, d`, or `a, b, d` and `b, c, d`), winding kept; `at` gives a corner's position.
pub(crate) fn split_quad(quad: [u32; 4], at: impl Fn(u32) -> DVec3) -> [[u32; 3]; 2] {
    let [a, b, c, d] = quad;
    if at(a).distance_squared(at(c)) <= at(b).distance_squared(at(d)) {
        [[a, b, c], [a, c, d]]
    } else {
        [[a, b, d], [b, c, d]]
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
