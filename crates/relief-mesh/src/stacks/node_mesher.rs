//! The quadrangulation of one octree node (sections 3.2.3 to 3.2.5 and 3.4): its density with
//! the finer side's border fitted to a coarser neighbour, the classification of its cells, the
//! allocation of vertices and faces by prefix sums, the vertex attributes and the faces.
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

use super::cell_patches::{edge_corners, edge_index, other_axes, CellPatches};
use super::density::{Channels, Density};
use super::lattice::{Block, Lattice};
use relief_core::DVec3;
use rustc_hash::FxHashMap as HashMap;
use std::borrow::Cow;

/// The iso-value of the density: half covered.
pub(crate) const ISO: f32 = 0.5;

/// One part's mesh made by one node: vertices named by key, faces in local indices.
#[derive(Debug, Clone, Default)]
pub(crate) struct NodePart {
    /// The key of each vertex (see [`vertex_key`]).
    pub keys: Vec<u128>,
    /// Whether another node may make the same vertex: a cell on the node's border (its ring
    /// of overlap, or its last cell, which is the next node's ring) or of a coarser level.
    pub shared: Vec<bool>,
    /// Positions, world.
    pub positions: Vec<DVec3>,
    /// Unit normals pointing out of the volume.
    pub normals: Vec<[f32; 3]>,
    /// Linear RGB colours.
    pub colors: Vec<[f32; 3]>,
    /// Quads, counter-clockwise from outside.
    pub quads: Vec<[u32; 4]>,
    /// Triangles where stitching collapsed a corner.
    pub triangles: Vec<[u32; 3]>,
}

/// The meshes of one node: the solid, then the liquid.
#[derive(Debug, Clone, Default)]
pub(crate) struct NodeMesh {
    /// Solid then water.
    pub parts: [NodePart; 2],
}

/// The name of the vertex of patch `patch` of cell `cell` at `level`.
#[inline]
pub(crate) fn vertex_key(level: usize, cell: [i32; 3], patch: u8) -> u128 {
    ((level as u128) << 112)
        | ((patch as u128) << 96)
        | ((cell[0] as u32 as u128) << 64)
        | ((cell[1] as u32 as u128) << 32)
        | (cell[2] as u32 as u128)
}

/// One level's data a node reads: its lattice and density.
pub(crate) struct LevelField<'a> {
    /// The level's index, 0 finest.
    pub level: usize,
    /// Where its points lie.
    pub lattice: &'a Lattice,
    /// Its density over the block the node needs.
    pub density: Density,
}

/// What the meshing of a node needs besides the densities.
pub(crate) struct NodeJob<'a> {
    /// The node's first own lattice point.
    pub origin: [i32; 3],
    /// Cells per axis.
    pub n: i32,
    /// Lattice boxes (closed, in this node's level's points) of the coarser neighbours.
    pub coarser: &'a [([i32; 3], [i32; 3])],
    /// The density channels.
    pub channels: &'a Channels,
    /// Linear colour of each per-material channel's material.
    pub colors: &'a [[f32; 3]],
    /// Linear colour of the liquid.
    pub liquid_color: [f32; 3],
}

/// The lattice points a node's own level must cover: its cells' corners and their Sobel
/// neighbours.
pub(crate) fn fine_block(origin: [i32; 3], n: i32) -> Block {
    Block::between(origin.map(|o| o - 2), origin.map(|o| o + n + 2))
}

/// The coarser level's points a node with coarser neighbours needs.
pub(crate) fn coarse_block(origin: [i32; 3], n: i32) -> Block {
    Block::between(
        origin.map(|o| (o - 2).div_euclid(2) - 1),
        origin.map(|o| (o + n + 1).div_euclid(2) + 3),
    )
}

/// The field a node contours: its level's density with the fitted points replaced.
struct Field<'a> {
    fine: &'a LevelField<'a>,
    coarse: Option<&'a LevelField<'a>>,
    fitted: Vec<bool>,
    /// Fitted values, channel-major, over the fine block.
    values: Cow<'a, [Vec<f32>]>,
}

impl Field<'_> {
    #[inline]
    fn at(&self, channel: usize, p: [i32; 3]) -> f32 {
        self.values[channel][self.fine.density.block.index_of(p)]
    }

    #[inline]
    fn fitted(&self, p: [i32; 3]) -> bool {
        self.fitted[self.fine.density.block.index_of(p)]
    }
}

