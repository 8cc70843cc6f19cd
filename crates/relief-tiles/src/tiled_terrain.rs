//! The tiles chosen for one frame, traced as one terrain: a [`Tracer`] like a single height
//! field's, so shading, shadow rays and every output work on it unchanged.
//!
//! The chosen tiles are the leaves of a quadtree whose inner nodes are their ancestors. A ray
//! walks it front to back: at each node it is clipped to the node's box (the node's rectangle,
//! from the solid's floor up to the highest sample under it), the children it crosses are
//! visited in the order it enters them, and the first tile that reports a hit ends the walk
//! (per-pixel early exit, as section 3.4 of Dick et al. 2009 does for whole tiles).
//!
//! A leaf's tile is traced by whatever tracer the store's [`crate::TileTracerFactory`] made for
//! it (a max-mipmap tracer by default): the terrain is an aggregate of tracers and a tracer
//! itself, so it nests as pbrt's aggregates do. Rays reach a leaf's tracer one at a time or
//! in batches (the rays of a batch that cross the tile), so a tracer with packets keeps them.
//!
//! Each tile is a height field of its own standing on the whole raster's floor, and a ray is
//! handed to a tile only over the stretch where it crosses the tile's box (over a flat tile,
//! whose box has no height, the stretch where it crosses the tile's rectangle: the tile's
//! tracer clips it to its own solid, whose top a stretch of no length could miss). The tiles'
//! solids are therefore columns that together make the untiled raster's solid when every tile
//! is of level 0. Where a coarse tile meets a finer one, the two surfaces need not meet: the
//! solids still do, as a vertical step at the rectangles' shared edge, whose face a ray that
//! enters a tile below its surface hits (with that face's normal). So the union has neither
//! cracks nor holes at any mix of levels.

use crate::store::LoadedTile;
use relief_core::{Aabb, BoxFace, Clip, DVec2, DVec3, Ray, SmoothNormals, Surface};
use relief_trace::{Hit, Tracer};
use std::sync::Arc;

/// One node of a frame's tile quadtree.
#[derive(Debug)]
enum Node {
    /// A tile to trace; `flat` when its box has no height.
    Leaf { bounds: Aabb, flat: bool, tile: Arc<LoadedTile> },
    /// Children to visit (indices into the node list), in the order a ray meets them for each
    /// of the four sign classes of its direction's x and y ([`sign_class`]).
    Inner { bounds: Aabb, orders: [Vec<u32>; 4] },
}

impl Node {
    fn bounds(&self) -> &Aabb {
        match self {
            Node::Leaf { bounds, .. } | Node::Inner { bounds, .. } => bounds,
        }
    }
}

/// Which way a direction goes along x and y: bit 0 set for west, bit 1 for south.
///
/// A ray crosses each of a node's two splitting lines at most once, in the direction it
/// travels, so it meets the children in the order of their centres along its direction's
/// signs: first the child on the side it comes from in both x and y, last the opposite one.
/// Of the two others it meets at most one, so their order does not matter. Every ray of one
/// sign class meets the children in one order, whatever its origin.
#[inline]
fn sign_class(dir: DVec3) -> usize {
    (dir.x < 0.0) as usize | ((dir.y < 0.0) as usize) << 1
}

/// A frame's tiles, traced as one terrain.
#[derive(Debug)]
pub struct TiledTerrain {
    surface: Surface,
    nodes: Vec<Node>,
    tiles: usize,
}

/// One node of the tree a [`TiledTerrain`] is made from.
#[derive(Debug)]
pub enum TreeNode {
    /// A tile.
    Tile(Arc<LoadedTile>),
    /// A node whose children are listed.
    Inner(Vec<TreeNode>),
}

