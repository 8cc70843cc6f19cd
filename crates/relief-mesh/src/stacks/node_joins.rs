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

/// Part `part` of every node's mesh appended into `out`, one triangle mesh with colour and
/// normal attributes (its buffers reused: a frame's meshes are about the last frame's size),
/// the nodes filled and checked in parallel at offsets from prefix sums. Fails on a position
/// or attribute that is not finite or an index out of its node's range, as
/// [`IndexedMesh::new`] and [`IndexedMesh::with_attributes`] would.
pub(crate) fn append_for_drawing(
    meshes: &[Arc<NodeMesh>],
    part: usize,
    out: &mut IndexedMesh,
) -> Result<(), MeshError> {
    let mut vertex_at = Vec::with_capacity(meshes.len() + 1);
    let (mut v, mut t) = (0usize, 0usize);
    for m in meshes {
        vertex_at.push(v);
        let p = &m.parts[part];
        v += p.positions.len();
        t += 2 * p.quads.len() + p.triangles.len();
    }
    if v > u32::MAX as usize || t >= u32::MAX as usize {
        return Err(MeshError::Limits(format!(
            "{v} vertices and {t} triangles exceed the u32 ids"
        )));
    }
    // Stale values left by the last frame are all overwritten below.
    out.positions.resize(v, DVec3::ZERO);
    out.triangles.resize(t, [0; 3]);
    out.attributes.resize(6 * v, 0.0);
    out.attributes_per_vertex = 6;
    // Split the outputs into each node's share, then fill the shares in parallel.
    let mut shares = Vec::with_capacity(meshes.len());
    let (mut pos_rest, mut tri_rest, mut att_rest) =
        (out.positions.as_mut_slice(), out.triangles.as_mut_slice(), out.attributes.as_mut_slice());
    for (k, m) in meshes.iter().enumerate() {
        let p = &m.parts[part];
        let (pos, r1) = std::mem::take(&mut pos_rest).split_at_mut(p.positions.len());
        let (tri, r2) =
            std::mem::take(&mut tri_rest).split_at_mut(2 * p.quads.len() + p.triangles.len());
        let (att, r3) = std::mem::take(&mut att_rest).split_at_mut(6 * p.positions.len());
        (pos_rest, tri_rest, att_rest) = (r1, r2, r3);
        shares.push((p, vertex_at[k], pos, tri, att));
    }
    shares.into_par_iter().try_for_each(|(p, first, pos, tri, att)| {
        let count = p.positions.len();
        if let Some((k, q)) = p.positions.iter().enumerate().find(|(_, q)| !q.is_finite()) {
            return Err(MeshError::NonFinitePosition { index: first + k, x: q.x, y: q.y, z: q.z });
        }
        pos.copy_from_slice(&p.positions);
        for (k, (c, n)) in p.colors.iter().zip(&p.normals).enumerate() {
            if let Some(value) = c.iter().chain(n).find(|v| !v.is_finite()) {
                return Err(MeshError::Attributes(format!(
                    "value {value} of vertex {} is not finite",
                    first + k
                )));
            }
            att[6 * k..6 * k + 3].copy_from_slice(c);
            att[6 * k + 3..6 * k + 6].copy_from_slice(n);
        }
        let mut faces = p.quads.iter().flatten().chain(p.triangles.iter().flatten());
        if let Some(&index) = faces.find(|&&v| v as usize >= count) {
            return Err(MeshError::Limits(format!(
                "a node's face uses vertex {index} of its {count}"
            )));
        }
        let base = first as u32;
        let mut at = 0;
        for q in &p.quads {
            // Split as the exported mesh is.
            let [one, two] = split_quad(*q, |v| p.positions[v as usize]);
            tri[at] = one.map(|i| i + base);
            tri[at + 1] = two.map(|i| i + base);
            at += 2;
        }
        for tr in &p.triangles {
            tri[at] = tr.map(|i| i + base);
            at += 1;
        }
        Ok(())
    })
}
