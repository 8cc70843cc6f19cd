//! Binary PLY (`.ply`) export: every non-empty part's vertices and faces concatenated, quads
//! kept as quads when every face is a quad, else every face a triangle (the quads split along
//! their shorter diagonal): readers such as trimesh need one length for every face list.
//!
//! The header is `format binary_little_endian 1.0` with `element vertex` (`float x y z`,
//! `float nx ny nz`, `uchar red green blue`) and `element face` (`list uchar int
//! vertex_indices`, 4 for a quad and 3 for a triangle, wound counter-clockwise seen from
//! outside). PLY has no parts: a `comment part NAME vertices A..B faces C..D` line per part
//! gives its half-open ranges of vertices and faces. Coordinates are relief's world as they
//! are (right-handed, **z up**, metres) in f32, about 7 significant digits, so georeferenced
//! coordinates lose precision (the `.glb` export keeps it); colours are sRGB-encoded to 8
//! bits, normals unit length.

use super::{exported_parts, one_word_name, srgb_encode_u8, unit_normal};
use crate::{MeshError, MeshPart, TerrainMesh};

/// `mesh` as the bytes of a binary PLY file (see the module docs of [`crate::export`] for
/// what is checked).
pub fn to_ply_bytes(mesh: &TerrainMesh) -> Result<Vec<u8>, MeshError> {
    let parts = exported_parts(mesh)?;
    let vertices: usize = parts.iter().map(|p| p.vertex_count()).sum();
    let all_quads = parts.iter().all(|p| p.triangles.is_empty());
    let faces_of = |p: &MeshPart| -> Vec<Vec<u32>> {
        if all_quads {
            p.quads.iter().map(|q| q.to_vec()).collect()
        } else {
            p.triangulated().into_iter().map(|t| t.to_vec()).collect()
        }
    };
    let part_faces: Vec<Vec<Vec<u32>>> = parts.iter().map(|p| faces_of(p)).collect();
    let faces: usize = part_faces.iter().map(Vec::len).sum();
    // PLY's indices here are `int`.
    if vertices > i32::MAX as usize + 1 {
        return Err(MeshError::Limits(format!(
            "{vertices} vertices; a PLY with int indices holds at most 2^31"
        )));
    }
    let mut header = String::from("ply\nformat binary_little_endian 1.0\n");
    header.push_str("comment relief terrain mesh: right-handed, z up, metres; colours sRGB\n");
    let (mut first_vertex, mut first_face) = (0, 0);
    for (index, part) in parts.iter().enumerate() {
        let (v, f) = (part.vertex_count(), part_faces[index].len());
        header.push_str(&format!(
            "comment part {} vertices {first_vertex}..{} faces {first_face}..{}\n",
            one_word_name(&part.name, index),
            first_vertex + v,
            first_face + f
        ));
        first_vertex += v;
        first_face += f;
    }
    header.push_str(&format!("element vertex {vertices}\n"));
    for property in ["x", "y", "z", "nx", "ny", "nz"] {
        header.push_str(&format!("property float {property}\n"));
    }
    for property in ["red", "green", "blue"] {
        header.push_str(&format!("property uchar {property}\n"));
    }
    header.push_str(&format!("element face {faces}\nproperty list uchar int vertex_indices\n"));
    header.push_str("end_header\n");

    let mut out = header.into_bytes();
    out.reserve(vertices * 27 + faces * 17);
    for part in &parts {
        for (vertex, ((p, &n), c)) in
            part.positions.iter().zip(&part.normals).zip(&part.colors).enumerate()
        {
            let position = p.to_array().map(|v| v as f32);
            if position.iter().any(|v| !v.is_finite()) {
                return Err(MeshError::Limits(format!(
                    "part {:?}: vertex {vertex} at {p} is out of the range of PLY's f32 \
                     positions",
                    part.name
                )));
            }
            let normal = unit_normal(n).map(|v| v as f32);
            for v in position.iter().chain(&normal) {
                out.extend_from_slice(&v.to_le_bytes());
            }
            out.extend(c.map(srgb_encode_u8));
        }
    }
    let mut offset: u32 = 0;
    for (part, faces) in parts.iter().zip(&part_faces) {
        for face in faces {
            out.push(face.len() as u8);
            for &v in face {
                // In range: the vertices were counted above.
                out.extend_from_slice(&(offset + v).to_le_bytes());
            }
        }
        offset += part.vertex_count() as u32;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::test_meshes::two_cubes;
    use super::*;

    #[test]
    fn ply_header_and_binary_body_agree() {
        let mut mesh = two_cubes();
        let quads = to_ply_bytes(&mesh).unwrap();
        let end = quads.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        assert_eq!(quads.len() - end, 16 * 27 + 12 * 17, "twelve quads");
        // One triangle among quads: every face a triangle.
        mesh.parts[1].triangles.push([0, 1, 2]);
        let bytes = to_ply_bytes(&mesh).unwrap();
        let end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let header = std::str::from_utf8(&bytes[..end]).unwrap();
        assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"), "{header}");
        assert!(header.contains("comment part solid vertices 0..8 faces 0..12\n"), "{header}");
        assert!(header.contains("comment part water vertices 8..16 faces 12..25\n"), "{header}");
        assert!(header.contains("element vertex 16\n") && header.contains("element face 25\n"));
        let body = &bytes[end..];
        assert_eq!(body.len(), 16 * 27 + 25 * 13);
        // Vertex 7 of the solid cube: (1, 1, 1), white.
        let v7 = &body[7 * 27..8 * 27];
        let f = |k: usize| f32::from_le_bytes(v7[4 * k..4 * k + 4].try_into().unwrap());
        assert_eq!([f(0), f(1), f(2)], [1.0, 1.0, 1.0]);
        assert_eq!(v7[24..], [255, 255, 255]);
        // The first face of the water cube, offset by the solid's 8 vertices.
        let faces = &body[16 * 27..];
        let water = &faces[12 * 13..13 * 13];
        assert_eq!(water[0], 3);
        let index = |k: usize| i32::from_le_bytes(water[1 + 4 * k..5 + 4 * k].try_into().unwrap());
        assert!((0..3).all(|k| (8..16).contains(&index(k))));
        assert_eq!(faces.len(), 25 * 13);
    }

    #[test]
    fn coordinates_beyond_f32_are_errors() {
        let mut mesh = two_cubes();
        mesh.parts[0].positions[0].z = 1e300;
        assert!(matches!(to_ply_bytes(&mesh), Err(MeshError::Limits(_))));
    }
}
