//! The mesh of the `boxes` solid over a block of texels: flat tops, the vertical faces between
//! texels of different heights, the walls and the bottom, split where faces meet so that every
//! edge is shared whole (no T-junction, hence no crack).

use crate::mesh_builder::MeshBuilder;
use crate::IndexedMesh;
use relief_core::{DVec3, HeightField, SampleRegion};
use std::collections::HashMap;

/// The `boxes` solid of `field` over the texels of `region` (see
/// [`crate::height_field_mesh`]).
///
/// A vertical face lies on a texel edge from corner P to corner Q and spans heights
/// `[lo, hi]`. Its vertical sides are split at every height of the texels around P (and Q)
/// and at the lowest sample that falls inside `[lo, hi]`: every face meeting that vertical
/// line is split at the same heights, so the faces share their vertical edges piece by piece,
/// and their horizontal edges are whole texel edges, as the tops' and the bottom's are.
pub(crate) fn box_mesh(field: &HeightField, region: SampleRegion) -> IndexedMesh {
    let mut boxes = BoxMesher {
        field,
        z_min: field.min_sample() as f64 + 0.0,
        mesh: MeshBuilder::default(),
        vertices: HashMap::new(),
    };
    if region.is_empty() {
        return boxes.mesh.finish();
    }
    let mut any_hole = false;
    for row in region.row0..region.row1 {
        for col in region.col0..region.col1 {
            let Some(top) = boxes.height(col as isize, row as isize) else {
                any_hole = true;
                continue;
            };
            let corner = |dx: usize, dy: usize| [col + dx, row + dy];
            let [c00, c10, c11, c01] = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            let v = |b: &mut BoxMesher, c: [usize; 2]| b.vertex(c, top);
            let (a, b, c, d) =
                (v(&mut boxes, c00), v(&mut boxes, c10), v(&mut boxes, c11), v(&mut boxes, c01));
            boxes.mesh.quad(a, b, c, d);
            // The faces this texel owns: where its neighbour is lower, missing or a hole.
            let sides =
                [((0, -1), c00, c10), ((1, 0), c10, c11), ((0, 1), c11, c01), ((-1, 0), c01, c00)];
            for ((dx, dy), p, q) in sides {
                let below =
                    boxes.height(col as isize + dx, row as isize + dy).unwrap_or(boxes.z_min);
                if top > below {
                    boxes.face(p, q, below, top);
                }
            }
        }
    }
    boxes.bottom(region, any_hole);
    boxes.mesh.finish()
}

/// The state of meshing one block.
struct BoxMesher<'a> {
    field: &'a HeightField,
    z_min: f64,
    mesh: MeshBuilder,
    /// Vertex of each (corner column, corner row, height bits) made so far.
    vertices: HashMap<(usize, usize, u64), u32>,
}

impl BoxMesher<'_> {
    /// Height of texel (col, row), `None` outside the grid or over a hole.
    fn height(&self, col: isize, row: isize) -> Option<f64> {
        let (w, h) = (self.field.width() as isize, self.field.height() as isize);
        if col < 0 || row < 0 || col >= w || row >= h {
            return None;
        }
        let (col, row) = (col as usize, row as usize);
        // `+ 0.0` turns a negative zero into zero: one vertex per point.
        (!self.field.is_hole(col, row)).then(|| self.field.sample(col, row) as f64 + 0.0)
    }

    /// The vertex at grid corner `c` and height `z`.
    fn vertex(&mut self, [x, y]: [usize; 2], z: f64) -> u32 {
        let geometry = self.field.geometry();
        let mesh = &mut self.mesh;
        *self.vertices.entry((x, y, z.to_bits())).or_insert_with(|| {
            mesh.vertex(geometry.point_to_world(DVec3::new(x as f64, y as f64, z)))
        })
    }

    /// The heights at which faces meeting on the vertical line of corner `c` are split: the
    /// texels around it and the lowest sample, sorted.
    fn breaks(&self, [x, y]: [usize; 2]) -> Vec<f64> {
        let (x, y) = (x as isize, y as isize);
        let mut heights: Vec<f64> = [(x - 1, y - 1), (x, y - 1), (x - 1, y), (x, y)]
            .iter()
            .filter_map(|&(c, r)| self.height(c, r))
            .chain([self.z_min])
            .collect();
        heights.sort_by(f64::total_cmp);
        heights.dedup();
        heights
    }

    /// The vertical face on the texel edge from corner `p` to `q` over heights `[lo, hi]`,
    /// its sides split at the corners' breaks, triangulated as a zigzag between them.
    fn face(&mut self, p: [usize; 2], q: [usize; 2], lo: f64, hi: f64) {
        let heights = |b: &Self, c: [usize; 2]| -> Vec<f64> {
            let mut zs: Vec<f64> =
                b.breaks(c).into_iter().filter(|&z| z > lo && z < hi).chain([lo, hi]).collect();
            zs.sort_by(f64::total_cmp);
            zs
        };
        let (left_z, right_z) = (heights(self, p), heights(self, q));
        let left: Vec<u32> = left_z.iter().map(|&z| self.vertex(p, z)).collect();
        let right: Vec<u32> = right_z.iter().map(|&z| self.vertex(q, z)).collect();
        let (mut i, mut j) = (0, 0);
        while i + 1 < left.len() || j + 1 < right.len() {
            let step_right =
                j + 1 < right.len() && (i + 1 == left.len() || right_z[j + 1] <= left_z[i + 1]);
            if step_right {
                self.mesh.triangle(left[i], right[j], right[j + 1]);
                j += 1;
            } else {
                self.mesh.triangle(left[i], right[j], left[i + 1]);
                i += 1;
            }
        }
    }

    /// The bottom at the lowest sample: without holes a fan from the block's centre to its
    /// border's corners, else a quad under every texel (also under a texel at the lowest
    /// sample, whose top it doubles: the solid is then a closed surface of zero thickness
    /// there, crossed twice by a ray, as everywhere else).
    fn bottom(&mut self, region: SampleRegion, any_hole: bool) {
        let z = self.z_min;
        let (c0, r0, c1, r1) = (region.col0, region.row0, region.col1, region.row1);
        if any_hole {
            for row in r0..r1 {
                for col in c0..c1 {
                    if self.height(col as isize, row as isize).is_some() {
                        let a = self.vertex([col, row], z);
                        let b = self.vertex([col + 1, row], z);
                        let c = self.vertex([col + 1, row + 1], z);
                        let d = self.vertex([col, row + 1], z);
                        self.mesh.quad(d, c, b, a);
                    }
                }
            }
            return;
        }
        let centre = self.field.geometry().point_to_world(DVec3::new(
            (c0 + c1) as f64 / 2.0,
            (r0 + r1) as f64 / 2.0,
            z,
        ));
        let centre = self.mesh.vertex(centre);
        let mut ring = Vec::with_capacity(2 * (c1 - c0 + r1 - r0));
        ring.extend((c0..c1).map(|x| [x, r0]));
        ring.extend((r0..r1).map(|y| [c1, y]));
        ring.extend((c0 + 1..=c1).rev().map(|x| [x, r1]));
        ring.extend((r0 + 1..=r1).rev().map(|y| [c0, y]));
        let ring: Vec<u32> = ring.into_iter().map(|c| self.vertex(c, z)).collect();
        for k in 0..ring.len() {
            self.mesh.triangle(centre, ring[(k + 1) % ring.len()], ring[k]);
        }
    }
}
