//! The quadrangulation of one octree node (sections 3.2.3 to 3.2.5 and 3.4): its density with
//! the finer side's border fitted to a coarser neighbour, the classification of its edges, the
//! allocation of faces by prefix sums, the vertices (numbered on first use) and the faces.
//!
//! Stitching. A node meshes the cells `[o - 1, o + n)` of its level along each axis (one cell
//! of overlap) and makes the faces of the lattice edges that start at its own points
//! `[o, o + n)`; the density extends by the filter's half-width, so a cell shared by two nodes
//! gets the same vertex in both (section 3.4.1). Where a neighbour is one level coarser, the
//! lattice points within two points of it take the coarser level's value at `floor(p / 2)`
//! (topology fitting), and a cell all of whose corners are fitted takes the vertex of the
//! coarser cell `floor(c / 2)` (T-junction removal: the finer border meshes as the coarser
//! level does and shares its vertices; faces that collapse are dropped or become triangles).
//! Every vertex is named by a key (level, cell, patch), so nodes' meshes join by key.
//!
//! Saddles. A lattice face whose four edges the surface crosses holds two separate crossings;
//! where two cells' single patches both span such a face, plain dual contouring would join
//! them by one mesh edge shared by four faces. Each crossing gets a vertex on the face, named by
//! the face and the corner it cuts off, and a quad with one is drawn as a fan around its
//! edge's crossing: every mesh edge then borders exactly two faces.

use super::fitted_field::Field;
use super::lattice::Block;
use super::node_mesh::{LevelField, NodeJob, NodeMesh, NodePart, ISO};
use super::vertex_table::{Resolved, VertexTable};

/// Meshes one node.
pub(crate) fn mesh_node(job: &NodeJob, fine: &LevelField, coarse: Option<&LevelField>) -> NodeMesh {
    let field = Field::fitted_to(job, fine, coarse);
    let mut mesh = NodeMesh::default();
    for (part, channel) in [(0, 0), (1, 1)] {
        mesh.parts[part] = mesh_part(job, &field, channel);
    }
    mesh
}