impl TiledTerrain {
    /// The terrain of `root`'s tiles on `surface`, over a solid from `floor` up (world z;
    /// `z_scale` turns the tiles' sample values into world z). Tiles of nothing but voids are
    /// left out, and so are tiles whose rectangle has no area (those of a `triangles` surface
    /// over a raster one sample wide or high, which has no squares).
    pub fn new(root: TreeNode, surface: Surface, floor: f64, z_scale: f64) -> Self {
        let mut terrain = TiledTerrain { surface, nodes: Vec::new(), tiles: 0 };
        terrain.add(root, floor, z_scale);
        terrain
    }

    /// Tiles with samples the terrain traces.
    pub fn tile_count(&self) -> usize {
        self.tiles
    }

    /// The slope (`dz/dx`, `dz/dy`, in world units) of the terrain's smooth tangent plane at
    /// world `(x, y)`, as Dick et al. (2009, section 3.3) take it for texture filtering: the
    /// central differences of the heights of the tile drawn there (one-sided at the edges of
    /// its stored samples), interpolated bilinearly between the four samples around the point.
    /// `None` outside every tile.
    pub fn surface_slope(&self, x: f64, y: f64) -> Option<DVec2> {
        tile_slope(self.tile_at(x, y)?, x, y)
    }

    /// The tile drawn at world `(x, y)`, whose rectangle holds the point; `None` outside
    /// every tile.
    fn tile_at(&self, x: f64, y: f64) -> Option<&LoadedTile> {
        let inside = |b: &Aabb| b.min.x <= x && x <= b.max.x && b.min.y <= y && y <= b.max.y;
        let mut at = 0usize;
        loop {
            match self.nodes.get(at)? {
                Node::Leaf { tile, bounds, .. } => return inside(bounds).then_some(&**tile),
                Node::Inner { orders, .. } => {
                    at = *orders[0].iter().find(|&&c| inside(self.nodes[c as usize].bounds()))?
                        as usize;
                }
            }
        }
    }

    /// Adds `node` and everything under it; returns its index, `None` when it holds no samples.
    fn add(&mut self, node: TreeNode, floor: f64, z_scale: f64) -> Option<u32> {
        let at = self.nodes.len() as u32;
        match node {
            TreeNode::Tile(tile) => {
                tile.heights.as_ref()?;
                let (min, max) = (tile.rect.min, tile.rect.max);
                if !(min[0] < max[0] && min[1] < max[1]) {
                    return None;
                }
                let top = tile.record.max as f64 * z_scale;
                let bounds =
                    Aabb::new(DVec3::new(min[0], min[1], floor), DVec3::new(max[0], max[1], top));
                let flat = top <= floor;
                self.nodes.push(Node::Leaf { bounds, flat, tile });
                self.tiles += 1;
            }
            TreeNode::Inner(children) => {
                let empty = Aabb::new(DVec3::INFINITY, DVec3::NEG_INFINITY);
                self.nodes.push(Node::Inner { bounds: empty, orders: Default::default() });
                let kids: Vec<u32> =
                    children.into_iter().filter_map(|c| self.add(c, floor, z_scale)).collect();
                if kids.is_empty() {
                    self.nodes.truncate(at as usize);
                    return None;
                }
                let mut bounds = *self.nodes[kids[0] as usize].bounds();
                for &k in &kids[1..] {
                    let b = self.nodes[k as usize].bounds();
                    bounds = Aabb::new(bounds.min.min(b.min), bounds.max.max(b.max));
                }
                let orders = std::array::from_fn(|class| {
                    let (sx, sy) =
                        (1.0 - 2.0 * (class & 1) as f64, 1.0 - 2.0 * (class >> 1) as f64);
                    let key = |k: &u32| {
                        let c = self.nodes[*k as usize].bounds().center();
                        sx * c.x + sy * c.y
                    };
                    let mut order = kids.clone();
                    order.sort_by(|a, b| key(a).total_cmp(&key(b)));
                    order
                });
                self.nodes[at as usize] = Node::Inner { bounds, orders };
            }
        }
        Some(at)
    }

