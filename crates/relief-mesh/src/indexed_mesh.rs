//! The indexed triangle mesh every relief renderer rasterizes, and its exact ray-plane hit.

use crate::MeshError;
use relief_core::{DVec3, Ray};

/// A triangle mesh in world coordinates: vertex positions, triangles as three vertex indices,
/// and optional per-vertex attributes (`attributes_per_vertex` floats for every vertex, e.g.
/// texture coordinates or material weights), validated on construction.
///
/// Both windings are front faces: the rasterizer draws a triangle seen from either side.
///
/// ```
/// use relief_core::DVec3;
/// use relief_mesh::IndexedMesh;
/// let mesh = IndexedMesh::new(
///     vec![DVec3::ZERO, DVec3::X, DVec3::Y],
///     vec![[0, 1, 2]],
/// ).unwrap();
/// assert_eq!(mesh.triangle_count(), 1);
/// assert!(IndexedMesh::new(vec![DVec3::ZERO], vec![[0, 1, 2]]).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IndexedMesh {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) triangles: Vec<[u32; 3]>,
    pub(crate) attributes_per_vertex: usize,
    pub(crate) attributes: Vec<f32>,
}

/// Where a ray meets the plane of one of a mesh's triangles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshHit {
    /// Ray parameter of the hit: the distance along a unit-direction ray.
    pub t: f64,
    /// World position `origin + t * dir`.
    pub position: DVec3,
    /// Unit geometric normal of the triangle, turned to face the ray (`dot(normal, dir) <= 0`).
    pub normal: DVec3,
    /// Barycentric coordinates of the hit for the triangle's vertices 0, 1, 2 (they sum to 1;
    /// slightly outside `[0, 1]` for a pixel centre on the triangle's edge, by rounding).
    pub barycentrics: [f64; 3],
}

impl IndexedMesh {
    /// A mesh of `positions` and `triangles` without attributes.
    ///
    /// Fails when a triangle names a vertex that does not exist, a position is not finite, or
    /// there are more than `u32::MAX` vertices or triangles.
    pub fn new(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        if positions.len() > u32::MAX as usize || triangles.len() >= u32::MAX as usize {
            return Err(MeshError::Limits(format!(
                "{} vertices and {} triangles exceed the u32 ids",
                positions.len(),
                triangles.len()
            )));
        }
        if let Some((index, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(MeshError::NonFinitePosition { index, x: p.x, y: p.y, z: p.z });
        }
        let vertex_count = positions.len();
        for (triangle, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&v| v as usize >= vertex_count) {
                return Err(MeshError::IndexOutOfRange { triangle, index, vertex_count });
            }
        }
        Ok(IndexedMesh { positions, triangles, attributes_per_vertex: 0, attributes: Vec::new() })
    }

