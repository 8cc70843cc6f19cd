//! The stacks mesher: the quadrangulation pipeline run over the octree's nodes, at one level of
//! detail or at the levels a camera asks for, node meshes cached across frames and joined into
//! one [`TerrainMesh`] of a `solid` and a `water` part.

use super::density::{Channels, Density, Smoothing};
use super::lattice::{Block, Lattice};
use super::node_mesher::{coarse_block, fine_block, mesh_node, LevelField, NodeJob, NodeMesh};
use super::octree::{Leaves, NodeKey};
use crate::terrain_mesh::split_quad;
use crate::{IndexedMesh, MeshError, MeshPart, TerrainMesh};
use rayon::prelude::*;
use relief_core::{Camera, DVec3, MaterialKind, StacksMipmap};
use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

/// The parameters of the stacks mesher.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StacksMeshParams {
    /// Cells per octree node along each axis (the paper's 17^3 nodes: 16 cells of 17 points).
    pub node_cells: usize,
    /// The low-pass filter of section 3.2.2.
    pub smoothing: Smoothing,
    /// Height of a density voxel at the finest level, metres; `None`: the stacks' spacing
    /// along x (cubic voxels).
    pub voxel_height: Option<f64>,
}

impl Default for StacksMeshParams {
    fn default() -> Self {
        StacksMeshParams {
            node_cells: 16,
            smoothing: Smoothing::Gaussian { sigma: 1.0 },
            voxel_height: None,
        }
    }
}

/// The octree nodes meshed for one level or one camera, and what meshing them cost.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MeshStats {
    /// Nodes selected (those that may hold surface).
    pub nodes: usize,
    /// Nodes whose mesh was made now (not found in the cache).
    pub meshed: usize,
    /// Nodes per level, finest first.
    pub per_level: [usize; 16],
    /// Milliseconds choosing the nodes.
    pub select_ms: f64,
    /// Milliseconds meshing the nodes not in the cache (all cores).
    pub mesh_ms: f64,
    /// Milliseconds joining the nodes' meshes into one.
    pub join_ms: f64,
}

/// Meshes a stacks terrain: its mipmap, the lattices of its levels and a cache of node meshes.
///
/// ```
/// use relief_core::{DVec2, MaterialStacks, StackLayer, StackMaterial, StacksMipmap};
/// use relief_mesh::{StacksMesher, StacksMeshParams};
/// // A 6 x 6 slab of bedrock, 3 m thick.
/// let stacks = MaterialStacks::from_stacks(6, 6, DVec2::ONE, DVec2::ZERO,
///     StackMaterial::defaults(), &vec![vec![StackLayer::new(0.0, 3.0, 0)]; 36]).unwrap();
/// let mesher = StacksMesher::new(StacksMipmap::new(stacks), StacksMeshParams::default()).unwrap();
/// let (mesh, _) = mesher.mesh_level(0).unwrap();
/// assert!(mesh.part("solid").unwrap().quads.len() > 0);
/// ```
#[derive(Debug)]
pub struct StacksMesher {
    mipmap: StacksMipmap,
    params: StacksMeshParams,
    lattices: Vec<Lattice>,
    channels: Channels,
    kernel: Vec<f32>,
    colors: Vec<[f32; 3]>,
    liquid_color: [f32; 3],
    /// Lattice z of the highest layer end at level 0.
    top_k: f64,
    /// Per level: the width of its grid of node columns, and per node column where the
    /// layers within its reach lie (see [`ColumnRange`]).
    node_columns: Vec<(usize, Vec<ColumnRange>)>,
    cache: HashMap<(NodeKey, Vec<NodeKey>), Arc<NodeMesh>>,
}

