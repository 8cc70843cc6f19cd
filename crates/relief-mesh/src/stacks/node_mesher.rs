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

use super::cell_patches::{edge_corners, edge_index, face_saddle, other_axes, CellPatches};
use super::density::Density;
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

/// The vertices of one part of a node, made on first use and named by key.
struct VertexTable<'a> {
    job: &'a NodeJob<'a>,
    field: &'a Field<'a>,
    channel: usize,
    index: HashMap<u128, u32>,
    patches: HashMap<(usize, [i32; 3]), CellPatches>,
    /// The node's own cells (`[o - 1, o + n)` along each axis, unsnapped): their patches and
    /// their patch vertices, looked up without hashing.
    own_cells: Block,
    own_patches: Vec<Option<CellPatches>>,
    own_vertices: Vec<[u32; 4]>,
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
            own_cells: Block::between(job.origin.map(|c| c - 1), job.origin.map(|c| c + job.n)),
            own_patches: vec![None; ((job.n + 1) as usize).pow(3)],
            own_vertices: vec![[u32::MAX; 4]; ((job.n + 1) as usize).pow(3)],
            part: NodePart::default(),
        }
    }

    /// The cell a quad corner takes: `cell` itself, or, when all its corners are fitted, the
    /// coarser cell `floor(cell / 2)`; with the quad's edge start `p` on the same grid.
    fn resolve(&self, cell: [i32; 3], p: [i32; 3]) -> Resolved {
        let field = self.field;
        let snapped = field.coarse.is_some() && (0..8).all(|c| field.fitted(corner(cell, c)));
        if snapped {
            // The fitted border meshes as the coarser level: the edge is the coarser edge
            // from floor(p / 2), the cell the coarser cell floor(cell / 2).
            Resolved {
                snapped,
                cell: cell.map(|c| c.div_euclid(2)),
                edge: p.map(|c| c.div_euclid(2)),
            }
        } else {
            Resolved { snapped, cell, edge: p }
        }
    }

    /// The level a resolved cell belongs to.
    fn level(&self, snapped: bool) -> &'a LevelField<'a> {
        if snapped {
            self.field.coarse.expect("snapped cells have a coarser level")
        } else {
            self.field.fine
        }
    }

    /// Channel `ch` at lattice point `q` of the fine (fitted) or the coarser field.
    #[inline]
    fn read(&self, snapped: bool, ch: usize, q: [i32; 3]) -> f32 {
        if snapped {
            self.level(true).density.at(ch, q)
        } else {
            self.field.at(ch, q)
        }
    }

    /// The vertex of the patch of cell `r` that the lattice edge from `r.edge` along `axis`
    /// crosses.
    fn patch_vertex(&mut self, r: Resolved, axis: usize) -> u32 {
        let level = self.level(r.snapped);
        let offset = std::array::from_fn(|a| r.edge[a] - r.cell[a]);
        debug_assert!(offset.iter().all(|&d| d == 0 || d == 1), "{offset:?}");
        let e = edge_index(axis, offset);
        let channel = self.channel;
        let values = |table: &Self| corner_values(|q| table.read(r.snapped, channel, q), r.cell);
        let own = (!r.snapped).then(|| self.own_cells.index_of(r.cell));
        let cached = match own {
            Some(i) => self.own_patches[i],
            None => self.patches.get(&(level.level, r.cell)).copied(),
        };
        let patches = match cached {
            Some(patches) => patches,
            None => {
                let patches = CellPatches::new(&values(self), ISO);
                match own {
                    Some(i) => self.own_patches[i] = Some(patches),
                    None => {
                        self.patches.insert((level.level, r.cell), patches);
                    }
                }
                patches
            }
        };
        let patch = patches.of_edge[e];
        debug_assert_ne!(patch, CellPatches::NONE, "edge {e} of cell {:?} is not crossed", r.cell);
        let key = vertex_key(level.level, r.cell, patch);
        match own {
            Some(i) if self.own_vertices[i][patch as usize] != u32::MAX => {
                return self.own_vertices[i][patch as usize]
            }
            None => {
                if let Some(&v) = self.index.get(&key) {
                    return v;
                }
            }
            _ => {}
        }
        // The mean of the patch's edge crossings.
        let values = values(self);
        let mut sum = [0f64; 3];
        let mut count = 0;
        for e in (0..12).filter(|&e| patches.of_edge[e] == patch) {
            let (a, b) = edge_corners(e);
            let t = crossing(values[a], values[b]);
            for (axis, s) in sum.iter_mut().enumerate() {
                let from = ((a >> axis) & 1) as f64;
                *s += from + t * (((b >> axis) & 1) as f64 - from);
            }
            count += 1;
        }
        let local = sum.map(|s| s / count as f64);
        let (o, n) = (self.job.origin, self.job.n);
        let shared = r.snapped || (0..3).any(|a| r.cell[a] < o[a] || r.cell[a] >= o[a] + n - 1);
        let v = self.add_vertex(key, shared, r.snapped, r.cell, local);
        match own {
            Some(i) => self.own_vertices[i][patch as usize] = v,
            None => {
                self.index.insert(key, v);
            }
        }
        v
    }

    /// The vertex of the crossing of a saddle face that the lattice edge from `p` along
    /// `axis` takes part in: the face spans `axis` and the unit step `towards`; `None` when the
    /// face is no saddle (two of its edges crossed, not four).
    fn saddle_vertex(
        &mut self,
        snapped: bool,
        p: [i32; 3],
        axis: usize,
        towards: [i32; 3],
    ) -> Option<u32> {
        let step = |q: [i32; 3], d: [i32; 3]| -> [i32; 3] { std::array::from_fn(|a| q[a] + d[a]) };
        let mut unit = [0; 3];
        unit[axis] = 1;
        let q = [p, step(p, unit), step(step(p, unit), towards), step(p, towards)];
        let channel = self.channel;
        let v = q.map(|x| self.read(snapped, channel, x));
        let inside = v.map(|x| x > ISO);
        if !(inside[0] != inside[1] && inside[2] == inside[0] && inside[3] == inside[1]) {
            return None;
        }
        // Corners 0 and 2 joined across the face: corners 1 and 3 are cut off, this edge's
        // crossing pairs with the one of edge 1-2; else with the one of edge 3-0.
        let first_joined = (face_saddle(v) > ISO) == inside[0];
        let (cut, partner) = if first_joined { (1, (1, 2)) } else { (0, (3, 0)) };
        let face_min: [i32; 3] = std::array::from_fn(|a| p[a] + towards[a].min(0));
        let normal_axis = 3 - axis - (0..3).find(|&a| towards[a] != 0).expect("a step");
        let (t0, t1) = other_axes(normal_axis);
        let corner_bits = (q[cut][t0] - face_min[t0]) | ((q[cut][t1] - face_min[t1]) << 1);
        let key = vertex_key(
            self.level(snapped).level,
            face_min,
            0x80 | ((normal_axis as u8) << 4) | corner_bits as u8,
        );
        if let Some(&v) = self.index.get(&key) {
            return Some(v);
        }
        let point = |x: [i32; 3], y: [i32; 3], vx: f32, vy: f32| -> [f64; 3] {
            // From the lower end, as every crossing is computed.
            let (lo, hi, vlo, vhi) = if x < y { (x, y, vx, vy) } else { (y, x, vy, vx) };
            let t = crossing(vlo, vhi);
            std::array::from_fn(|a| (lo[a] - face_min[a]) as f64 + t * (hi[a] - lo[a]) as f64)
        };
        let m = point(q[0], q[1], v[0], v[1]);
        let n = point(q[partner.0], q[partner.1], v[partner.0], v[partner.1]);
        let local = std::array::from_fn(|a| 0.5 * (m[a] + n[a]));
        let v = self.add_vertex(key, true, snapped, face_min, local);
        self.index.insert(key, v);
        Some(v)
    }

    /// The vertex at the crossing of the lattice edge from `p` along `axis`.
    fn edge_vertex(&mut self, snapped: bool, p: [i32; 3], axis: usize) -> u32 {
        let key = vertex_key(self.level(snapped).level, p, 0x40 | axis as u8);
        if let Some(&v) = self.index.get(&key) {
            return v;
        }
        let mut q = p;
        q[axis] += 1;
        let channel = self.channel;
        let t = crossing(self.read(snapped, channel, p), self.read(snapped, channel, q));
        let mut local = [0.0; 3];
        local[axis] = t;
        let v = self.add_vertex(key, true, snapped, p, local);
        self.index.insert(key, v);
        v
    }

    /// Adds the vertex `key` (its caller remembers it) at `local` coordinates of the cell from
    /// `base`: its position,
    /// normal (the 3D Sobel gradient of the density, interpolated) and colour (the materials'
    /// densities, interpolated).
    fn add_vertex(
        &mut self,
        key: u128,
        shared: bool,
        snapped: bool,
        base: [i32; 3],
        local: [f64; 3],
    ) -> u32 {
        let lattice = self.level(snapped).lattice;
        let weights = trilinear(local);
        let position = lattice.world(std::array::from_fn(|a| base[a] as f64 + local[a]));
        let read = |ch: usize, q: [i32; 3]| self.read(snapped, ch, q);
        // The 4 x 4 x 4 points around the cell, read once: the Sobel gradients of its corners.
        let (block, values) = if snapped {
            let level = self.level(true);
            (level.density.block, &level.density.channels[self.channel][..])
        } else {
            (self.field.fine.density.block, &self.field.values[self.channel][..])
        };
        let first = block.index_of(base.map(|c| c - 1));
        let (sy, sz) = (block.size[0], block.size[0] * block.size[1]);
        let mut around = [[[0f32; 4]; 4]; 4];
        for (k, plane) in around.iter_mut().enumerate() {
            for (j, row) in plane.iter_mut().enumerate() {
                let start = first + k * sz + j * sy;
                row.copy_from_slice(&values[start..start + 4]);
            }
        }
        let corners = sobel(&around);
        let mut gradient = DVec3::ZERO;
        for (c, &w) in weights.iter().enumerate() {
            gradient += corners[c] * w;
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
                    if w != 0.0 {
                        w_m += w * read(2 + m, corner(base, c)).max(0.0) as f64;
                    }
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
        let v = self.part.keys.len() as u32;
        self.part.keys.push(key);
        self.part.shared.push(shared);
        self.part.positions.push(position);
        self.part.normals.push(normal);
        self.part.colors.push(color);
        v
    }
}