/// Meshes one node.
pub(crate) fn mesh_node(job: &NodeJob, fine: &LevelField, coarse: Option<&LevelField>) -> NodeMesh {
    let block = fine.density.block;
    let mut fitted = Vec::new();
    let mut values = Cow::Borrowed(fine.density.channels.as_slice());
    if let Some(coarse) = coarse {
        fitted = vec![false; block.len()];
        let values = values.to_mut();
        for (i, flag) in fitted.iter_mut().enumerate() {
            let p = block.point(i);
            let in_band = job
                .coarser
                .iter()
                .any(|(lo, hi)| (0..3).all(|a| p[a] >= lo[a] - 2 && p[a] <= hi[a] + 2));
            if in_band {
                *flag = true;
                let q = p.map(|c| c.div_euclid(2));
                for (channel, v) in values.iter_mut().enumerate() {
                    v[i] = coarse.density.at(channel, q);
                }
            }
        }
    }
    let field = Field { fine, coarse, fitted, values };
    let mut mesh = NodeMesh::default();
    for (part, channel) in [(0, 0), (1, 1)] {
        mesh.parts[part] = mesh_part(job, &field, channel);
    }
    mesh
}

/// A cell's corner values of `channel`, corner `c` at `cell + bits(c)`.
fn corner_values(at: impl Fn([i32; 3]) -> f32, cell: [i32; 3]) -> [f32; 8] {
    std::array::from_fn(|c| at(corner(cell, c)))
}

#[inline]
fn corner(cell: [i32; 3], c: usize) -> [i32; 3] {
    [cell[0] + (c & 1) as i32, cell[1] + ((c >> 1) & 1) as i32, cell[2] + ((c >> 2) & 1) as i32]
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
            // The four cells around the edge, counter-clockwise seen from +axis.
            let mut quad = [0u32; 4];
            for (k, (db, dc)) in [(-1, -1), (0, -1), (0, 0), (-1, 0)].into_iter().enumerate() {
                let mut cell = p;
                cell[b] += db;
                cell[c] += dc;
                quad[k] = vertices.vertex(cell, axis, p);
            }
            if !inside {
                quad.reverse();
            }
            faces[slot] = quad;
            slot += 1;
        }
    }
    let NodePart { keys, shared, positions, normals, colors, .. } = vertices.part;
    part.keys = keys;
    part.shared = shared;
    part.positions = positions;
    part.normals = normals;
    part.colors = colors;
    for quad in faces {
        push_face(&mut part, quad);
    }
    part
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

/// The vertices of one part of a node, made on first use and named by key.
struct VertexTable<'a> {
    job: &'a NodeJob<'a>,
    field: &'a Field<'a>,
    channel: usize,
    index: HashMap<u128, u32>,
    patches: HashMap<(usize, [i32; 3]), CellPatches>,
    part: NodePart,
}

impl<'a> VertexTable<'a> {
    fn new(job: &'a NodeJob<'a>, field: &'a Field<'a>, channel: usize) -> Self {
        VertexTable {
            job,
            field,
            channel,
            index: HashMap::default(),
            patches: HashMap::default(),
            part: NodePart::default(),
        }
    }

    /// The vertex of the patch of `cell` that the lattice edge from `p` along `axis` crosses.
    fn vertex(&mut self, cell: [i32; 3], axis: usize, p: [i32; 3]) -> u32 {
        let field = self.field;
        let snapped = field.coarse.is_some() && (0..8).all(|c| field.fitted(corner(cell, c)));
        let (level_field, cell, p) = if snapped {
            // The fitted border meshes as the coarser level: the edge is the coarser edge
            // from floor(p / 2), the cell the coarser cell floor(cell / 2).
            let coarse = field.coarse.expect("fitted points have a coarser level");
            (coarse, cell.map(|c| c.div_euclid(2)), p.map(|c| c.div_euclid(2)))
        } else {
            (field.fine, cell, p)
        };
        let offset = std::array::from_fn(|a| p[a] - cell[a]);
        debug_assert!(offset.iter().all(|&d| d == 0 || d == 1), "{offset:?}");
        let e = edge_index(axis, offset);
        let channel = self.channel;
        let corner_values_here = || {
            if snapped {
                corner_values(|q| level_field.density.at(channel, q), cell)
            } else {
                corner_values(|q| field.at(channel, q), cell)
            }
        };
        let patches = *self
            .patches
            .entry((level_field.level, cell))
            .or_insert_with(|| CellPatches::new(&corner_values_here(), ISO));
        let patch = patches.of_edge[e];
        debug_assert_ne!(patch, CellPatches::NONE, "edge {e} of cell {cell:?} is not crossed");
        let key = vertex_key(level_field.level, cell, patch);
        if let Some(&v) = self.index.get(&key) {
            return v;
        }
        let v = self.part.keys.len() as u32;
        self.index.insert(key, v);
        self.part.keys.push(key);
        let (o, n) = (self.job.origin, self.job.n);
        self.part.shared.push(snapped || (0..3).any(|a| cell[a] < o[a] || cell[a] >= o[a] + n - 1));
        let read = |ch: usize, q: [i32; 3]| {
            if snapped {
                level_field.density.at(ch, q)
            } else {
                field.at(ch, q)
            }
        };
        let values = corner_values_here();
        let (position, normal, color) =
            self.attributes(level_field.lattice, cell, &values, &patches, patch, &read);
        self.part.positions.push(position);
        self.part.normals.push(normal);
        self.part.colors.push(color);
        v
    }