impl StacksMesher {
    /// A mesher for `mipmap`. Fails when the parameters are out of range (fewer than 2 cells a
    /// node, a voxel height or a Gaussian's sigma not finite and positive).
    pub fn new(mipmap: StacksMipmap, params: StacksMeshParams) -> Result<Self, MeshError> {
        if params.node_cells < 2 || params.node_cells > 256 {
            return Err(MeshError::Parameter {
                name: "node cells",
                reason: format!("{}: 2 to 256 cells a node", params.node_cells),
            });
        }
        if let Smoothing::Gaussian { sigma } = params.smoothing {
            if !(sigma.is_finite() && sigma > 0.0 && sigma <= 16.0) {
                return Err(MeshError::Parameter {
                    name: "sigma",
                    reason: format!("{sigma}: must lie in (0, 16]"),
                });
            }
        }
        let level0 = &mipmap.levels()[0];
        let dz0 = params.voxel_height.unwrap_or(level0.spacing().x);
        if !(dz0.is_finite() && dz0 > 0.0) {
            return Err(MeshError::Parameter {
                name: "voxel height",
                reason: format!("{dz0}: must be finite and positive"),
            });
        }
        let (bottom, top) = level0.height_range().unwrap_or((0.0, 0.0));
        let z0 = bottom as f64;
        let lattices: Vec<Lattice> =
            mipmap.levels().iter().enumerate().map(|(l, s)| Lattice::new(s, l, z0, dz0)).collect();
        let channels = Channels::new(level0);
        let linear = |c: [u8; 3]| c.map(srgb_to_linear);
        let colors = channels
            .materials
            .iter()
            .map(|&m| linear(level0.materials()[m as usize].color))
            .collect();
        let liquid_color = level0
            .materials()
            .iter()
            .find(|m| m.kind == MaterialKind::Liquid)
            .map_or([0.03, 0.1, 0.3], |m| linear(m.color));
        let n = params.node_cells as i32;
        let kernel = params.smoothing.kernel();
        let reach = node_reach(&kernel);
        let node_columns = mipmap
            .levels()
            .iter()
            .zip(&lattices)
            .map(|(s, lattice)| node_columns(s, lattice, n, reach))
            .collect();
        Ok(StacksMesher {
            kernel,
            top_k: (top as f64 - z0) / dz0,
            mipmap,
            params,
            lattices,
            channels,
            colors,
            liquid_color,
            node_columns,
            cache: HashMap::new(),
        })
    }

    /// The mipmap meshed.
    pub fn mipmap(&self) -> &StacksMipmap {
        &self.mipmap
    }

    /// The parameters.
    pub fn params(&self) -> &StacksMeshParams {
        &self.params
    }

    /// Number of levels of detail (the mipmap's levels).
    pub fn level_count(&self) -> usize {
        self.mipmap.levels().len()
    }

    fn n(&self) -> i32 {
        self.params.node_cells as i32
    }

    /// The nodes of `level` that cover the terrain and the air ring around it.
    fn nodes_of_level(&self, level: usize) -> Vec<NodeKey> {
        let s = &self.mipmap.levels()[level];
        let n = self.n();
        let top = (self.top_k / (1u64 << level) as f64).ceil() as i32 + 1;
        let last = [s.width() as i32, s.height() as i32, top];
        let mut out = Vec::new();
        for z in (-1i32).div_euclid(n)..=last[2].div_euclid(n) {
            for y in (-1i32).div_euclid(n)..=last[1].div_euclid(n) {
                for x in (-1i32).div_euclid(n)..=last[0].div_euclid(n) {
                    out.push(NodeKey { level: level as u8, at: [x, y, z] });
                }
            }
        }
        out
    }

    /// Whether node `key` certainly holds no surface: within its points and the filter's
    /// reach around them, no layer of its level, or solid everywhere.
    fn is_empty(&self, key: &NodeKey) -> bool {
        let level = key.level as usize;
        let n = self.n();
        let (w, columns) = &self.node_columns[level];
        let (x, y) = (key.at[0] + 1, key.at[1] + 1);
        if x < 0 || y < 0 || x as usize >= *w || (x as usize + y as usize * w) >= columns.len() {
            return true;
        }
        let c = &columns[x as usize + y as usize * w];
        let reach = self.reach();
        let z_lo = (key.at[2] * n - reach) as f32 - 0.5;
        let z_hi = (key.at[2] * n + n + reach) as f32 + 0.5;
        let all_air = c.end < z_lo || c.start > z_hi;
        let all_solid = c.solid_start <= z_lo && c.solid_end >= z_hi;
        all_air || all_solid
    }

    /// How far beyond its points a node's density reaches: its cells' ring, the Sobel
    /// neighbours and the filter.
    fn reach(&self) -> i32 {
        node_reach(&self.kernel)
    }

