//! What a closed mesh part holds: the volume it encloses and its connected pieces, the
//! measures by which a stacks mesh is checked against its stacks.

use crate::MeshPart;
use relief_core::DVec3;

/// One connected piece of a [`MeshPart`]: faces joined through shared vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Component {
    /// Number of faces (quads and triangles).
    pub faces: usize,
    /// The smallest corner of the piece's box, world coordinates.
    pub min: DVec3,
    /// The largest corner of the piece's box, world coordinates.
    pub max: DVec3,
    /// The volume the piece encloses, cubic metres (see [`MeshPart::enclosed_volume`]).
    pub volume: f64,
}

impl Component {
    /// Whether this piece's box and `other`'s, each grown by `margin` metres, overlap.
    pub fn overlaps(&self, other: &Component, margin: f64) -> bool {
        (0..3).all(|a| {
            self.min[a] - margin <= other.max[a] + margin
                && other.min[a] - margin <= self.max[a] + margin
        })
    }
}

impl MeshPart {
    /// The volume the part encloses, cubic metres: the divergence theorem over its faces,
    /// which are wound counter-clockwise seen from outside. Meaningful for a closed part.
    pub fn enclosed_volume(&self) -> f64 {
        self.triangulated().iter().map(|t| self.signed_volume(t)).sum()
    }

    /// The part's connected pieces (faces that share a vertex belong together), largest
    /// first, then by position.
    pub fn components(&self) -> Vec<Component> {
        let mut parent: Vec<u32> = (0..self.positions.len() as u32).collect();
        let faces: Vec<&[u32]> = self
            .quads
            .iter()
            .map(|q| q.as_slice())
            .chain(self.triangles.iter().map(|t| t.as_slice()))
            .collect();
        for face in &faces {
            for pair in face.windows(2) {
                union(&mut parent, pair[0], pair[1]);
            }
        }
        let mut index_of_root = vec![usize::MAX; parent.len()];
        let mut pieces: Vec<Component> = Vec::new();
        let mut piece_of = |root: u32, pieces: &mut Vec<Component>| {
            if index_of_root[root as usize] == usize::MAX {
                index_of_root[root as usize] = pieces.len();
                pieces.push(Component {
                    faces: 0,
                    min: DVec3::splat(f64::INFINITY),
                    max: DVec3::splat(f64::NEG_INFINITY),
                    volume: 0.0,
                });
            }
            index_of_root[root as usize]
        };
        let triangles = self.triangulated();
        for face in &faces {
            let piece = piece_of(find(&mut parent, face[0]), &mut pieces);
            let c = &mut pieces[piece];
            c.faces += 1;
            for &v in face.iter() {
                let p = self.positions[v as usize];
                c.min = c.min.min(p);
                c.max = c.max.max(p);
            }
        }
        for t in &triangles {
            let piece = piece_of(find(&mut parent, t[0]), &mut pieces);
            pieces[piece].volume += self.signed_volume(t);
        }
        pieces.sort_by(|a, b| {
            b.faces.cmp(&a.faces).then(a.min.to_array().partial_cmp(&b.min.to_array()).unwrap())
        });
        pieces
    }

    /// The signed volume of the tetrahedron of triangle `t` and the origin.
    fn signed_volume(&self, t: &[u32; 3]) -> f64 {
        let [a, b, c] = t.map(|v| self.positions[v as usize]);
        a.dot(b.cross(c)) / 6.0
    }
}

/// The root of `v`'s set, halving the path on the way.
fn find(parent: &mut [u32], mut v: u32) -> u32 {
    while parent[v as usize] != v {
        parent[v as usize] = parent[parent[v as usize] as usize];
        v = parent[v as usize];
    }
    v
}

/// Joins the sets of `a` and `b` (the smaller root under the larger, so the result does not
/// depend on the order of the calls).
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (low, high) = (ra.min(rb), ra.max(rb));
        parent[high as usize] = low;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's six quads, wound outwards, shifted by `at`.
    fn cube(part: &mut MeshPart, at: DVec3, size: f64) {
        let base = part.positions.len() as u32;
        for k in 0..8 {
            let corner = DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64);
            part.positions.push(at + corner * size);
        }
        for q in
            [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
        {
            part.quads.push(q.map(|v| base + v));
        }
    }

    #[test]
    fn two_cubes_are_two_pieces_with_their_volumes() {
        let mut part = MeshPart::new("solid", [1.0; 4]);
        cube(&mut part, DVec3::ZERO, 2.0);
        cube(&mut part, DVec3::new(5.0, 0.0, 0.0), 1.0);
        assert!((part.enclosed_volume() - 9.0).abs() < 1e-12);
        let pieces = part.components();
        assert_eq!(pieces.len(), 2);
        assert!((pieces[0].volume - 8.0).abs() < 1e-12 && (pieces[1].volume - 1.0).abs() < 1e-12);
        assert_eq!(pieces[1].min, DVec3::new(5.0, 0.0, 0.0));
        assert!(!pieces[0].overlaps(&pieces[1], 1.0) && pieces[0].overlaps(&pieces[1], 1.5));
    }
}
