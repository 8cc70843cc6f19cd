//! The stacks mesher: the quadrangulation pipeline run over the octree's nodes, at one level of
//! detail or at the levels a camera asks for, node meshes cached across frames and joined into
//! one [`TerrainMesh`] of a `solid` and a `water` part.

use super::density::{Channels, Smoothing};
use super::lattice::Lattice;
use super::node_cache::{NodeCache, NodeMaking};
use super::node_columns::{node_columns, node_reach, ColumnRange};
use super::node_joins::{append_for_drawing, join_part};
use super::node_maker::NodeMaker;
use super::node_mesh::NodeMesh;
use super::octree::{Leaves, NodeKey};
use super::view_culling::outside_view;
use crate::{IndexedMesh, MeshError, MeshPart, TerrainMesh};
use rayon::prelude::*;
use relief_core::{Camera, DVec3, MaterialKind, StacksMipmap};
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
    /// Nodes whose mesh was made for this frame (not found in the cache): now, or ahead
    /// since the last frame (see [`StacksMesher::begin_meshing_ahead`]).
    pub meshed: usize,
    /// Nodes drawn by a stand-in, their own mesh still to make (past the node budget, see
    /// [`StacksMesher::set_node_budget`]).
    pub waiting: usize,
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
/// let mipmap = StacksMipmap::new(stacks).unwrap();
/// let mesher = StacksMesher::new(mipmap, StacksMeshParams::default()).unwrap();
/// let (mesh, _) = mesher.mesh_level(0).unwrap();
/// assert!(mesh.part("solid").unwrap().quads.len() > 0);
/// ```
#[derive(Debug)]
pub struct StacksMesher {
    /// What meshing a node reads (shared with the meshing done ahead, in the background).
    maker: Arc<NodeMaker>,
    params: StacksMeshParams,
    /// Lattice z of the highest layer end at level 0.
    top_k: f64,
    /// Per level: the width of its grid of node columns, and per node column where the
    /// layers within its reach lie (see [`ColumnRange`]).
    node_columns: Vec<(usize, Vec<ColumnRange>)>,
    cache: NodeCache,
    /// The last frame's solid and water for drawing (their buffers reused by the next).
    drawing: [IndexedMesh; 2],
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
        let kernels: Vec<Vec<f32>> =
            (0..lattices.len()).map(|l| params.smoothing.at_level(l).kernel()).collect();
        let liquid_kernels = (0..lattices.len())
            .map(|l| match params.smoothing.at_level(l) {
                Smoothing::Gaussian { sigma } if sigma < 0.75 => Smoothing::None,
                other => other,
            })
            .map(|s| s.kernel())
            .collect();
        let node_columns = mipmap
            .levels()
            .iter()
            .zip(&lattices)
            .zip(&kernels)
            .map(|((s, lattice), kernel)| node_columns(s, lattice, n, node_reach(kernel)))
            .collect();
        let (o, s) = (level0.origin(), level0.spacing());
        let domain =
            [[o.x, o.y], [o.x + s.x * level0.width() as f64, o.y + s.y * level0.height() as f64]];
        let maker = NodeMaker {
            mipmap,
            lattices,
            channels,
            kernels,
            liquid_kernels,
            colors,
            liquid_color,
            domain,
            n,
        };
        Ok(StacksMesher {
            maker: Arc::new(maker),
            top_k: (top as f64 - z0) / dz0,
            params,
            node_columns,
            cache: NodeCache::default(),
            drawing: Default::default(),
        })
    }

    /// The mipmap meshed.
    pub fn mipmap(&self) -> &StacksMipmap {
        &self.maker.mipmap
    }

    /// The parameters.
    pub fn params(&self) -> &StacksMeshParams {
        &self.params
    }

    /// Number of levels of detail (the mipmap's levels).
    pub fn level_count(&self) -> usize {
        self.maker.mipmap.levels().len()
    }

    fn n(&self) -> i32 {
        self.maker.n
    }

    /// The nodes of `level` that cover the terrain and the air ring around it.
    fn nodes_of_level(&self, level: usize) -> Vec<NodeKey> {
        let s = &self.maker.mipmap.levels()[level];
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
        node_reach(&self.maker.kernels[0])
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
        let meshes: Vec<NodeMesh> = nodes.par_iter().map(|(k, c)| self.maker.make(k, c)).collect();
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
            let cell = self.maker.lattices[level].step.max_element();
            // A node of the floor's ring (it holds the solid's flat bottom) is split as the
            // node above it is: a coarser node below would fit the lowest points of the
            // node above to its values, where thin layers near the floor lie.
            let (lo, hi) =
                self.node_box(&NodeKey { at: [key.at[0], key.at[1], key.at[2].max(0)], ..*key });
            if cull && outside_view(camera, lo, hi) {
                return false;
            }
            let eye = camera.eye();
            let d = (eye.clamp(lo, hi) - eye).length();
            let footprint = camera.pixel_footprint(d);
            footprint <= 0.0 || cell / footprint > tau
        });
        leaves
            .coarser_neighbours(|k| {
                let (lo, hi) = self.node_box(k);
                let unseen = cull && outside_view(camera, lo, hi);
                !(self.is_empty(k) || unseen)
            })
            .into_iter()
            .collect()
    }

    /// The world box around a node's cells.
    fn node_box(&self, key: &NodeKey) -> (DVec3, DVec3) {
        let lattice = &self.maker.lattices[key.level as usize];
        let o = key.origin(self.n());
        let lo = lattice.world(o.map(|c| (c - 1) as f64));
        let hi = lattice.world(o.map(|c| (c + self.n() + 1) as f64));
        (lo, hi)
    }

    /// The selected nodes' meshes for `camera` at screen-space error `tau` pixels, from the
    /// cache where a node with the same coarser neighbours was meshed before; the others made
    /// now, or, past the node budget (see [`StacksMesher::set_node_budget`]) when `amortised`,
    /// drawn by stand-ins from the last frame. The cache then keeps the nodes of this frame.
    fn frame_nodes(
        &mut self,
        camera: &Camera,
        tau: f64,
        cull: bool,
        amortised: bool,
    ) -> (Vec<Arc<NodeMesh>>, MeshStats) {
        let start = Instant::now();
        let nodes = self.select_nodes(camera, tau, cull);
        let select_ms = ms(start);
        let start = Instant::now();
        let mut cache = std::mem::take(&mut self.cache);
        let frame = cache.frame(&nodes, amortised, &self.making());
        self.cache = cache;
        let mut stats = MeshStats {
            nodes: nodes.len(),
            meshed: frame.meshed,
            waiting: frame.waiting,
            select_ms,
            mesh_ms: ms(start),
            ..Default::default()
        };
        for (k, _) in &nodes {
            stats.per_level[(k.level as usize).min(15)] += 1;
        }
        (frame.meshes, stats)
    }

    /// Sets how many node meshes a frame drawn by [`StacksMesher::draw_meshes_for_camera`]
    /// makes at most beyond those nothing drawn before can stand in for (`None`, the default:
    /// every node a frame wants). Nodes past the budget are drawn, until a later frame meshes
    /// them, by what the last frame drew in their place: the same node's mesh next to other
    /// neighbours, a coarser ancestor's mesh or finer descendants' meshes (as Löffler et al.
    /// amortise their updates, with the same popping and delayed level switches). Such a
    /// frame may show cracks and overlaps where a stand-in meets its neighbours; once the
    /// camera stays put long enough, every node has its own mesh and the frame is the one
    /// drawn without a budget.
    pub fn set_node_budget(&mut self, budget: Option<usize>) {
        self.cache.set_budget(budget);
    }

    /// Begins, on a thread of low priority, the node meshes the last frame drawn by
    /// [`StacksMesher::draw_meshes_for_camera`] chose to make ahead of the next (those past
    /// the node budget's share of this frame). Called once a frame is drawn, it overlaps
    /// their meshing with what the caller does until the next frame, which makes whatever is
    /// left; uncalled, the next frame makes them all. The frames are the same either way.
    pub fn begin_meshing_ahead(&mut self) {
        let making = self.making();
        self.cache.begin_ahead(&making);
    }

    /// Node meshing as the cache and the thread meshing ahead call it.
    fn making(&self) -> NodeMaking {
        let maker = self.maker.clone();
        Arc::new(move |key: &NodeKey, coarser: &[NodeKey]| maker.make(key, coarser))
    }

    /// The node budget of a frame (see [`StacksMesher::set_node_budget`]).
    pub fn node_budget(&self) -> Option<usize> {
        self.cache.budget()
    }

    /// The mesh for `camera` at screen-space error `tau` pixels (see
    /// [`StacksMesher::select`]), each vertex once; node meshes come from the cache where a
    /// node with the same coarser neighbours was meshed for an earlier camera.
    pub fn mesh_for_camera(&mut self, camera: &Camera, tau: f64) -> (TerrainMesh, MeshStats) {
        let (meshes, mut stats) = self.frame_nodes(camera, tau, false, false);
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
    ) -> Result<(&[IndexedMesh; 2], MeshStats), MeshError> {
        let (meshes, mut stats) = self.frame_nodes(camera, tau, true, true);
        let start = Instant::now();
        let [solid, water] = &mut self.drawing;
        append_for_drawing(&meshes, 0, solid)?;
        append_for_drawing(&meshes, 1, water)?;
        stats.join_ms = ms(start);
        Ok((&self.drawing, stats))
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
    use crate::stacks::density::Density;
    use crate::stacks::lattice::Block;
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
            StacksMipmap::new(terrain()).unwrap(),
            StacksMeshParams { node_cells: 6, ..Default::default() },
        )
        .unwrap();
        let (mesh, _) = mesher.mesh_level(0).unwrap();
        let maker = &mesher.maker;
        let lattice = &maker.lattices[0];
        let block = Block::between([-4, -4, -4], [28, 28, 24]);
        let density = Density::new(
            &maker.mipmap.levels()[0],
            lattice,
            &maker.channels,
            block,
            maker.kernels(0),
        );
        let solid = mesh.part("solid").unwrap();
        assert!(solid.vertex_count() > 500);
        let mut worst = 0f64;
        // Vertices on the terrain's sides are moved onto them, off the iso-surface.
        let on_side = |p: &DVec3| p.x == 0.0 || p.y == 0.0 || p.x == 24.0 || p.y == 24.0;
        for position in solid.positions.iter().filter(|p| !on_side(p)) {
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

    #[test]
    fn meshing_ahead_changes_no_frame() {
        let make = || {
            let params = StacksMeshParams { node_cells: 4, ..Default::default() };
            let mut mesher =
                StacksMesher::new(StacksMipmap::new(terrain()).unwrap(), params).unwrap();
            mesher.set_node_budget(Some(3));
            mesher
        };
        let camera = |x: f64| {
            let (eye, target) = (DVec3::new(x, -10.0, 20.0), DVec3::new(12.0, 12.0, 6.0));
            Camera::look_at(eye, target, DVec3::Z, 55.0, 80, 60).unwrap()
        };
        // One mesher begins meshing ahead after every frame, the other never does.
        let (mut ahead, mut plain) = (make(), make());
        let mut waited = 0;
        for x in [-90.0, -60.0, -40.0, -20.0, -8.0, -8.0, -8.0, -8.0] {
            let (got, got_stats) = ahead.draw_meshes_for_camera(&camera(x), 3.0).unwrap();
            let got = got.clone();
            ahead.begin_meshing_ahead();
            let (want, want_stats) = plain.draw_meshes_for_camera(&camera(x), 3.0).unwrap();
            assert!(got == *want, "the frame at x = {x} differs");
            assert_eq!(
                (got_stats.meshed, got_stats.waiting),
                (want_stats.meshed, want_stats.waiting)
            );
            waited += got_stats.waiting;
        }
        assert!(waited > 0, "some nodes waited for their turn");
    }
}
