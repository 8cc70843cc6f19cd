//! Writing a [`TerrainMesh`] to the files other tools read: glTF 2.0 binary (`.glb`),
//! Wavefront OBJ (`.obj`) and binary PLY (`.ply`).
//!
//! Every format writes the parts that have faces, in order, and skips empty ones; a mesh with
//! no faces at all still writes a valid, empty file. Before anything is written each exported
//! part is checked: one normal and one colour per vertex, finite positions and colours, face
//! indices in range (a bad index is reported as [`MeshError::IndexOutOfRange`] with the face's
//! index in its part, quads first, then triangles), and sizes each format can index.
//! Normals are renormalised, and a zero or non-finite normal becomes `(0, 0, 1)`; colours are
//! clamped to `[0, 1]`.
//!
//! | format | axes | positions | colours | faces |
//! |---|---|---|---|---|
//! | [`.glb`](to_glb_bytes) | glTF's y up: relief's `(x, y, z)` is written `(x, z, -y)` | f32, relative to a node translation (f64) at the mesh's bounding-box centre | `COLOR_0`, linear | triangles ([`MeshPart::triangulated`]) |
//! | [`.obj`](to_obj_bytes) | relief's z up, as they are | decimal text of the f64 values | `v x y z r g b`, sRGB-encoded in `[0, 1]` | quads and triangles |
//! | [`.ply`](to_ply_bytes) | relief's z up, as they are | f32 | `uchar red green blue`, sRGB-encoded | quads and triangles |
//!
//! The encoders make bytes; writing them is the caller's (relief's command line writes them
//! atomically with `relief_io::write_bytes_atomically`, so a failed write leaves no partial
//! file).
//!
//! ```
//! use relief_core::DVec3;
//! use relief_mesh::export::{to_glb_bytes, MeshFormat};
//! use relief_mesh::{MeshPart, TerrainMesh};
//! let mut solid = MeshPart::new("solid", [0.5, 0.4, 0.3, 1.0]);
//! solid.positions = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
//! solid.normals = vec![[0.0, 0.0, 1.0]; 4];
//! solid.colors = vec![[0.2, 0.6, 0.1]; 4];
//! solid.quads = vec![[0, 1, 2, 3]];
//! let mesh = TerrainMesh { parts: vec![solid] };
//! let glb = to_glb_bytes(&mesh).unwrap();
//! assert_eq!(&glb[..4], b"glTF");
//! assert_eq!(MeshFormat::from_path("terrain.PLY".as_ref()).unwrap(), MeshFormat::Ply);
//! assert!(MeshFormat::from_path("terrain.stl".as_ref()).is_err());
//! ```

mod glb;
mod obj;
mod ply;

pub use glb::to_glb_bytes;
pub use obj::to_obj_bytes;
pub use ply::to_ply_bytes;

use crate::{MeshError, MeshPart, TerrainMesh};
use std::path::Path;

/// The file formats a [`TerrainMesh`] is exported to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// glTF 2.0 binary, `.glb`.
    Glb,
    /// Wavefront OBJ with vertex colours, `.obj`.
    Obj,
    /// Binary little-endian PLY, `.ply`.
    Ply,
}

impl MeshFormat {
    /// The format named by the extension of `path` (`.glb`, `.obj` or `.ply`, in any case);
    /// any other extension, or none, is [`MeshError::UnknownFormat`].
    pub fn from_path(path: &Path) -> Result<Self, MeshError> {
        let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("glb") => Ok(MeshFormat::Glb),
            Some("obj") => Ok(MeshFormat::Obj),
            Some("ply") => Ok(MeshFormat::Ply),
            _ => Err(MeshError::UnknownFormat { path: path.to_path_buf() }),
        }
    }

    /// The format's file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            MeshFormat::Glb => "glb",
            MeshFormat::Obj => "obj",
            MeshFormat::Ply => "ply",
        }
    }

    /// The bytes of `mesh` in this format.
    pub fn to_bytes(self, mesh: &TerrainMesh) -> Result<Vec<u8>, MeshError> {
        match self {
            MeshFormat::Glb => to_glb_bytes(mesh),
            MeshFormat::Obj => to_obj_bytes(mesh),
            MeshFormat::Ply => to_ply_bytes(mesh),
        }
    }
}

/// The parts of `mesh` that have faces, each checked to be exportable (see the module docs).
fn exported_parts(mesh: &TerrainMesh) -> Result<Vec<&MeshPart>, MeshError> {
    let parts: Vec<&MeshPart> = mesh.parts.iter().filter(|p| !p.is_empty()).collect();
    for part in &parts {
        check_part(part)?;
    }
    Ok(parts)
}