/// Where the iso-surface crosses the lattice edge from a point of value `from` to its upper
/// neighbour of value `to`, as a fraction of the edge.
#[inline]
fn crossing(from: f32, to: f32) -> f64 {
    ((ISO - from) / (to - from)) as f64
}

/// A quad corner's cell as the mesh takes it: the node's own level's, or the coarser cell a
/// cell of fitted corners takes (`snapped`), with the quad's edge start on the same grid.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Resolved {
    snapped: bool,
    cell: [i32; 3],
    edge: [i32; 3],
}

/// Trilinear weights of the eight corners at local coordinates `l`.
fn trilinear(l: [f64; 3]) -> [f64; 8] {
    std::array::from_fn(|c| {
        (0..3).map(|a| if (c >> a) & 1 == 1 { l[a] } else { 1.0 - l[a] }).product()
    })
}

/// The 3D Sobel gradients, lattice units, at the eight corners of the cell whose 4 x 4 x 4
/// surrounding points are `around` (`around[z][y][x]`, the cell's corner 0 at index 1):
/// central differences along each axis, smoothed by (1, 2, 1) along the other two.
// The indices name lattice positions; iterators would hide which is which.
#[allow(clippy::needless_range_loop)]
fn sobel(around: &[[[f32; 4]; 4]; 4]) -> [DVec3; 8] {
    let g = |x: usize, y: usize, z: usize| around[z][y][x];
    let mut out = [[0f32; 3]; 8];
    for axis in 0..3 {
        // Differences along `axis` at the two inner positions of that axis, all positions of
        // the other two; then (1, 2, 1) along each of them at their inner positions.
        let mut d = [[[0f32; 4]; 4]; 2];
        for (i, plane) in d.iter_mut().enumerate() {
            for (u, row) in plane.iter_mut().enumerate() {
                for (v, value) in row.iter_mut().enumerate() {
                    let (hi, lo) = match axis {
                        0 => (g(i + 2, u, v), g(i, u, v)),
                        1 => (g(u, i + 2, v), g(u, i, v)),
                        _ => (g(u, v, i + 2), g(u, v, i)),
                    };
                    *value = hi - lo;
                }
            }
        }
        for i in 0..2 {
            for u in 0..2 {
                for v in 0..2 {
                    let mut sum = 0f32;
                    for (du, wu) in [1f32, 2.0, 1.0].into_iter().enumerate() {
                        for (dv, wv) in [1f32, 2.0, 1.0].into_iter().enumerate() {
                            sum += wu * wv * d[i][u + du][v + dv];
                        }
                    }
                    // Corner bits: x in bit 0, y in bit 1, z in bit 2; (u, v) are the other
                    // two axes in increasing order.
                    let (x, y, z) = match axis {
                        0 => (i, u, v),
                        1 => (u, i, v),
                        _ => (u, v, i),
                    };
                    out[x | (y << 1) | (z << 2)][axis] = sum / 32.0;
                }
            }
        }
    }
    out.map(|g| DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64))
}
