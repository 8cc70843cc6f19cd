//! glTF 2.0 binary (`.glb`) export: one glTF mesh, node and material per non-empty part.
//!
//! glTF is y up, relief is z up: a point or normal `(x, y, z)` of relief's world is written
//! `(x, z, -y)` (a rotation, so handedness and windings are kept; metres stay metres).
//! Positions are f32 in glTF, which keeps about 7 significant digits: so that large
//! georeferenced coordinates keep their precision, every node has a `translation` (f64 in the
//! JSON) at the bounding-box centre of the whole mesh, and the positions are stored relative
//! to it; the `POSITION` accessor's `min`/`max` are those of the f32 values written.
//!
//! Each part becomes a mesh and a node named after it with one triangle primitive
//! ([`MeshPart::triangulated`], u32 indices), attributes `POSITION`, `NORMAL` (unit length) and
//! `COLOR_0` (linear RGB, f32), and its own material: `baseColorFactor` the part's
//! `base_color`, metallic 0, roughness 0.9, alpha mode `BLEND` when the base colour's alpha is
//! below 1, single-sided.

use super::{clamp_unit, exported_parts, unit_normal};
use crate::{MeshError, MeshPart, TerrainMesh};
use serde_json::{json, Value};

/// The GLB header's magic, `glTF`.
const MAGIC: u32 = 0x4654_6C67;
/// The type of the JSON chunk.
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// The type of the binary chunk.
const CHUNK_BIN: u32 = 0x004E_4942;
/// `bufferView.target` of vertex attributes.
const ARRAY_BUFFER: u32 = 34962;
/// `bufferView.target` of indices.
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// `accessor.componentType` of f32.
const FLOAT: u32 = 5126;
/// `accessor.componentType` of u32.
const UNSIGNED_INT: u32 = 5125;
/// Roughness of every exported material.
const ROUGHNESS: f32 = 0.9;

/// `mesh` as the bytes of a glTF 2.0 binary file (see the module docs of
/// [`crate::export`] for what is checked).
pub fn to_glb_bytes(mesh: &TerrainMesh) -> Result<Vec<u8>, MeshError> {
    let parts = exported_parts(mesh)?;
    let centre = bounding_box_centre(&parts);
    let mut gltf = GltfBuilder::default();
    for (index, part) in parts.iter().enumerate() {
        gltf.add_part(index, part, centre)?;
    }
    gltf.into_glb()
}

/// relief's `(x, y, z)` in glTF's axes, `(x, z, -y)`.
fn to_gltf_axes([x, y, z]: [f64; 3]) -> [f64; 3] {
    [x, z, -y]
}

/// Centre of the bounding box of every vertex of `parts`, in glTF's axes; the origin when
/// there are none.
fn bounding_box_centre(parts: &[&MeshPart]) -> [f64; 3] {
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    for p in parts.iter().flat_map(|part| &part.positions) {
        let g = to_gltf_axes(p.to_array());
        for k in 0..3 {
            min[k] = min[k].min(g[k]);
            max[k] = max[k].max(g[k]);
        }
    }
    if min[0] > max[0] {
        return [0.0; 3];
    }
    // Halved first so that coordinates near f64's range do not overflow.
    std::array::from_fn(|k| min[k] / 2.0 + max[k] / 2.0)
}

/// The JSON arrays and the binary buffer of a glTF asset, filled part by part.
#[derive(Default)]
struct GltfBuilder {
    bin: Vec<u8>,
    buffer_views: Vec<Value>,
    accessors: Vec<Value>,
    materials: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
}

