//! The vertices of one part of a node: made on first use and named by key, at the mean of
//! their patch's edge crossings (or on a saddle face, or on an edge), with the density's
//! Sobel gradient as normal and the materials' densities as colour.

use super::cell_patches::{edge_corners, edge_index, face_saddle, other_axes, CellPatches};
use super::fitted_field::{corner, Field};
use super::lattice::Block;
use super::node_mesh::{vertex_key, LevelField, NodeJob, NodePart, ISO};
use relief_core::DVec3;
use rustc_hash::FxHashMap as HashMap;

/// A cell's corner values of `channel`, corner `c` at `cell + bits(c)`.
fn corner_values(at: impl Fn([i32; 3]) -> f32, cell: [i32; 3]) -> [f32; 8] {
    std::array::from_fn(|c| at(corner(cell, c)))
}

/// The vertices of one part of a node, made on first use and named by key.
pub(crate) struct VertexTable<'a> {
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
    /// The vertices made so far.
    pub part: NodePart,
}

impl<'a> VertexTable<'a> {
    /// An empty table for `channel` of `field`, the node of `job`.
    pub(crate) fn new(job: &'a NodeJob<'a>, field: &'a Field<'a>, channel: usize) -> Self {
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
    pub(crate) fn resolve(&self, cell: [i32; 3], p: [i32; 3]) -> Resolved {
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
    pub(crate) fn patch_vertex(&mut self, r: Resolved, axis: usize) -> u32 {
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
        // The mean of the patch's edge crossings; for the liquid, along each axis the mean of
        // the crossings of the edges along that axis where there are some.
        let values = values(self);
        let mut sum = [0f64; 3];
        let mut count = 0;
        let mut along = [(0f64, 0u32); 3];
        for e in (0..12).filter(|&e| patches.of_edge[e] == patch) {
            let (a, b) = edge_corners(e);
            let edge_axis = (a ^ b).trailing_zeros() as usize;
            let t = self
                .fitted_crossing(r, a, b, edge_axis)
                .unwrap_or_else(|| self.crossing(r.snapped, edge_axis, values[a], values[b]));
            for (axis, s) in sum.iter_mut().enumerate() {
                let from = ((a >> axis) & 1) as f64;
                let at = from + t * (((b >> axis) & 1) as f64 - from);
                *s += at;
                if axis == edge_axis {
                    along[axis].0 += at;
                    along[axis].1 += 1;
                }
            }
            count += 1;
        }
        let local: [f64; 3] = std::array::from_fn(|a| match along[a] {
            (at, n) if self.channel == 1 && n > 0 => at / n as f64,
            _ => sum[a] / count as f64,
        });
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
    pub(crate) fn saddle_vertex(
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
            let along = (0..3).find(|&a| lo[a] != hi[a]).expect("an edge");
            let t = self.crossing(snapped, along, vlo, vhi);
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
    pub(crate) fn edge_vertex(&mut self, snapped: bool, p: [i32; 3], axis: usize) -> u32 {
        let key = vertex_key(self.level(snapped).level, p, 0x40 | axis as u8);
        if let Some(&v) = self.index.get(&key) {
            return v;
        }
        let mut q = p;
        q[axis] += 1;
        let channel = self.channel;
        let t = self.crossing(
            snapped,
            axis,
            self.read(snapped, channel, p),
            self.read(snapped, channel, q),
        );
        let mut local = [0.0; 3];
        local[axis] = t;
        let v = self.add_vertex(key, true, snapped, p, local);
        self.index.insert(key, v);
        v
    }

    /// Where the surface crosses the edge from corner `a` to corner `b` (along `axis`) of the
    /// fine cell `r`, when both ends took the coarser level's values (topology fitting): at
    /// the coarser edge's own crossing, as a fraction of the fine edge (it may lie outside it).
    /// Fitting repeats each coarser value on two fine points, so interpolating the fine edge
    /// would move the crossing by up to a fine step off the coarser level's (a ledge where the
    /// levels meet) and make a sheet thinner than a coarser step a fine step thicker.
    fn fitted_crossing(&self, r: Resolved, a: usize, b: usize, axis: usize) -> Option<f64> {
        let coarse = self.field.coarse.filter(|_| !r.snapped)?;
        let (pa, pb) = (corner(r.cell, a), corner(r.cell, b));
        if !(self.field.fitted(pa) && self.field.fitted(pb)) {
            return None;
        }
        let (qa, qb) = (pa.map(|c| c.div_euclid(2)), pb.map(|c| c.div_euclid(2)));
        if qa == qb {
            return None;
        }
        let read = |q: [i32; 3]| coarse.density.at(self.channel, q);
        let t = self.crossing(true, axis, read(qa), read(qb));
        // The coarser crossing in fine units, from the fine edge's start.
        Some(2.0 * (qa[axis] as f64 + t) - pa[axis] as f64)
    }

    /// Where the iso-surface crosses the lattice edge along `axis` from a point of value
    /// `from` to its upper neighbour of value `to`, as a fraction of the edge: by linear
    /// interpolation, except, at a level not smoothed (coarse levels), the liquid's edges across
    /// the columns, crossed half-way: its shore then lies between a wet stack and a dry one,
    /// as the stacks have it, not where a layer's depth would put it. Its vertices are placed as
    /// dual contouring's QEF places them on box-like data (Ju et al. 2002): each crossing's
    /// normal is its edge's axis, so each coordinate is the mean of the crossings on the
    /// edges along that axis, and a sheet keeps its depth up to its shore.
    fn crossing(&self, snapped: bool, axis: usize, from: f32, to: f32) -> f64 {
        if self.channel == 1 && axis < 2 && !self.level(snapped).smoothed {
            0.5
        } else {
            crossing(from, to)
        }
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
        let mut position = lattice.world(std::array::from_fn(|a| base[a] as f64 + local[a]));
        // A vertex in a cell the terrain's side crosses lies on that side: the mesh's
        // footprint is the terrain's at every level.
        for (a, step) in [lattice.step.x, lattice.step.y].into_iter().enumerate() {
            for edge in [self.job.domain[0][a], self.job.domain[1][a]] {
                let u = (edge - lattice.origin[a]) / step;
                let cell = u.floor();
                let at = (position[a] - lattice.origin[a]) / step;
                if u > cell && at >= cell && at <= cell + 1.0 {
                    position[a] = edge;
                }
            }
        }
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
pub(crate) struct Resolved {
    /// Whether the cell is the coarser level's.
    pub snapped: bool,
    /// The cell, on its level's grid.
    pub cell: [i32; 3],
    /// The quad's edge start, on the same grid.
    pub edge: [i32; 3],
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