    /// The mesh of the whole terrain at `level` (0 finest). Fails naming the level when the
    /// mipmap has no such level.
    pub fn mesh_level(&self, level: usize) -> Result<(TerrainMesh, MeshStats), MeshError> {
        if level >= self.level_count() {
            return Err(MeshError::Parameter {
                name: "level of detail",
                reason: format!(
                    "level {level} is beyond the mipmap's levels 0 to {}",
                    self.level_count() - 1
                ),
            });
        }
        let start = Instant::now();
        let nodes: Vec<(NodeKey, Vec<NodeKey>)> = self
            .nodes_of_level(level)
            .into_iter()
            .filter(|k| !self.is_empty(k))
            .map(|k| (k, Vec::new()))
            .collect();
        let select_ms = ms(start);
        let start = Instant::now();
        let meshes: Vec<NodeMesh> = nodes.par_iter().map(|(k, c)| self.mesh_one(k, c)).collect();
        let mesh_ms = ms(start);
        let start = Instant::now();
        let mesh = self.join(&meshes.iter().collect::<Vec<_>>());
        let mut stats = MeshStats {
            nodes: nodes.len(),
            meshed: nodes.len(),
            select_ms,
            mesh_ms,
            join_ms: ms(start),
            ..Default::default()
        };
        stats.per_level[level.min(15)] = nodes.len();
        Ok((mesh, stats))
    }

    /// The leaves of the octree for `camera`: nodes split while a cell's screen-space extent
    /// (equation 1) exceeds `tau` pixels, then balanced.
    pub fn select(&self, camera: &Camera, tau: f64) -> Vec<(NodeKey, Vec<NodeKey>)> {
        self.select_nodes(camera, tau, false)
    }

    /// The leaves as [`StacksMesher::select`] chooses them; with `cull`, nodes outside the
    /// camera's view are not refined, and not returned (their neighbours still stitch to
    /// them as they are).
    fn select_nodes(&self, camera: &Camera, tau: f64, cull: bool) -> Vec<(NodeKey, Vec<NodeKey>)> {
        let roots: Vec<NodeKey> = self
            .nodes_of_level(self.level_count() - 1)
            .into_iter()
            .filter(|k| !self.is_empty(k))
            .collect();
        let leaves = Leaves::select(&roots, |key| {
            if self.is_empty(key) {
                return false;
            }
            let level = key.level as usize;
            let cell = self.lattices[level].step.max_element();
            let (lo, hi) = self.node_box(key);
            if cull && outside_view(camera, lo, hi) {
                return false;
            }
            let eye = camera.eye();
            let d = (eye.clamp(lo, hi) - eye).length();
            let footprint = camera.pixel_footprint(d);
            footprint <= 0.0 || cell / footprint > tau
        });
        leaves
            .coarser_neighbours()
            .into_iter()
            .filter(|(k, _)| !self.is_empty(k))
            .filter(|(k, _)| {
                let (lo, hi) = self.node_box(k);
                !(cull && outside_view(camera, lo, hi))
            })
            .collect()
    }

    /// The world box around a node's cells.
    fn node_box(&self, key: &NodeKey) -> (DVec3, DVec3) {
        let lattice = &self.lattices[key.level as usize];
        let o = key.origin(self.n());
        let lo = lattice.world(o.map(|c| (c - 1) as f64));
        let hi = lattice.world(o.map(|c| (c + self.n() + 1) as f64));
        (lo, hi)
    }

    /// The selected nodes' meshes for `camera` at screen-space error `tau` pixels, from the
    /// cache where a node with the same coarser neighbours was meshed before; the cache then
    /// keeps the nodes of this frame.
    fn frame_nodes(
        &mut self,
        camera: &Camera,
        tau: f64,
        cull: bool,
    ) -> (Vec<Arc<NodeMesh>>, MeshStats) {
        let start = Instant::now();
        let nodes = self.select_nodes(camera, tau, cull);
        let select_ms = ms(start);
        let start = Instant::now();
        let missing: Vec<&(NodeKey, Vec<NodeKey>)> =
            nodes.iter().filter(|k| !self.cache.contains_key(*k)).collect();
        let made: Vec<Arc<NodeMesh>> =
            missing.par_iter().map(|(k, c)| Arc::new(self.mesh_one(k, c))).collect();
        let mut stats = MeshStats {
            nodes: nodes.len(),
            meshed: made.len(),
            select_ms,
            mesh_ms: ms(start),
            ..Default::default()
        };
        for (key, mesh) in missing.into_iter().zip(made) {
            self.cache.insert(key.clone(), mesh);
        }
        for (k, _) in &nodes {
            stats.per_level[(k.level as usize).min(15)] += 1;
        }
        let keep: std::collections::HashSet<&(NodeKey, Vec<NodeKey>)> = nodes.iter().collect();
        self.cache.retain(|k, _| keep.contains(k));
        (nodes.iter().map(|k| self.cache[k].clone()).collect(), stats)
    }