/// Checks that `part` can be written: attribute counts, finite values, indices in range and
/// a vertex count below `u32::MAX` (so that no index is glTF's primitive-restart value).
fn check_part(part: &MeshPart) -> Result<(), MeshError> {
    let n = part.positions.len();
    if n >= u32::MAX as usize {
        return Err(MeshError::Limits(format!(
            "part {:?} has {n} vertices; at most {} can be exported",
            part.name,
            u32::MAX - 1
        )));
    }
    if part.normals.len() != n || part.colors.len() != n {
        return Err(MeshError::Attributes(format!(
            "part {:?} has {n} vertices but {} normals and {} colours",
            part.name,
            part.normals.len(),
            part.colors.len()
        )));
    }
    if let Some((index, p)) = part.positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(MeshError::NonFinitePosition { index, x: p.x, y: p.y, z: p.z });
    }
    if let Some(index) = part.colors.iter().position(|c| c.iter().any(|v| !v.is_finite())) {
        return Err(MeshError::Attributes(format!(
            "part {:?}: vertex {index} has the non-finite colour {:?}",
            part.name, part.colors[index]
        )));
    }
    if part.base_color.iter().any(|v| !v.is_finite()) {
        return Err(MeshError::Attributes(format!(
            "part {:?} has the non-finite base colour {:?}",
            part.name, part.base_color
        )));
    }
    let faces = part.quads.iter().map(|q| &q[..]).chain(part.triangles.iter().map(|t| &t[..]));
    for (triangle, face) in faces.enumerate() {
        if let Some(&index) = face.iter().find(|&&v| v as usize >= n) {
            return Err(MeshError::IndexOutOfRange { triangle, index, vertex_count: n });
        }
    }
    Ok(())
}