/// Contours `channel` of the field over the node: the vertices of its cells and the faces of
/// its edges.
fn mesh_part(job: &NodeJob, field: &Field, channel: usize) -> NodePart {
    let o = job.origin;
    let n = job.n;
    // Quick out: no crossing among the node's points and its ring.
    let region = Block::between(o.map(|c| c - 1), o.map(|c| c + n + 1));
    let mut any_in = false;
    let mut any_out = false;
    for i in 0..region.len() {
        if field.at(channel, region.point(i)) > ISO {
            any_in = true;
        } else {
            any_out = true;
        }
        if any_in && any_out {
            break;
        }
    }
    let mut part = NodePart::default();
    if !(any_in && any_out) {
        return part;
    }

    // Classification and allocation: the faces each own point makes (one per crossed edge
    // starting there), their offsets by an exclusive prefix sum.
    let own = Block::between(o, o.map(|c| c + n));
    let mut face_count = vec![0u8; own.len()];
    for (i, count) in face_count.iter_mut().enumerate() {
        let p = own.point(i);
        let inside = field.at(channel, p) > ISO;
        for axis in 0..3 {
            let mut q = p;
            q[axis] += 1;
            if (field.at(channel, q) > ISO) != inside {
                *count += 1;
            }
        }
    }
    let mut face_offset = Vec::with_capacity(own.len() + 1);
    let mut total = 0u32;
    face_offset.push(0);
    for &c in &face_count {
        total += c as u32;
        face_offset.push(total);
    }

    // Vertices: allocated on first use, one per (resolved cell, patch).
    let mut vertices = VertexTable::new(job, field, channel);
    let mut faces: Vec<[u32; 4]> = vec![[0; 4]; total as usize];
    let mut fans: Vec<[u32; 3]> = Vec::new();
    for (i, &count) in face_count.iter().enumerate() {
        if count == 0 {
            continue;
        }
        let p = own.point(i);
        let inside = field.at(channel, p) > ISO;
        let mut slot = face_offset[i] as usize;
        for axis in 0..3 {
            let mut q = p;
            q[axis] += 1;
            if (field.at(channel, q) > ISO) == inside {
                continue;
            }
            let (b, c) = match axis {
                0 => (1, 2),
                1 => (2, 0),
                _ => (0, 1),
            };
            // The four cells around the edge, counter-clockwise seen from +axis, and the
            // direction from the edge into the lattice face between each and the next.
            let offsets = [(-1, -1), (0, -1), (0, 0), (-1, 0)];
            let mut towards = [[0i32; 3]; 4];
            (towards[0][c], towards[1][b], towards[2][c], towards[3][b]) = (-1, 1, 1, -1);
            let resolved: [Resolved; 4] = std::array::from_fn(|k| {
                let mut cell = p;
                cell[b] += offsets[k].0;
                cell[c] += offsets[k].1;
                vertices.resolve(cell, p)
            });
            let quad: [u32; 4] = std::array::from_fn(|k| vertices.patch_vertex(resolved[k], axis));
            // A lattice face the surface crosses on all four edges (a saddle) holds two
            // separate crossings; their mesh edges get a vertex each on the face, so that
            // two cells whose single patches both span the face do not share one edge four
            // times.
            let mut polygon = Vec::with_capacity(8);
            let mut saddles = false;
            if !collapses(&quad) {
                for k in 0..4 {
                    let (from, to) = (resolved[k], resolved[(k + 1) % 4]);
                    if quad[k] == quad[(k + 1) % 4] {
                        continue;
                    }
                    polygon.push(quad[k]);
                    // Both cells on one grid: the face between them there; a fine cell next
                    // to a coarser one: the fine face.
                    let (on_coarse, edge) =
                        if from.snapped && to.snapped { (true, from.edge) } else { (false, p) };
                    if let Some(v) = vertices.saddle_vertex(on_coarse, edge, axis, towards[k]) {
                        polygon.push(v);
                        saddles = true;
                    }
                }
            }
            if !saddles {
                // No saddle face: the quad, or what stitching collapsed it to.
                polygon = quad.to_vec();
            }
            if !inside {
                polygon.reverse();
            }
            if !saddles {
                faces[slot] = [polygon[0], polygon[1], polygon[2], polygon[3]];
            } else {
                // A fan around the edge's own crossing.
                let snapped = resolved.iter().all(|r| r.snapped);
                let centre =
                    vertices.edge_vertex(snapped, if snapped { resolved[0].edge } else { p }, axis);
                for k in 0..polygon.len() {
                    let (u, w) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                    if u != w {
                        fans.push([centre, u, w]);
                    }
                }
                faces[slot] = [u32::MAX; 4];
            }
            slot += 1;
        }
    }
    let NodePart { keys, shared, positions, normals, colors, .. } = vertices.part;
    part.keys = keys;
    part.shared = shared;
    part.positions = positions;
    part.normals = normals;
    part.colors = colors;
    for quad in faces.into_iter().filter(|q| q[0] != u32::MAX) {
        push_face(&mut part, quad);
    }
    part.triangles.extend(fans);
    part
}

/// Whether a quad whose corners stitching may have merged has collapsed to a segment or a
/// point (fewer than three corners left, or two opposite corners merged).
fn collapses(quad: &[u32; 4]) -> bool {
    let distinct: Vec<u32> =
        (0..4).filter(|&k| quad[k] != quad[(k + 1) % 4]).map(|k| quad[k]).collect();
    distinct.len() < 3 || (distinct.len() == 3 && distinct[0] == distinct[2])
}

/// Adds a quad, or the triangle it collapsed to, or nothing when it collapsed further.
fn push_face(part: &mut NodePart, quad: [u32; 4]) {
    let mut distinct: Vec<u32> = Vec::with_capacity(4);
    for k in 0..4 {
        if quad[k] != quad[(k + 1) % 4] {
            distinct.push(quad[k]);
        }
    }
    match distinct.len() {
        4 => part.quads.push(quad),
        3 if distinct[0] != distinct[2] => {
            part.triangles.push([distinct[0], distinct[1], distinct[2]])
        }
        _ => {}
    }
}