    /// The mesh for `camera` at screen-space error `tau` pixels (see
    /// [`StacksMesher::select`]), each vertex once; node meshes come from the cache where a
    /// node with the same coarser neighbours was meshed for an earlier camera.
    pub fn mesh_for_camera(&mut self, camera: &Camera, tau: f64) -> (TerrainMesh, MeshStats) {
        let (meshes, mut stats) = self.frame_nodes(camera, tau, false);
        let start = Instant::now();
        let mesh = self.join(&meshes.iter().map(|m| m.as_ref()).collect::<Vec<_>>());
        stats.join_ms = ms(start);
        (mesh, stats)
    }

    /// The same nodes' meshes for drawing, those outside the camera's view left out: the
    /// solid, then the water, as triangle meshes with
    /// the colour (3 floats) then the normal (3 floats) per vertex. The nodes' meshes are
    /// appended as they are (a vertex a neighbouring node shares appears in both, at the same
    /// position), which the rasterizer needs no more.
    pub fn draw_meshes_for_camera(
        &mut self,
        camera: &Camera,
        tau: f64,
    ) -> Result<([IndexedMesh; 2], MeshStats), MeshError> {
        let (meshes, mut stats) = self.frame_nodes(camera, tau, true);
        let start = Instant::now();
        let solid = append_for_drawing(&meshes, 0)?;
        let water = append_for_drawing(&meshes, 1)?;
        stats.join_ms = ms(start);
        Ok(([solid, water], stats))
    }

    /// Meshes one node of `key`'s level next to the coarser leaves `coarser`.
    fn mesh_one(&self, key: &NodeKey, coarser: &[NodeKey]) -> NodeMesh {
        let level = key.level as usize;
        let n = self.n();
        let o = key.origin(n);
        let levels = self.mipmap.levels();
        let density = |l: usize, block: Block| {
            Density::new(&levels[l], &self.lattices[l], &self.channels, block, &self.kernel)
        };
        let fine = LevelField {
            level,
            lattice: &self.lattices[level],
            density: density(level, fine_block(o, n)),
        };
        let boxes: Vec<([i32; 3], [i32; 3])> = coarser
            .iter()
            .map(|c| {
                let origin = c.origin(n);
                (origin.map(|v| 2 * v), origin.map(|v| 2 * (v + n)))
            })
            .collect();
        let coarse = (!coarser.is_empty() && level + 1 < levels.len()).then(|| LevelField {
            level: level + 1,
            lattice: &self.lattices[level + 1],
            density: density(level + 1, coarse_block(o, n)),
        });
        let job = NodeJob {
            origin: o,
            n,
            coarser: &boxes,
            colors: &self.colors,
            liquid_color: self.liquid_color,
        };
        mesh_node(&job, &fine, coarse.as_ref())
    }

    /// Joins node meshes into one terrain mesh, each vertex once (by key).
    fn join(&self, meshes: &[&NodeMesh]) -> TerrainMesh {
        // The solid and the water are joined at the same time.
        let (solid, water) = rayon::join(
            || join_part(meshes, 0, MeshPart::new("solid", [1.0; 4])),
            || join_part(meshes, 1, MeshPart::new("water", [1.0, 1.0, 1.0, 0.7])),
        );
        TerrainMesh { parts: vec![solid, water] }
    }
}