impl GltfBuilder {
    /// Appends `bytes` (a multiple of 4 long) as a buffer view for `target`; its index.
    fn push_view(&mut self, bytes: &[u8], target: u32) -> usize {
        let view = json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": bytes.len(),
            "target": target,
        });
        self.bin.extend_from_slice(bytes);
        self.buffer_views.push(view);
        self.buffer_views.len() - 1
    }

    /// Appends a tightly packed f32 VEC3 accessor of `values`, with `min`/`max` when `bounds`;
    /// its index.
    fn push_vec3(&mut self, values: &[[f32; 3]], bounds: bool) -> usize {
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.push_view(&bytes, ARRAY_BUFFER);
        let mut accessor = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": values.len(),
            "type": "VEC3",
        });
        if bounds {
            let mut min = [f32::INFINITY; 3];
            let mut max = [f32::NEG_INFINITY; 3];
            for v in values {
                for k in 0..3 {
                    min[k] = min[k].min(v[k]);
                    max[k] = max[k].max(v[k]);
                }
            }
            accessor["min"] = json!(min);
            accessor["max"] = json!(max);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Adds `part` (checked, with faces) as material, mesh and node number `index`, its
    /// positions relative to `centre` (glTF axes).
    fn add_part(
        &mut self,
        index: usize,
        part: &MeshPart,
        centre: [f64; 3],
    ) -> Result<(), MeshError> {
        let mut positions = Vec::with_capacity(part.positions.len());
        for (vertex, p) in part.positions.iter().enumerate() {
            let g = to_gltf_axes(p.to_array());
            let relative: [f32; 3] = std::array::from_fn(|k| (g[k] - centre[k]) as f32);
            if relative.iter().any(|v| !v.is_finite()) {
                return Err(MeshError::Limits(format!(
                    "part {:?}: vertex {vertex} at {p} is too far from the mesh's centre for \
                     glTF's f32 positions",
                    part.name
                )));
            }
            positions.push(relative);
        }
        let normals: Vec<[f32; 3]> =
            part.normals.iter().map(|&n| to_gltf_axes(unit_normal(n)).map(|v| v as f32)).collect();
        let colors: Vec<[f32; 3]> = part.colors.iter().map(|c| c.map(clamp_unit)).collect();
        let position = self.push_vec3(&positions, true);
        let normal = self.push_vec3(&normals, false);
        let color = self.push_vec3(&colors, false);

        let triangles = part.triangulated();
        let bytes: Vec<u8> = triangles.iter().flatten().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.push_view(&bytes, ELEMENT_ARRAY_BUFFER);
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": UNSIGNED_INT,
            "count": triangles.len() * 3,
            "type": "SCALAR",
        }));
        let indices = self.accessors.len() - 1;

        let base_color = part.base_color.map(clamp_unit);
        let mut material = json!({
            "name": part.name,
            "pbrMetallicRoughness": {
                "baseColorFactor": base_color,
                "metallicFactor": 0.0,
                "roughnessFactor": ROUGHNESS,
            },
            "doubleSided": false,
        });
        if base_color[3] < 1.0 {
            material["alphaMode"] = json!("BLEND");
        }
        self.materials.push(material);
        self.meshes.push(json!({
            "name": part.name,
            "primitives": [{
                "attributes": { "POSITION": position, "NORMAL": normal, "COLOR_0": color },
                "indices": indices,
                "material": index,
                "mode": 4,
            }],
        }));
        self.nodes.push(json!({ "name": part.name, "mesh": index, "translation": centre }));
        Ok(())
    }

    /// The GLB file: header, JSON chunk (padded with spaces) and, unless the buffer is empty,
    /// the BIN chunk (padded with zeros).
    fn into_glb(self) -> Result<Vec<u8>, MeshError> {
        let mut root = json!({ "asset": { "version": "2.0", "generator": "relief" } });
        // glTF arrays may not be empty: an asset without faces has none of them.
        if !self.nodes.is_empty() {
            let nodes: Vec<usize> = (0..self.nodes.len()).collect();
            root["scene"] = json!(0);
            root["scenes"] = json!([{ "nodes": nodes }]);
            root["nodes"] = Value::Array(self.nodes);
            root["meshes"] = Value::Array(self.meshes);
            root["materials"] = Value::Array(self.materials);
            root["accessors"] = Value::Array(self.accessors);
            root["bufferViews"] = Value::Array(self.buffer_views);
            root["buffers"] = json!([{ "byteLength": self.bin.len() }]);
        }
        let mut json = root.to_string().into_bytes();
        json.resize(json.len().next_multiple_of(4), b' ');
        let mut bin = self.bin;
        bin.resize(bin.len().next_multiple_of(4), 0);

        let chunks = if bin.is_empty() {
            vec![(CHUNK_JSON, json)]
        } else {
            vec![(CHUNK_JSON, json), (CHUNK_BIN, bin)]
        };
        let total: usize = 12 + chunks.iter().map(|(_, data)| 8 + data.len()).sum::<usize>();
        let total = u32::try_from(total).map_err(|_| {
            MeshError::Limits(format!("the .glb would be {total} bytes; at most 4 GiB can be"))
        })?;
        let mut out = Vec::with_capacity(total as usize);
        out.extend_from_slice(&MAGIC.to_le_bytes());
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&total.to_le_bytes());
        for (kind, data) in chunks {
            // Fits: the whole file does.
            out.extend_from_slice(&(data.len() as u32).to_le_bytes());
            out.extend_from_slice(&kind.to_le_bytes());
            out.extend_from_slice(&data);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_meshes::{cube, two_cubes};
    use super::*;
    use relief_core::DVec3;

    fn u32_at(bytes: &[u8], offset: usize) -> u32 {
        u32::from_le_bytes(bytes[offset..offset + 4].try_into().unwrap())
    }

    /// A parsed GLB: its JSON and its BIN chunk, after checking the container's structure.
    fn parse(glb: &[u8]) -> (Value, Vec<u8>) {
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(u32_at(glb, 4), 2);
        assert_eq!(u32_at(glb, 8) as usize, glb.len());
        let json_len = u32_at(glb, 12) as usize;
        assert_eq!(u32_at(glb, 16), CHUNK_JSON);
        assert_eq!(json_len % 4, 0);
        let json_bytes = &glb[20..20 + json_len];
        assert!(!json_bytes.trim_ascii_end().ends_with(b" "));
        let json: Value = serde_json::from_slice(json_bytes).unwrap();
        let mut offset = 20 + json_len;
        let mut bin = Vec::new();
        if offset < glb.len() {
            let bin_len = u32_at(glb, offset) as usize;
            assert_eq!(u32_at(glb, offset + 4), CHUNK_BIN);
            assert_eq!(bin_len % 4, 0);
            bin = glb[offset + 8..offset + 8 + bin_len].to_vec();
            offset += 8 + bin_len;
        }
        assert_eq!(offset, glb.len());
        (json, bin)
    }

    /// The f32 or u32 components an accessor reads, after checking it fits its buffer view
    /// and the view its buffer.
    fn read_accessor(json: &Value, bin: &[u8], index: &Value) -> (Vec<[u8; 4]>, usize) {
        let accessor = &json["accessors"][index.as_u64().unwrap() as usize];
        let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
        assert!(view.get("byteStride").is_none());
        let components = match accessor["type"].as_str().unwrap() {
            "SCALAR" => 1,
            "VEC3" => 3,
            other => panic!("{other}"),
        };
        let count = accessor["count"].as_u64().unwrap() as usize;
        let offset = view["byteOffset"].as_u64().unwrap() as usize;
        let length = view["byteLength"].as_u64().unwrap() as usize;
        assert_eq!(offset % 4, 0);
        assert_eq!(count * components * 4, length);
        assert!(offset + length <= json["buffers"][0]["byteLength"].as_u64().unwrap() as usize);
        assert!(json["buffers"][0]["byteLength"].as_u64().unwrap() as usize <= bin.len());
        let data = bin[offset..offset + length].chunks(4).map(|c| c.try_into().unwrap()).collect();
        (data, components)
    }

    fn floats(data: &[[u8; 4]]) -> Vec<[f32; 3]> {
        data.chunks(3).map(|c| std::array::from_fn(|k| f32::from_le_bytes(c[k]))).collect()
    }

    #[test]
    fn glb_structure_accessors_and_bounds_are_consistent() {
        let mesh = two_cubes();
        let (json, bin) = parse(&to_glb_bytes(&mesh).unwrap());
        assert_eq!(json["asset"]["version"], "2.0");
        assert_eq!(json["asset"]["generator"], "relief");
        assert_eq!(json["scenes"][0]["nodes"], json!([0, 1]));
        assert_eq!(json["buffers"][0]["byteLength"].as_u64().unwrap() as usize, bin.len());
        // Bounding box of both cubes: x 0..2.5, y 0..1, z 0..1 -> glTF (1.25, 0.5, -0.5).
        let centre = [1.25, 0.5, -0.5];
        for (k, part) in mesh.parts.iter().enumerate() {
            let node = &json["nodes"][k];
            assert_eq!(node["name"], part.name.as_str());
            assert_eq!(node["mesh"], k);
            assert_eq!(node["translation"], json!(centre));
            let gltf_mesh = &json["meshes"][k];
            assert_eq!(gltf_mesh["name"], part.name.as_str());
            let primitive = &gltf_mesh["primitives"][0];
            assert_eq!(primitive["mode"], 4);
            let material = &json["materials"][primitive["material"].as_u64().unwrap() as usize];
            assert_eq!(material["name"], part.name.as_str());
            assert_eq!(material["doubleSided"], false);
            let factor = &material["pbrMetallicRoughness"]["baseColorFactor"];
            assert_eq!(factor, &json!(part.base_color));
            let blend = part.base_color[3] < 1.0;
            assert_eq!(material.get("alphaMode") == Some(&json!("BLEND")), blend);

            let attributes = &primitive["attributes"];
            let (data, _) = read_accessor(&json, &bin, &attributes["POSITION"]);
            let positions = floats(&data);
            assert_eq!(positions.len(), part.vertex_count());
            for (p, q) in positions.iter().zip(&part.positions) {
                let world =
                    [p[0] as f64 + centre[0], p[1] as f64 + centre[1], p[2] as f64 + centre[2]];
                assert_eq!(world, [q.x, q.z, -q.y]);
            }
            let accessor = &json["accessors"][attributes["POSITION"].as_u64().unwrap() as usize];
            for k in 0..3 {
                let min = positions.iter().map(|p| p[k]).fold(f32::INFINITY, f32::min);
                let max = positions.iter().map(|p| p[k]).fold(f32::NEG_INFINITY, f32::max);
                assert_eq!(accessor["min"][k].as_f64().unwrap() as f32, min);
                assert_eq!(accessor["max"][k].as_f64().unwrap() as f32, max);
            }
            let (data, _) = read_accessor(&json, &bin, &attributes["NORMAL"]);
            for (n, m) in floats(&data).iter().zip(&part.normals) {
                let length = n.iter().map(|v| v * v).sum::<f32>().sqrt();
                assert!((length - 1.0).abs() < 1e-6);
                assert_eq!(*n, [m[0], m[2], -m[1]]);
            }
            let (data, _) = read_accessor(&json, &bin, &attributes["COLOR_0"]);
            assert_eq!(floats(&data), part.colors);
            let (data, components) = read_accessor(&json, &bin, &primitive["indices"]);
            assert_eq!(components, 1);
            let indices: Vec<u32> = data.iter().map(|b| u32::from_le_bytes(*b)).collect();
            assert_eq!(indices, part.triangulated().concat());
            assert!(indices.iter().all(|&i| (i as usize) < part.vertex_count()));
        }
    }

    #[test]
    fn far_coordinates_keep_their_precision_through_the_translation() {
        // UTM-like coordinates: f32 alone would round them to a metre or so.
        let origin = DVec3::new(500_000.123, 5_200_000.456, 1234.5);
        let mesh = TerrainMesh { parts: vec![cube("solid", origin, 0.25, [1.0; 4])] };
        let (json, bin) = parse(&to_glb_bytes(&mesh).unwrap());
        let translation: Vec<f64> = json["nodes"][0]["translation"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let attributes = &json["meshes"][0]["primitives"][0]["attributes"];
        let (data, _) = read_accessor(&json, &bin, &attributes["POSITION"]);
        for (p, q) in floats(&data).iter().zip(&mesh.parts[0].positions) {
            let world: [f64; 3] = std::array::from_fn(|k| p[k] as f64 + translation[k]);
            let want = [q.x, q.z, -q.y];
            for k in 0..3 {
                assert!((world[k] - want[k]).abs() < 1e-6, "{world:?} {want:?}");
            }
        }
    }

    #[test]
    fn a_mesh_without_faces_is_a_valid_empty_asset() {
        let mut empty = MeshPart::new("water", [0.0, 0.0, 1.0, 0.5]);
        empty.positions.push(DVec3::ONE);
        for mesh in [TerrainMesh::default(), TerrainMesh { parts: vec![empty] }] {
            let (json, bin) = parse(&to_glb_bytes(&mesh).unwrap());
            assert!(bin.is_empty());
            assert_eq!(json, json!({ "asset": { "version": "2.0", "generator": "relief" } }));
        }
    }

    #[test]
    fn bad_normals_become_up_and_far_vertices_are_errors() {
        let mut part = cube("solid", DVec3::ZERO, 1.0, [1.0; 4]);
        part.normals[0] = [0.0; 3];
        part.normals[1] = [f32::NAN, 1.0, 0.0];
        part.normals[2] = [0.0, 0.0, -7.0];
        let mesh = TerrainMesh { parts: vec![part.clone()] };
        let (json, bin) = parse(&to_glb_bytes(&mesh).unwrap());
        let (data, _) =
            read_accessor(&json, &bin, &json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"]);
        let normals = floats(&data);
        assert_eq!(normals[..3], [[0.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]);

        part.positions[0].x = -1e300;
        part.positions[1].x = 1e300;
        let err = to_glb_bytes(&TerrainMesh { parts: vec![part] }).unwrap_err();
        assert!(matches!(err, MeshError::Limits(_)), "{err}");
    }
}