    /// The same mesh with `per_vertex` attribute floats for every vertex, vertex-major
    /// (`values[v * per_vertex + k]`). Fails when the count does not match or a value is not
    /// finite.
    pub fn with_attributes(
        mut self,
        per_vertex: usize,
        values: Vec<f32>,
    ) -> Result<Self, MeshError> {
        let expected = per_vertex.checked_mul(self.positions.len());
        if expected != Some(values.len()) {
            return Err(MeshError::Attributes(format!(
                "{} values for {} vertices of {per_vertex} attributes",
                values.len(),
                self.positions.len()
            )));
        }
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(MeshError::Attributes(format!(
                "value {} of vertex {} is not finite",
                values[k],
                k / per_vertex.max(1)
            )));
        }
        self.attributes_per_vertex = per_vertex;
        self.attributes = values;
        Ok(self)
    }

    /// Vertex positions in world coordinates.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Triangles as indices into [`IndexedMesh::positions`].
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of attribute floats per vertex (0: none).
    pub fn attributes_per_vertex(&self) -> usize {
        self.attributes_per_vertex
    }

    /// All attributes, vertex-major.
    pub fn attributes(&self) -> &[f32] {
        &self.attributes
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Whether the mesh has no triangles.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Appends `other`'s vertices and triangles (its indices shifted past this mesh's
    /// vertices). Fails when the attribute counts differ or the ids would overflow `u32`.
    pub fn append(&mut self, other: &IndexedMesh) -> Result<(), MeshError> {
        if self.attributes_per_vertex != other.attributes_per_vertex
            && !(self.positions.is_empty() && self.attributes_per_vertex == 0)
        {
            return Err(MeshError::Attributes(format!(
                "cannot append a mesh of {} attributes per vertex to one of {}",
                other.attributes_per_vertex, self.attributes_per_vertex
            )));
        }
        let base = self.positions.len();
        let (vertices, triangles) =
            (base + other.positions.len(), self.triangles.len() + other.triangles.len());
        if vertices > u32::MAX as usize || triangles >= u32::MAX as usize {
            return Err(MeshError::Limits(format!(
                "{vertices} vertices and {triangles} triangles exceed the u32 ids"
            )));
        }
        let shift = base as u32;
        self.attributes_per_vertex = other.attributes_per_vertex;
        self.positions.extend_from_slice(&other.positions);
        self.attributes.extend_from_slice(&other.attributes);
        self.triangles.extend(other.triangles.iter().map(|t| t.map(|v| v + shift)));
        Ok(())
    }

    /// The three corners of `triangle`, or `None` when there is no such triangle.
    pub fn corners(&self, triangle: u32) -> Option<[DVec3; 3]> {
        let tri = self.triangles.get(triangle as usize)?;
        Some(tri.map(|v| self.positions[v as usize]))
    }

    /// Where `ray` meets the plane of `triangle`: the exact ray-plane distance
    /// `t = dot(n, p0 - o) / dot(n, d)` the rasterizer writes for the pixels it covers, the
    /// position, the normal facing the ray and the barycentrics. `None` when the triangle does
    /// not exist, is degenerate, or its plane is parallel to the ray. The triangle's edges are
    /// not tested: the rasterizer has decided coverage.
    pub fn hit(&self, triangle: u32, ray: &Ray) -> Option<MeshHit> {
        let [p0, p1, p2] = self.corners(triangle)?;
        let n = (p1 - p0).cross(p2 - p0);
        let t = n.dot(p0 - ray.origin) / n.dot(ray.dir);
        let area2 = n.length_squared();
        if !t.is_finite() || area2 == 0.0 {
            return None;
        }
        let position = ray.at(t);
        let b1 = (position - p0).cross(p2 - p0).dot(n) / area2;
        let b2 = (p1 - p0).cross(position - p0).dot(n) / area2;
        let unit = n / area2.sqrt();
        let normal = if unit.dot(ray.dir) > 0.0 { -unit } else { unit };
        Some(MeshHit { t, position, normal, barycentrics: [1.0 - b1 - b2, b1, b2] })
    }

    /// The attributes of `triangle` interpolated at `barycentrics` into `out` (which must hold
    /// [`IndexedMesh::attributes_per_vertex`] floats). The barycentrics are clamped to the
    /// triangle first, so an edge pixel never extrapolates. Fails when the triangle does not
    /// exist or `out` has the wrong length.
    pub fn interpolate_attributes(
        &self,
        triangle: u32,
        barycentrics: [f64; 3],
        out: &mut [f32],
    ) -> Result<(), MeshError> {
        let k = self.attributes_per_vertex;
        if out.len() != k {
            return Err(MeshError::Attributes(format!(
                "output holds {} values for {k} attributes per vertex",
                out.len()
            )));
        }
        let tri = self.triangles.get(triangle as usize).ok_or_else(|| MeshError::Parameter {
            name: "triangle",
            reason: format!(
                "{triangle} is not one of the mesh's {} triangles",
                self.triangles.len()
            ),
        })?;
        let clamped = barycentrics.map(|b| if b.is_finite() { b.clamp(0.0, 1.0) } else { 0.0 });
        let sum: f64 = clamped.iter().sum();
        let weights = if sum > 0.0 { clamped.map(|b| b / sum) } else { [1.0 / 3.0; 3] };
        for (a, value) in out.iter_mut().enumerate() {
            *value = tri
                .iter()
                .zip(weights)
                .map(|(&v, w)| w * self.attributes[v as usize * k + a] as f64)
                .sum::<f64>() as f32;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> IndexedMesh {
        let p = vec![
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(2.0, 0.0, 1.0),
            DVec3::new(0.0, 2.0, 1.0),
            DVec3::new(2.0, 2.0, 1.0),
        ];
        IndexedMesh::new(p, vec![[0, 1, 2], [1, 3, 2]]).unwrap()
    }

    #[test]
    fn refuses_bad_indices_positions_and_attributes() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        assert!(matches!(
            IndexedMesh::new(p.clone(), vec![[0, 1, 3]]),
            Err(MeshError::IndexOutOfRange { triangle: 0, index: 3, vertex_count: 3 })
        ));
        let bad = vec![DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Y];
        assert!(matches!(
            IndexedMesh::new(bad, vec![]),
            Err(MeshError::NonFinitePosition { index: 1, .. })
        ));
        let mesh = IndexedMesh::new(p, vec![[0, 1, 2]]).unwrap();
        assert!(mesh.clone().with_attributes(2, vec![0.0; 5]).is_err());
        assert!(mesh.clone().with_attributes(1, vec![0.0, f32::NAN, 1.0]).is_err());
        assert!(mesh.with_attributes(2, vec![0.0; 6]).is_ok());
    }

    #[test]
    fn hit_gives_the_plane_distance_a_facing_normal_and_barycentrics() {
        let mesh = square().with_attributes(1, vec![0.0, 1.0, 2.0, 3.0]).unwrap();
        let down = Ray::new(DVec3::new(1.5, 0.25, 5.0), -DVec3::Z);
        let hit = mesh.hit(0, &down).unwrap();
        assert_eq!(hit.t, 4.0);
        assert_eq!(hit.normal, DVec3::Z);
        let [b0, b1, b2] = hit.barycentrics;
        assert!(
            (b0 - 0.125).abs() < 1e-12 && (b1 - 0.75).abs() < 1e-12 && (b2 - 0.125).abs() < 1e-12
        );
        let mut out = [0.0f32];
        mesh.interpolate_attributes(0, hit.barycentrics, &mut out).unwrap();
        assert!((out[0] - (0.75 * 1.0 + 0.125 * 2.0)).abs() < 1e-6);
        // From below the normal turns to face the ray.
        let up = Ray::new(DVec3::new(0.5, 0.5, -1.0), DVec3::Z);
        assert_eq!(mesh.hit(1, &up).unwrap().normal, -DVec3::Z);
        // Parallel rays and missing triangles give nothing.
        assert!(mesh.hit(0, &Ray::new(DVec3::ZERO, DVec3::X)).is_none());
        assert!(mesh.hit(2, &down).is_none());
        assert!(mesh.interpolate_attributes(0, hit.barycentrics, &mut [0.0; 2]).is_err());
    }

    #[test]
    fn append_shifts_indices() {
        let mut a = square();
        a.append(&square()).unwrap();
        assert_eq!(a.vertex_count(), 8);
        assert_eq!(a.triangles()[3], [5, 7, 6]);
        let with = square().with_attributes(1, vec![0.0; 4]).unwrap();
        assert!(a.append(&with).is_err());
        let mut empty = IndexedMesh::default();
        empty.append(&with).unwrap();
        assert_eq!(empty.attributes_per_vertex(), 1);
    }
}
