//! Wavefront OBJ (`.obj`) export: one `o` group per non-empty part, vertex colours, normals,
//! quads kept as quads.
//!
//! Coordinates are relief's world as they are: right-handed, **z up**, metres, written as the
//! shortest decimals that read back to the same f64 (importers that assume y up show the
//! terrain lying on its side unless told the up axis). Each vertex is a `v x y z r g b` line
//! (the vertex-colour extension MeshLab, Blender and trimesh read), its colour sRGB-encoded in
//! `[0, 1]`, and a `vn` line with its unit normal; faces are `f a//a b//b c//c [d//d]`, wound
//! counter-clockwise seen from outside, with 1-based indices running on across parts. No
//! `.mtl` is written: the parts' base colours are in comments.

use super::{exported_parts, one_word_name, srgb_encode, unit_normal};
use crate::{MeshError, TerrainMesh};
use std::fmt::{self, Write};

/// `mesh` as the text of an OBJ file (see the module docs of [`crate::export`] for what is
/// checked).
pub fn to_obj_bytes(mesh: &TerrainMesh) -> Result<Vec<u8>, MeshError> {
    let parts = exported_parts(mesh)?;
    let mut out = String::new();
    let text = (|| -> fmt::Result {
        let vertices: usize = parts.iter().map(|p| p.vertex_count()).sum();
        let faces: usize = parts.iter().map(|p| p.quads.len() + p.triangles.len()).sum();
        writeln!(
            out,
            "# relief terrain mesh: {} parts, {vertices} vertices, {faces} faces",
            parts.len()
        )?;
        writeln!(out, "# axes: relief's world, right-handed, z up, metres")?;
        writeln!(out, "# v x y z r g b: position, then vertex colour sRGB-encoded in [0, 1]")?;
        writeln!(out, "# vn: unit vertex normal; f v//vn: faces counter-clockwise from outside")?;
        let mut offset: u64 = 1;
        for (index, part) in parts.iter().enumerate() {
            let [r, g, b, a] = part.base_color;
            writeln!(out, "o {}", one_word_name(&part.name, index))?;
            writeln!(out, "# base colour (linear RGBA): {r} {g} {b} {a}")?;
            for (p, c) in part.positions.iter().zip(&part.colors) {
                let [r, g, b] = c.map(srgb_encode);
                writeln!(out, "v {} {} {} {r} {g} {b}", p.x, p.y, p.z)?;
            }
            for &n in &part.normals {
                let [x, y, z] = unit_normal(n).map(|v| v as f32);
                writeln!(out, "vn {x} {y} {z}")?;
            }
            let faces =
                part.quads.iter().map(|q| &q[..]).chain(part.triangles.iter().map(|t| &t[..]));
            for face in faces {
                out.push('f');
                for &v in face {
                    let i = offset + u64::from(v);
                    write!(out, " {i}//{i}")?;
                }
                out.push('\n');
            }
            offset += part.vertex_count() as u64;
        }
        Ok(())
    })();
    text.map_err(|e| MeshError::Limits(format!("formatting the OBJ text failed: {e}")))?;
    Ok(out.into_bytes())
}

#[cfg(test)]
mod tests {
    use super::super::test_meshes::two_cubes;
    use super::*;

    #[test]
    fn obj_has_groups_coloured_vertices_and_offset_quads() {
        let mut mesh = two_cubes();
        mesh.parts[1].triangles.push([0, 1, 2]);
        let text = String::from_utf8(to_obj_bytes(&mesh).unwrap()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("# relief terrain mesh: 2 parts, 16 vertices, 13 faces"));
        let groups: Vec<&str> = lines.iter().filter(|l| l.starts_with("o ")).copied().collect();
        assert_eq!(groups, ["o solid", "o water"]);
        assert_eq!(lines.iter().filter(|l| l.starts_with("v ")).count(), 16);
        assert_eq!(lines.iter().filter(|l| l.starts_with("vn ")).count(), 16);
        let faces: Vec<&str> = lines.iter().filter(|l| l.starts_with("f ")).copied().collect();
        assert_eq!(faces.len(), 13);
        assert_eq!(faces[0], "f 1//1 3//3 4//4 2//2");
        assert_eq!(faces[6], "f 9//9 11//11 12//12 10//10");
        assert_eq!(faces[12], "f 9//9 10//10 11//11");
        // Vertex 8 (the corner (1, 1, 1) of the unit cube): white, normal (1, 1, 1)/sqrt 3.
        let v8 = lines.iter().filter(|l| l.starts_with("v ")).nth(7).unwrap();
        assert_eq!(*v8, "v 1 1 1 1 1 1");
        let vn8 = lines.iter().filter(|l| l.starts_with("vn ")).nth(7).unwrap();
        let n: Vec<f32> = vn8[3..].split(' ').map(|v| v.parse().unwrap()).collect();
        assert!(n.iter().all(|v| (v - 1.0 / 3f32.sqrt()).abs() < 1e-6), "{vn8}");
    }

    #[test]
    fn an_empty_mesh_is_only_comments() {
        let text = String::from_utf8(to_obj_bytes(&TerrainMesh::default()).unwrap()).unwrap();
        assert!(text.lines().all(|l| l.starts_with('#')), "{text}");
    }
}