/// `normal` (relief's axes) as a unit vector in f64; `(0, 0, 1)` for a zero or non-finite one.
fn unit_normal(normal: [f32; 3]) -> [f64; 3] {
    let [x, y, z] = normal.map(f64::from);
    let length = (x * x + y * y + z * z).sqrt();
    if length.is_finite() && length > 0.0 {
        [x / length, y / length, z / length]
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// A linear colour channel clamped to `[0, 1]` (its value is finite, see [`check_part`]).
fn clamp_unit(value: f32) -> f32 {
    value.clamp(0.0, 1.0)
}

/// A linear colour channel sRGB-encoded, in `[0, 1]` (IEC 61966-2-1; computed in f64 so that
/// 1 stays exactly 1).
fn srgb_encode(linear: f32) -> f32 {
    let l = f64::from(clamp_unit(linear));
    let encoded = if l <= 0.003_130_8 { 12.92 * l } else { 1.055 * l.powf(1.0 / 2.4) - 0.055 };
    (encoded as f32).clamp(0.0, 1.0)
}

/// A linear colour channel sRGB-encoded to 8 bits.
fn srgb_encode_u8(linear: f32) -> u8 {
    (srgb_encode(linear) * 255.0).round().clamp(0.0, 255.0) as u8
}

/// `name` made safe for a one-line, whitespace-separated text field (an OBJ `o` line, a PLY
/// comment): whitespace and control characters become `_`, and an empty name `part<index>`.
fn one_word_name(name: &str, index: usize) -> String {
    if name.is_empty() {
        return format!("part{index}");
    }
    name.chars().map(|c| if c.is_whitespace() || c.is_control() { '_' } else { c }).collect()
}

#[cfg(test)]
pub(crate) mod test_meshes {
    //! Meshes shared by the export tests.

    use crate::{MeshPart, TerrainMesh};
    use relief_core::DVec3;

    /// An axis-aligned cube from `min` with edge `size`: 8 corners shared by 6 outward quads
    /// (counter-clockwise seen from outside), each corner's normal the normalised sum of the
    /// three faces' normals.
    pub(crate) fn cube(name: &str, min: DVec3, size: f64, base_color: [f32; 4]) -> MeshPart {
        let mut part = MeshPart::new(name, base_color);
        for k in 0..8u32 {
            let corner = DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64);
            part.positions.push(min + corner * size);
            let n = (corner * 2.0 - DVec3::ONE).normalize();
            part.normals.push([n.x as f32, n.y as f32, n.z as f32]);
            part.colors.push([corner.x as f32, corner.y as f32, corner.z as f32]);
        }
        part.quads = vec![
            [0, 2, 3, 1], // z = 0, facing -z
            [4, 5, 7, 6], // z = 1, facing +z
            [0, 1, 5, 4], // y = 0, facing -y
            [2, 6, 7, 3], // y = 1, facing +y
            [0, 4, 6, 2], // x = 0, facing -x
            [1, 3, 7, 5], // x = 1, facing +x
        ];
        part
    }

    /// A unit `solid` cube at the origin and a half-size translucent `water` cube beside it.
    pub(crate) fn two_cubes() -> TerrainMesh {
        TerrainMesh {
            parts: vec![
                cube("solid", DVec3::ZERO, 1.0, [0.6, 0.5, 0.4, 1.0]),
                cube("water", DVec3::new(2.0, 0.0, 0.0), 0.5, [0.1, 0.3, 0.6, 0.7]),
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_meshes::{cube, two_cubes};
    use super::*;
    use relief_core::DVec3;

    #[test]
    fn formats_by_extension_in_any_case() {
        for (name, format) in [
            ("a.glb", MeshFormat::Glb),
            ("dir/a.GLB", MeshFormat::Glb),
            ("a.Obj", MeshFormat::Obj),
            ("a.b.ply", MeshFormat::Ply),
        ] {
            assert_eq!(MeshFormat::from_path(Path::new(name)).unwrap(), format, "{name}");
        }
        for name in ["a.gltf", "a", "glb", "a.glb.tmp", ""] {
            let err = MeshFormat::from_path(Path::new(name)).unwrap_err();
            assert!(matches!(err, MeshError::UnknownFormat { .. }), "{name}");
            let message = err.to_string();
            assert!(message.contains(".glb") && message.contains(".obj"), "{message}");
            assert!(message.contains(".ply"), "{message}");
        }
    }

    #[test]
    fn invalid_parts_are_errors_in_every_format_not_panics() {
        let mut bad_index = cube("solid", DVec3::ZERO, 1.0, [1.0; 4]);
        bad_index.triangles.push([0, 1, 8]);
        let mut few_normals = cube("solid", DVec3::ZERO, 1.0, [1.0; 4]);
        few_normals.normals.pop();
        let mut nan_position = cube("solid", DVec3::ZERO, 1.0, [1.0; 4]);
        nan_position.positions[3].y = f64::NAN;
        let mut nan_color = cube("solid", DVec3::ZERO, 1.0, [1.0; 4]);
        nan_color.colors[5][2] = f32::INFINITY;
        let mut nan_base = cube("solid", DVec3::ZERO, 1.0, [1.0; 4]);
        nan_base.base_color[3] = f32::NAN;
        for format in [MeshFormat::Glb, MeshFormat::Obj, MeshFormat::Ply] {
            let err = |part: &MeshPart| {
                format.to_bytes(&TerrainMesh { parts: vec![part.clone()] }).unwrap_err()
            };
            assert_eq!(
                err(&bad_index),
                MeshError::IndexOutOfRange { triangle: 6, index: 8, vertex_count: 8 }
            );
            assert!(matches!(err(&few_normals), MeshError::Attributes(_)));
            assert!(matches!(err(&nan_position), MeshError::NonFinitePosition { index: 3, .. }));
            assert!(matches!(err(&nan_color), MeshError::Attributes(_)));
            assert!(matches!(err(&nan_base), MeshError::Attributes(_)));
        }
    }

    #[test]
    fn empty_parts_are_skipped_unchecked() {
        let mut empty = MeshPart::new("water", [0.0; 4]);
        empty.positions.push(DVec3::NAN);
        let mesh = TerrainMesh { parts: vec![empty, cube("solid", DVec3::ZERO, 1.0, [1.0; 4])] };
        for format in [MeshFormat::Glb, MeshFormat::Obj, MeshFormat::Ply] {
            assert!(format.to_bytes(&mesh).is_ok());
        }
    }

    #[test]
    fn normals_and_colours_are_sanitised() {
        assert_eq!(unit_normal([0.0, 0.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(unit_normal([f32::NAN, 0.0, 1.0]), [0.0, 0.0, 1.0]);
        assert_eq!(unit_normal([0.0, 3.0, 4.0]), [0.0, 0.6, 0.8]);
        assert_eq!(unit_normal([f32::MAX, f32::MAX, 0.0]), [0.5f64.sqrt(), 0.5f64.sqrt(), 0.0]);
        assert_eq!(srgb_encode(1.0), 1.0);
        assert_eq!(srgb_encode_u8(0.0), 0);
        assert_eq!(srgb_encode_u8(1.0), 255);
        assert_eq!(srgb_encode_u8(2.0), 255);
        assert_eq!(srgb_encode_u8(-1.0), 0);
        assert_eq!(srgb_encode_u8(0.215_861), 128); // sRGB 128/255 is linear 0.2159
        assert_eq!(one_word_name("deep water\n", 0), "deep_water_");
        assert_eq!(one_word_name("", 2), "part2");
    }

    #[test]
    fn the_extension_picks_the_format_and_bad_meshes_are_refused() {
        let mesh = two_cubes();
        for (name, format) in
            [("t.glb", MeshFormat::Glb), ("t.OBJ", MeshFormat::Obj), ("t.ply", MeshFormat::Ply)]
        {
            assert_eq!(MeshFormat::from_path(name.as_ref()).unwrap(), format);
        }
        assert!(MeshFormat::from_path("t.stl".as_ref()).is_err());
        let mut bad = mesh.clone();
        bad.parts[0].quads[0][0] = 99;
        for format in [MeshFormat::Glb, MeshFormat::Obj, MeshFormat::Ply] {
            assert!(format.to_bytes(&mesh).is_ok());
            assert!(format.to_bytes(&bad).is_err(), "{format:?}");
        }
    }
}
