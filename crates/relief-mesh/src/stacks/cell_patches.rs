//! The surface patches of one dual-contouring cell: which of its 12 edges the iso-surface
//! crosses and how the crossings join into patches ([`CellPatches`]), one vertex each.
//!
//! Plain dual contouring gives a cell one vertex; a cell whose face has the iso-surface
//! crossing all four of its edges (a saddle) then makes the mesh edge across that face shared
//! by four quads. Here a cell gets one vertex per patch of its surface: on each face the
//! crossings are paired, a saddle face by the asymptotic decider (the bilinear interpolant's
//! value at its saddle point), which depends on the face's four values alone, so both cells
//! that share the face pair it alike; the patches are the cycles those pairings make. Every
//! mesh edge then borders exactly two faces.

/// Edge `e` of a cell runs along axis `e / 4` from the corner with that axis' bit clear and
/// the other two axes' bits `e % 4` (lower axis in bit 0) to the corner with it set.
pub(crate) fn edge_corners(e: usize) -> (usize, usize) {
    let axis = e / 4;
    let (t0, t1) = other_axes(axis);
    let base = ((e & 1) << t0) | (((e >> 1) & 1) << t1);
    (base, base | (1 << axis))
}

/// The two axes other than `axis`, in increasing order.
#[inline]
pub(crate) fn other_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The index of the cell edge along `axis` whose lower corner has the bits `offset` (one per
/// axis, the bit of `axis` itself ignored).
#[inline]
pub(crate) fn edge_index(axis: usize, offset: [i32; 3]) -> usize {
    let (t0, t1) = other_axes(axis);
    axis * 4 + offset[t0] as usize + 2 * offset[t1] as usize
}

/// Which patch each crossed edge of a cell belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct CellPatches {
    /// Patch of each edge, or [`CellPatches::NONE`] where the surface does not cross it.
    pub of_edge: [u8; 12],
    /// Number of patches.
    pub count: u8,
}

impl CellPatches {
    /// Marks an edge the surface does not cross.
    pub const NONE: u8 = u8::MAX;

    /// The patches of a cell whose corner `c` (x in bit 0, y in bit 1, z in bit 2) has value
    /// `values[c]`; a corner is inside where its value exceeds `iso`.
    pub fn new(values: &[f32; 8], iso: f32) -> Self {
        let inside = |c: usize| values[c] > iso;
        let mut parent: [u8; 12] = std::array::from_fn(|e| e as u8);
        let crossed: [bool; 12] = std::array::from_fn(|e| {
            let (a, b) = edge_corners(e);
            inside(a) != inside(b)
        });
        for axis in 0..3 {
            let (b, c) = other_axes(axis);
            for side in 0..2 {
                // The face's corners in cyclic order in the (b, c) plane, and the edge from
                // each to the next.
                let corner = |u: usize, v: usize| (side << axis) | (u << b) | (v << c);
                let corners = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                let edges = [
                    edge_index(b, offset_of(corners[0])),
                    edge_index(c, offset_of(corners[1])),
                    edge_index(b, offset_of(corners[3])),
                    edge_index(c, offset_of(corners[0])),
                ];
                let crossing: Vec<usize> = (0..4).filter(|&k| crossed[edges[k]]).collect();
                match crossing.len() {
                    2 => union(&mut parent, edges[crossing[0]], edges[crossing[1]]),
                    4 => {
                        let saddle = face_saddle(corners.map(|c| values[c]));
                        // The corners on the saddle's side are joined across the face; the
                        // others are cut off, each by the pair of edges that meet at it.
                        let cut_first = (saddle > iso) != inside(corners[0]);
                        if cut_first {
                            union(&mut parent, edges[3], edges[0]);
                            union(&mut parent, edges[1], edges[2]);
                        } else {
                            union(&mut parent, edges[0], edges[1]);
                            union(&mut parent, edges[2], edges[3]);
                        }
                    }
                    _ => {}
                }
            }
        }
        let mut of_edge = [Self::NONE; 12];
        let mut roots = [Self::NONE; 12];
        let mut count = 0u8;
        for e in 0..12 {
            if crossed[e] {
                let root = find(&mut parent, e) as usize;
                if roots[root] == Self::NONE {
                    roots[root] = count;
                    count += 1;
                }
                of_edge[e] = roots[root];
            }
        }
        CellPatches { of_edge, count }
    }
}

/// The value at the saddle point of the bilinear interpolant of a face's four values `v`, in
/// cyclic order around the face. Computed from the two diagonals, each sorted, so that every
/// cell and quad that looks at the face, in whatever order, gets the same bits.
pub(crate) fn face_saddle(v: [f32; 4]) -> f32 {
    let sorted = |a: f32, b: f32| if a <= b { (a, b) } else { (b, a) };
    let (mut d, mut e) = (sorted(v[0], v[2]), sorted(v[1], v[3]));
    if (e.0, e.1) < (d.0, d.1) {
        std::mem::swap(&mut d, &mut e);
    }
    (d.0 * d.1 - e.0 * e.1) / ((d.0 + d.1) - (e.0 + e.1))
}

/// The corner bits of corner `c` as offsets.
#[inline]
fn offset_of(c: usize) -> [i32; 3] {
    [(c & 1) as i32, ((c >> 1) & 1) as i32, ((c >> 2) & 1) as i32]
}

fn find(parent: &mut [u8; 12], e: usize) -> u8 {
    let mut r = e as u8;
    while parent[r as usize] != r {
        r = parent[r as usize];
    }
    parent[e] = r;
    r
}

fn union(parent: &mut [u8; 12], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_run_between_the_corners_they_name() {
        for e in 0..12 {
            let (a, b) = edge_corners(e);
            assert_eq!((a ^ b).count_ones(), 1);
            assert_eq!(a ^ b, 1 << (e / 4));
            assert_eq!(edge_index(e / 4, offset_of(a)), e);
        }
    }

    #[test]
    fn one_inside_corner_makes_one_patch_of_three_edges() {
        let mut v = [0.0f32; 8];
        v[5] = 1.0;
        let p = CellPatches::new(&v, 0.5);
        assert_eq!(p.count, 1);
        assert_eq!(p.of_edge.iter().filter(|&&x| x == 0).count(), 3);
    }

    #[test]
    fn two_opposite_corners_make_two_patches_unless_the_saddle_joins_them() {
        // Corners 0 and 3 (a face diagonal) inside.
        let mut v = [0.0f32; 8];
        v[0] = 1.0;
        v[3] = 1.0;
        assert_eq!(CellPatches::new(&v, 0.5).count, 2, "a low saddle separates them");
        v[1] = 0.9;
        v[2] = 0.9;
        // Now 1 and 2 are inside too: a single patch.
        assert_eq!(CellPatches::new(&v, 0.5).count, 1);
        v[1] = 0.45;
        v[2] = 0.45;
        // Saddle value (1 - 0.2025) / (2 - 0.9) = 0.725 > 0.5: the inside corners join.
        assert_eq!(CellPatches::new(&v, 0.5).count, 1);
    }
}