/// Part `p` of the nodes' meshes joined into `part`, each vertex once (by key; a vertex only
/// one node makes needs no lookup).
fn join_part(meshes: &[&NodeMesh], p: usize, mut part: MeshPart) -> MeshPart {
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

/// How far beyond its points a node's density reaches with filter `kernel`: its cells' ring,
/// the Sobel neighbours and the filter's half-width.
fn node_reach(kernel: &[f32]) -> i32 {
    3 + (kernel.len() / 2) as i32
}

/// The node columns of one level (nodes `-1 ..= size / n` along x and y, x fastest), each
/// the union of the ranges of the stacks within `reach` of its points; a node column reaching
/// beyond the grid is never solid throughout.
fn node_columns(
    stacks: &relief_core::MaterialStacks,
    lattice: &Lattice,
    n: i32,
    reach: i32,
) -> (usize, Vec<ColumnRange>) {
    let (w, h) = (stacks.width() as i32, stacks.height() as i32);
    let columns: Vec<ColumnRange> = (0..stacks.height())
        .flat_map(|y| (0..stacks.width()).map(move |x| (x, y)))
        .map(|(x, y)| ColumnRange::of(stacks.stack(x, y), stacks.materials(), lattice))
        .collect();
    let nodes_x = (w.div_euclid(n) + 2) as usize;
    let nodes_y = (h.div_euclid(n) + 2) as usize;
    let mut out = Vec::with_capacity(nodes_x * nodes_y);
    for ny in 0..nodes_y as i32 {
        for nx in 0..nodes_x as i32 {
            let (ox, oy) = ((nx - 1) * n, (ny - 1) * n);
            let (lo_x, hi_x) = (ox - reach, ox + n + reach);
            let (lo_y, hi_y) = (oy - reach, oy + n + reach);
            let inside = lo_x >= 0 && lo_y >= 0 && hi_x <= w && hi_y <= h;
            let mut union = ColumnRange::EMPTY;
            union.solid_start = f32::NEG_INFINITY;
            union.solid_end = f32::INFINITY;
            for y in lo_y.max(0)..hi_y.min(h) {
                for x in lo_x.max(0)..hi_x.min(w) {
                    let c = &columns[(x + y * w) as usize];
                    union.start = union.start.min(c.start);
                    union.end = union.end.max(c.end);
                    union.solid_start = union.solid_start.max(c.solid_start);
                    union.solid_end = union.solid_end.min(c.solid_end);
                }
            }
            if !inside {
                union.solid_start = f32::INFINITY;
            }
            out.push(union);
        }
    }
    (nodes_x, out)
}

/// Where a column's layers lie, lattice k of its level: all of them, and the solid run from
/// its lowest layer up to the first gap or liquid.
#[derive(Debug, Clone, Copy)]
struct ColumnRange {
    start: f32,
    end: f32,
    solid_start: f32,
    solid_end: f32,
}

impl ColumnRange {
    /// A column with no layer.
    const EMPTY: ColumnRange = ColumnRange {
        start: f32::INFINITY,
        end: f32::NEG_INFINITY,
        solid_start: f32::INFINITY,
        solid_end: f32::NEG_INFINITY,
    };

    fn of(
        stack: &[relief_core::StackLayer],
        materials: &[relief_core::StackMaterial],
        lattice: &Lattice,
    ) -> Self {
        let (Some(first), Some(last)) = (stack.first(), stack.last()) else {
            return ColumnRange::EMPTY;
        };
        let mut solid_end = f32::NEG_INFINITY;
        let mut solid_start = f32::INFINITY;
        for layer in stack {
            let solid = !materials[layer.material as usize].is_liquid();
            if !solid || (solid_end.is_finite() && layer.start > solid_end) {
                break;
            }
            if solid_start.is_infinite() {
                solid_start = layer.start;
            }
            solid_end = layer.end;
        }
        let k = |z: f32| lattice.to_k(z) as f32;
        ColumnRange {
            start: k(first.start),
            end: k(last.end),
            solid_start: if solid_start.is_finite() { k(solid_start) } else { f32::INFINITY },
            solid_end: if solid_end.is_finite() { k(solid_end) } else { f32::NEG_INFINITY },
        }
    }
}

/// Part `part` of every node's mesh appended into one triangle mesh with colour and normal
/// attributes, the nodes filled in parallel at offsets from prefix sums.
fn append_for_drawing(meshes: &[Arc<NodeMesh>], part: usize) -> Result<IndexedMesh, MeshError> {
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

/// Whether the box `lo`..`hi` lies wholly outside the camera's view: all its corners behind
/// the eye, or beyond one side of the image.
fn outside_view(camera: &Camera, lo: DVec3, hi: DVec3) -> bool {
    let half_h = camera.half_height();
    let half_w = half_h * camera.width() as f64 / camera.height() as f64;
    let perspective = camera.fov_deg().is_some();
    let mut outside = [true; 5];
    for c in 0..8 {
        let p = DVec3::new(
            if c & 1 == 0 { lo.x } else { hi.x },
            if c & 2 == 0 { lo.y } else { hi.y },
            if c & 4 == 0 { lo.z } else { hi.z },
        );
        let d = p - camera.eye();
        let (x, y, z) = (d.dot(camera.right()), d.dot(camera.image_up()), d.dot(camera.forward()));
        let scale = if perspective { z.max(0.0) } else { 1.0 };
        let checks = [
            z < 0.0,
            x > scale * half_w,
            x < -scale * half_w,
            y > scale * half_h,
            y < -scale * half_h,
        ];
        for (o, check) in outside.iter_mut().zip(checks) {
            *o &= check;
        }
    }
    outside.iter().any(|&o| o)
}

fn ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// sRGB 8-bit to linear.
fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::{DVec2, MaterialStacks, StackLayer, StackMaterial};

    /// Rolling ground with an overhanging slab and a sand bank.
    fn terrain() -> MaterialStacks {
        let mut stacks = Vec::new();
        for y in 0..24 {
            for x in 0..24 {
                let ground = 6.0 + 2.0 * (x as f32 / 4.0).sin() * (y as f32 / 5.0).cos();
                let mut layers = vec![StackLayer::new(0.0, ground, 0)];
                if x > 14 {
                    layers.push(StackLayer::new(ground, ground + 1.5, 1));
                }
                if (6..16).contains(&x) && (4..18).contains(&y) {
                    layers.push(StackLayer::new(11.0, 14.0, 0));
                }
                stacks.push(layers);
            }
        }
        MaterialStacks::from_stacks(
            24,
            24,
            DVec2::ONE,
            DVec2::ZERO,
            StackMaterial::defaults(),
            &stacks,
        )
        .unwrap()
    }

    #[test]
    fn vertices_lie_on_the_smoothed_density_iso_surface() {
        let mesher = StacksMesher::new(
            StacksMipmap::new(terrain()),
            StacksMeshParams { node_cells: 6, ..Default::default() },
        )
        .unwrap();
        let (mesh, _) = mesher.mesh_level(0).unwrap();
        let lattice = &mesher.lattices[0];
        let block = Block::between([-4, -4, -4], [28, 28, 24]);
        let density = Density::new(
            &mesher.mipmap.levels()[0],
            lattice,
            &mesher.channels,
            block,
            &mesher.kernel,
        );
        let solid = mesh.part("solid").unwrap();
        assert!(solid.vertex_count() > 500);
        let mut worst = 0f64;
        for position in &solid.positions {
            let p = (*position - lattice.origin) / lattice.step;
            let cell = [p.x.floor() as i32, p.y.floor() as i32, p.z.floor() as i32];
            let local = [p.x - cell[0] as f64, p.y - cell[1] as f64, p.z - cell[2] as f64];
            // The trilinear interpolant of the density and its gradient at the vertex.
            let (mut f, mut g) = (0.0, DVec3::ZERO);
            for c in 0..8 {
                let bits = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
                let v = density.at(0, std::array::from_fn(|a| cell[a] + bits[a])) as f64;
                let w: [f64; 3] =
                    std::array::from_fn(|a| if bits[a] == 1 { local[a] } else { 1.0 - local[a] });
                f += v * w[0] * w[1] * w[2];
                let sign = |a: usize| if bits[a] == 1 { 1.0 } else { -1.0 };
                g +=
                    DVec3::new(sign(0) * w[1] * w[2], sign(1) * w[0] * w[2], sign(2) * w[0] * w[1])
                        * v;
            }
            // Distance to the iso-surface, first order, in cells.
            let distance = (f - 0.5).abs() / g.length().max(1e-9);
            worst = worst.max(distance);
        }
        println!("worst distance to the iso-surface: {worst:.3} cells");
        assert!(worst < 0.15, "a vertex lies {worst} cells off the iso-surface");
    }
}
