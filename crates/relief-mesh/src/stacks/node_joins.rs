//! Node meshes joined into one: for export, each vertex once (by key), as a [`MeshPart`]; for
//! drawing, appended as they are into an [`IndexedMesh`] with colour and normal attributes.

use super::node_mesh::NodeMesh;
use crate::terrain_mesh::split_quad;
use crate::{IndexedMesh, MeshError, MeshPart};
use rayon::prelude::*;
use relief_core::DVec3;
use std::sync::Arc;

/// Part `p` of the nodes' meshes joined into `part`, each vertex once (by key; a vertex only
/// one node makes needs no lookup).
pub(crate) fn join_part(meshes: &[&NodeMesh], p: usize, mut part: MeshPart) -> MeshPart {
    let vertices: usize = meshes.iter().map(|m| m.parts[p].keys.len()).sum();
    let quads: usize = meshes.iter().map(|m| m.parts[p].quads.len()).sum();
    let mut index = rustc_hash::FxHashMap::<u128, u32>::default();
    index.reserve(vertices / 2);
    part.positions.reserve(vertices);
    part.normals.reserve(vertices);
    part.colors.reserve(vertices);
    part.quads.reserve(quads);
    for mesh in meshes {
        let node_part = &mesh.parts[p];
        let map: Vec<u32> = node_part
            .keys
            .iter()
            .enumerate()
            .map(|(v, key)| {
                let mut push = || {
                    part.positions.push(node_part.positions[v]);
                    part.normals.push(node_part.normals[v]);
                    part.colors.push(node_part.colors[v]);
                    (part.positions.len() - 1) as u32
                };
                if node_part.shared[v] {
                    *index.entry(*key).or_insert_with(push)
                } else {
                    push()
                }
            })
            .collect();
        part.quads.extend(node_part.quads.iter().map(|q| q.map(|v| map[v as usize])));
        part.triangles.extend(node_part.triangles.iter().map(|t| t.map(|v| map[v as usize])));
    }
    part
}

/// Part `part` of every node's mesh appended into one triangle mesh with colour and normal
/// attributes, the nodes filled in parallel at offsets from prefix sums.
pub(crate) fn append_for_drawing(
    meshes: &[Arc<NodeMesh>],
    part: usize,
) -> Result<IndexedMesh, MeshError> {
    let mut vertex_at = Vec::with_capacity(meshes.len() + 1);
    let (mut v, mut t) = (0usize, 0usize);
    for m in meshes {
        vertex_at.push(v);
        let p = &m.parts[part];
        v += p.positions.len();
        t += 2 * p.quads.len() + p.triangles.len();
    }
    let mut positions = vec![DVec3::ZERO; v];
    let mut triangles = vec![[0u32; 3]; t];
    let mut attributes = vec![0f32; 6 * v];
    // Split the outputs into each node's share, then fill the shares in parallel.
    let mut shares = Vec::with_capacity(meshes.len());
    let (mut pos_rest, mut tri_rest, mut att_rest) =
        (positions.as_mut_slice(), triangles.as_mut_slice(), attributes.as_mut_slice());
    for (k, m) in meshes.iter().enumerate() {
        let p = &m.parts[part];
        let (pos, r1) = std::mem::take(&mut pos_rest).split_at_mut(p.positions.len());
        let (tri, r2) =
            std::mem::take(&mut tri_rest).split_at_mut(2 * p.quads.len() + p.triangles.len());
        let (att, r3) = std::mem::take(&mut att_rest).split_at_mut(6 * p.positions.len());
        (pos_rest, tri_rest, att_rest) = (r1, r2, r3);
        shares.push((p, vertex_at[k] as u32, pos, tri, att));
    }
    shares.into_par_iter().for_each(|(p, base, pos, tri, att)| {
        pos.copy_from_slice(&p.positions);
        for (k, (c, n)) in p.colors.iter().zip(&p.normals).enumerate() {
            att[6 * k..6 * k + 3].copy_from_slice(c);
            att[6 * k + 3..6 * k + 6].copy_from_slice(n);
        }
        let mut out = 0;
        for q in &p.quads {
            // Split as the exported mesh is.
            let [first, second] = split_quad(*q, |v| p.positions[v as usize]);
            tri[out] = first.map(|i| i + base);
            tri[out + 1] = second.map(|i| i + base);
            out += 2;
        }
        for tr in &p.triangles {
            tri[out] = tr.map(|i| i + base);
            out += 1;
        }
    });
    IndexedMesh::new(positions, triangles)?.with_attributes(6, attributes)
}