    /// Position (the mean of the patch's edge crossings), normal (the 3D Sobel gradient,
    /// interpolated) and colour (the materials' smoothed densities, interpolated) of a vertex.
    fn attributes(
        &self,
        lattice: &Lattice,
        cell: [i32; 3],
        values: &[f32; 8],
        patches: &CellPatches,
        patch: u8,
        read: &dyn Fn(usize, [i32; 3]) -> f32,
    ) -> (DVec3, [f32; 3], [f32; 3]) {
        let mut sum = [0f64; 3];
        let mut count = 0;
        for e in 0..12 {
            if patches.of_edge[e] != patch {
                continue;
            }
            let (a, b) = edge_corners(e);
            let t = ((ISO - values[a]) / (values[b] - values[a])) as f64;
            for (axis, s) in sum.iter_mut().enumerate() {
                let from = ((a >> axis) & 1) as f64;
                let to = ((b >> axis) & 1) as f64;
                *s += from + t * (to - from);
            }
            count += 1;
        }
        let local = sum.map(|s| s / count as f64);
        let weights = trilinear(local);
        let position = lattice.world(std::array::from_fn(|a| cell[a] as f64 + local[a]));

        let mut gradient = DVec3::ZERO;
        for (c, &w) in weights.iter().enumerate() {
            if w != 0.0 {
                gradient += sobel(read, self.channel, corner(cell, c)) * w;
            }
        }
        let gradient = gradient / lattice.step;
        let normal = if gradient.length_squared() > 0.0 {
            (-gradient.normalize()).as_vec3().to_array()
        } else {
            [0.0, 0.0, 1.0]
        };

        let color = if self.channel == 1 {
            self.job.liquid_color
        } else {
            let mut rgb = [0f64; 3];
            let mut total = 0.0;
            for (m, color) in self.job.colors.iter().enumerate() {
                let mut w_m = 0.0;
                for (c, &w) in weights.iter().enumerate() {
                    w_m += w * read(2 + m, corner(cell, c)).max(0.0) as f64;
                }
                total += w_m;
                for k in 0..3 {
                    rgb[k] += w_m * color[k] as f64;
                }
            }
            if total > 0.0 {
                rgb.map(|v| (v / total) as f32)
            } else {
                self.job.colors.first().copied().unwrap_or([0.5; 3])
            }
        };
        let _ = self.job.channels;
        (position, normal, color)
    }
}

/// Trilinear weights of the eight corners at local coordinates `l`.
fn trilinear(l: [f64; 3]) -> [f64; 8] {
    std::array::from_fn(|c| {
        (0..3).map(|a| if (c >> a) & 1 == 1 { l[a] } else { 1.0 - l[a] }).product()
    })
}

/// The 3D Sobel gradient of a channel at lattice point `p`, lattice units.
fn sobel(read: &dyn Fn(usize, [i32; 3]) -> f32, channel: usize, p: [i32; 3]) -> DVec3 {
    let mut g = [0f64; 3];
    for (axis, out) in g.iter_mut().enumerate() {
        let (b, c) = other_axes(axis);
        for db in -1..=1i32 {
            for dc in -1..=1i32 {
                let w = ((2 - db.abs()) * (2 - dc.abs())) as f64;
                let mut q = p;
                q[b] += db;
                q[c] += dc;
                let mut hi = q;
                hi[axis] += 1;
                let mut lo = q;
                lo[axis] -= 1;
                *out += w * (read(channel, hi) - read(channel, lo)) as f64;
            }
        }
    }
    DVec3::from_array(g) / 32.0
}