    /// The first hit under node `at`, or (with `any`) the first one found.
    fn trace(&self, at: u32, ray: &Ray, inv_dir: DVec3, any: bool, steps: &mut u32) -> Option<Hit> {
        let node = &self.nodes[at as usize];
        let clip = node.bounds().clip_with_inverse(ray, inv_dir)?;
        *steps += 1;
        match node {
            Node::Leaf { tile, flat, bounds } => {
                let tracer = leaf_tracer(tile);
                let clip = if *flat { over_rectangle(bounds, ray, inv_dir, clip) } else { clip };
                let part = Ray { t_min: clip.t_enter, t_max: clip.t_exit, ..*ray };
                if any {
                    let blocked = tracer.occluded_counted(&part, steps);
                    return blocked.then_some(Hit {
                        t: clip.t_enter,
                        position: ray.origin,
                        normal: DVec3::Z,
                    });
                }
                let hit = tracer.intersect_counted(&part, steps)?;
                Some(entry_face_fixed(hit, &clip, ray))
            }
            Node::Inner { orders, .. } => orders[sign_class(ray.dir)]
                .iter()
                .find_map(|&c| self.trace(c, ray, inv_dir, any, steps)),
        }
    }

    /// The rays `ids` of a batch (all of sign class `class`, none decided yet) under node
    /// `at`: leaves trace the rays that cross them together, with their own packets.
    fn trace_packet(&self, at: u32, batch: &mut Batch<'_>, ids: &[u32], class: usize) {
        let node = &self.nodes[at as usize];
        let mut entering = batch.scratch.take_clips();
        for &k in ids {
            if batch.done[k as usize] {
                continue;
            }
            let ray = &batch.rays[k as usize];
            if let Some(clip) = node.bounds().clip_with_inverse(ray, batch.inv_dirs[k as usize]) {
                batch.steps[k as usize] += 1;
                entering.push((k, clip));
            }
        }
        if !entering.is_empty() {
            match node {
                Node::Leaf { tile, flat, bounds } => {
                    if *flat {
                        for (k, clip) in entering.iter_mut() {
                            let k = *k as usize;
                            *clip =
                                over_rectangle(bounds, &batch.rays[k], batch.inv_dirs[k], *clip);
                        }
                    }
                    batch.trace_leaf(leaf_tracer(tile), &entering);
                }
                Node::Inner { orders, .. } => {
                    let mut alive = batch.scratch.take_ids();
                    alive.extend(entering.iter().map(|&(k, _)| k));
                    for &child in &orders[class] {
                        self.trace_packet(child, batch, &alive, class);
                    }
                    batch.scratch.ids.push(alive);
                }
            }
        }
        batch.scratch.clips.push(entering);
    }

    /// Traces a batch: the rays of each sign class walk the tree together.
    fn trace_batch(&self, batch: &mut Batch<'_>) {
        for class in 0..4 {
            let ids: Vec<u32> = (0..batch.rays.len() as u32)
                .filter(|&k| sign_class(batch.rays[k as usize].dir) == class)
                .collect();
            if !ids.is_empty() {
                self.trace_packet(0, batch, &ids, class);
            }
        }
    }
}

/// The stretch of `ray` over the rectangle of a flat tile's box `bounds`, which it crosses as
/// `clip` (kept should rounding make the stretch empty).
fn over_rectangle(bounds: &Aabb, ray: &Ray, inv_dir: DVec3, clip: Clip) -> Clip {
    let column = Aabb::new(
        DVec3::new(bounds.min.x, bounds.min.y, f64::NEG_INFINITY),
        DVec3::new(bounds.max.x, bounds.max.y, f64::INFINITY),
    );
    column.clip_with_inverse(ray, inv_dir).unwrap_or(clip)
}

/// The tracer of a leaf (leaves are tiles with samples).
#[inline]
fn leaf_tracer(tile: &LoadedTile) -> &dyn Tracer {
    &*tile.heights.as_ref().expect("leaves have samples").tracer
}

/// The smooth shading normal of the tile drawn at a point: its height field's
/// ([`HeightField::smooth_normal_at`](relief_core::HeightField::smooth_normal_at)), from the
/// tile's own samples (one-sided differences at its stored edges, so a seam between tiles of
/// different levels may show a slight crease). A `boxes` terrain has none.
impl SmoothNormals for TiledTerrain {
    fn smooth_normal(&self, position: DVec3) -> Option<DVec3> {
        if self.surface != Surface::Triangles {
            return None;
        }
        let field = &self.tile_at(position.x, position.y)?.heights.as_ref()?.field;
        field.smooth_normal_at(position.x, position.y)
    }
}

/// The slope of `tile`'s heights at world `(x, y)` (see [`TiledTerrain::surface_slope`]).
fn tile_slope(tile: &LoadedTile, x: f64, y: f64) -> Option<DVec2> {
    let field = &tile.heights.as_ref()?.field;
    let g = field.geometry();
    let (w, h) = (field.width(), field.height());
    if w < 2 || h < 2 {
        return None;
    }
    let height = |c: usize, r: usize| field.sample(c, r) as f64 * g.z_scale;
    // The central difference at sample (c, r), one-sided on the stored edge.
    let gradient = |c: usize, r: usize| {
        let (cl, ch) = (c.saturating_sub(1), (c + 1).min(w - 1));
        let (rl, rh) = (r.saturating_sub(1), (r + 1).min(h - 1));
        DVec2::new(
            (height(ch, r) - height(cl, r)) / ((ch - cl) as f64 * g.dx),
            (height(c, rh) - height(c, rl)) / ((rh - rl) as f64 * g.dy),
        )
    };
    let u = (x - g.origin.x) / g.dx - 0.5;
    let v = (y - g.origin.y) / g.dy - 0.5;
    let c0 = u.floor().clamp(0.0, (w - 2) as f64);
    let r0 = v.floor().clamp(0.0, (h - 2) as f64);
    let (fu, fv) = ((u - c0).clamp(0.0, 1.0), (v - r0).clamp(0.0, 1.0));
    let (c0, r0) = (c0 as usize, r0 as usize);
    let south = gradient(c0, r0).lerp(gradient(c0 + 1, r0), fu);
    let north = gradient(c0, r0 + 1).lerp(gradient(c0 + 1, r0 + 1), fu);
    let slope = south.lerp(north, fv);
    slope.is_finite().then_some(slope)
}

/// The rays of one batch as [`TiledTerrain::trace_packet`] walks them.
struct Batch<'a> {
    rays: &'a [Ray],
    /// `1 / dir` of each ray.
    inv_dirs: Vec<DVec3>,
    /// First hits (unused for occlusion).
    hits: &'a mut [Option<Hit>],
    /// Whether a ray is decided: hit, or blocked.
    done: Vec<bool>,
    steps: &'a mut [u32],
    /// Occlusion only: stop at any hit.
    any: bool,
    scratch: Scratch,
}

/// Buffers the walk reuses instead of allocating at every node.
#[derive(Default)]
struct Scratch {
    clips: Vec<Vec<(u32, Clip)>>,
    ids: Vec<Vec<u32>>,
    parts: Vec<Ray>,
    hits: Vec<Option<Hit>>,
    blocked: Vec<bool>,
    steps: Vec<u32>,
}

impl Scratch {
    fn take_clips(&mut self) -> Vec<(u32, Clip)> {
        let mut v = self.clips.pop().unwrap_or_default();
        v.clear();
        v
    }

    fn take_ids(&mut self) -> Vec<u32> {
        let mut v = self.ids.pop().unwrap_or_default();
        v.clear();
        v
    }
}

impl<'a> Batch<'a> {
    fn new(rays: &'a [Ray], hits: &'a mut [Option<Hit>], steps: &'a mut [u32], any: bool) -> Self {
        let inv_dirs = rays.iter().map(|r| DVec3::ONE / r.dir).collect();
        let done = vec![false; rays.len()];
        Batch { rays, inv_dirs, hits, done, steps, any, scratch: Scratch::default() }
    }

    /// Traces the `entering` rays, each over the stretch where it crosses the tile's box.
    fn trace_leaf(&mut self, tracer: &dyn Tracer, entering: &[(u32, Clip)]) {
        let s = &mut self.scratch;
        s.parts.clear();
        s.parts.extend(entering.iter().map(|&(k, clip)| Ray {
            t_min: clip.t_enter,
            t_max: clip.t_exit,
            ..self.rays[k as usize]
        }));
        s.steps.clear();
        s.steps.resize(entering.len(), 0);
        if self.any {
            s.blocked.clear();
            s.blocked.resize(entering.len(), false);
            tracer.occluded_batch(&s.parts, &mut s.blocked, &mut s.steps);
            for (((k, _), &b), &n) in entering.iter().zip(&s.blocked).zip(&s.steps) {
                self.steps[*k as usize] += n;
                self.done[*k as usize] = b;
            }
        } else {
            s.hits.clear();
            s.hits.resize(entering.len(), None);
            tracer.intersect_batch(&s.parts, &mut s.hits, &mut s.steps);
            for (((k, clip), hit), &n) in entering.iter().zip(&s.hits).zip(&s.steps) {
                self.steps[*k as usize] += n;
                if let Some(hit) = hit {
                    self.hits[*k as usize] =
                        Some(entry_face_fixed(*hit, clip, &self.rays[*k as usize]));
                    self.done[*k as usize] = true;
                }
            }
        }
    }
}

/// A ray that enters the tile's box already in the solid hits the face it crossed: a wall
/// where levels meet or at the raster's edge, the floor, or a flat top at the tile's highest
/// sample (the tile's tracer, which sees the ray start there, cannot tell which).
fn entry_face_fixed(mut hit: Hit, clip: &Clip, ray: &Ray) -> Hit {
    if hit.t == clip.t_enter && clip.face != BoxFace::Inside {
        hit.normal = face_normal(clip.face, ray.dir);
    }
    hit
}

/// The unit normal of a box face perpendicular to `face`'s axis, facing against `dir`.
fn face_normal(face: BoxFace, dir: DVec3) -> DVec3 {
    match face {
        BoxFace::X => DVec3::new(-dir.x.signum(), 0.0, 0.0),
        BoxFace::Y => DVec3::new(0.0, -dir.y.signum(), 0.0),
        BoxFace::Z | BoxFace::Inside => DVec3::new(0.0, 0.0, -dir.z.signum()),
    }
}

impl Tracer for TiledTerrain {
    fn name(&self) -> &'static str {
        "tiles"
    }

    fn surface(&self) -> Surface {
        self.surface
    }

    /// The root node's box (an empty box, min above max, when no tile holds samples).
    fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::new(DVec3::INFINITY, DVec3::NEG_INFINITY), |n| *n.bounds())
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        self.trace(0, ray, DVec3::ONE / ray.dir, false, steps)
    }

    fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
        !self.nodes.is_empty() && self.trace(0, ray, DVec3::ONE / ray.dir, true, steps).is_some()
    }

    /// Traces the rays together: each tile traces the rays that cross it as one batch (with
    /// its tracer's batches: the max-mipmap tracer's packets by default).
    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], steps: &mut [u32]) {
        assert!(rays.len() == hits.len() && rays.len() == steps.len(), "batch slices differ");
        hits.fill(None);
        if self.nodes.is_empty() {
            return;
        }
        self.trace_batch(&mut Batch::new(rays, hits, steps, false));
    }

    /// As [`TiledTerrain::intersect_batch`], for occlusion.
    fn occluded_batch(&self, rays: &[Ray], occluded: &mut [bool], steps: &mut [u32]) {
        assert!(rays.len() == occluded.len() && rays.len() == steps.len(), "batch slices differ");
        occluded.fill(false);
        if self.nodes.is_empty() {
            return;
        }
        let mut hits = vec![None; rays.len()];
        let mut batch = Batch::new(rays, &mut hits, steps, true);
        self.trace_batch(&mut batch);
        occluded.copy_from_slice(&batch.done);
    }
}
