//! The tiles chosen for one frame, traced as one terrain: a [`Tracer`] like a single height
//! field's, so shading, shadow rays and every output work on it unchanged.
//!
//! The chosen tiles are the leaves of a quadtree whose inner nodes are their ancestors. A ray
//! walks it front to back: at each node it is clipped to the node's box (the node's rectangle,
//! from the solid's floor up to the highest sample under it), the children it crosses are
//! visited in the order it enters them, and the first tile that reports a hit ends the walk
//! (per-pixel early exit, as section 3.4 of Dick et al. 2009 does for whole tiles).
//!
//! Each tile is a height field of its own standing on the whole raster's floor, and a ray is
//! handed to a tile only over the stretch where it crosses the tile's rectangle. The tiles'
//! solids are therefore columns that together make the untiled raster's solid when every tile
//! is of level 0. Where a coarse tile meets a finer one, the two surfaces need not meet: the
//! solids still do, as a vertical step at the rectangles' shared edge, whose face a ray that
//! enters a tile below its surface hits (with that face's normal). So the union has neither
//! cracks nor holes at any mix of levels.

use crate::store::LoadedTile;
use relief_core::{Aabb, BoxFace, DVec3, Ray, Surface};
use relief_trace::{Hit, Tracer};
use std::sync::Arc;

/// One node of a frame's tile quadtree.
#[derive(Debug)]
enum Node {
    /// A tile to trace.
    Leaf { bounds: Aabb, tile: Arc<LoadedTile> },
    /// Children to visit (indices into the node list).
    Inner { bounds: Aabb, children: Vec<u32> },
}

impl Node {
    fn bounds(&self) -> &Aabb {
        match self {
            Node::Leaf { bounds, .. } | Node::Inner { bounds, .. } => bounds,
        }
    }
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
    /// left out.
    pub fn new(root: TreeNode, surface: Surface, floor: f64, z_scale: f64) -> Self {
        let mut terrain = TiledTerrain { surface, nodes: Vec::new(), tiles: 0 };
        terrain.add(root, floor, z_scale);
        terrain
    }

    /// Tiles with samples the terrain traces.
    pub fn tile_count(&self) -> usize {
        self.tiles
    }

    /// Adds `node` and everything under it; returns its index, `None` when it holds no samples.
    fn add(&mut self, node: TreeNode, floor: f64, z_scale: f64) -> Option<u32> {
        let at = self.nodes.len() as u32;
        match node {
            TreeNode::Tile(tile) => {
                tile.tracer.as_ref()?;
                let top = tile.record.max as f64 * z_scale;
                let bounds = Aabb::new(
                    DVec3::new(tile.rect.min[0], tile.rect.min[1], floor),
                    DVec3::new(tile.rect.max[0], tile.rect.max[1], top),
                );
                self.nodes.push(Node::Leaf { bounds, tile });
                self.tiles += 1;
            }
            TreeNode::Inner(children) => {
                self.nodes.push(Node::Inner {
                    bounds: Aabb::new(DVec3::INFINITY, DVec3::NEG_INFINITY),
                    children: Vec::new(),
                });
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
                self.nodes[at as usize] = Node::Inner { bounds, children: kids };
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
            Node::Leaf { tile, .. } => {
                let tracer = tile.tracer.as_ref().expect("leaves have samples");
                let part = Ray { t_min: clip.t_enter, t_max: clip.t_exit, ..*ray };
                if any {
                    return tracer.occluded_counted(&part, steps).then_some(Hit {
                        t: clip.t_enter,
                        position: ray.origin,
                        normal: DVec3::Z,
                    });
                }
                let mut hit = tracer.intersect_counted(&part, steps)?;
                // A ray that enters the tile's box already in the solid hits the face it
                // crossed: a wall where levels meet or at the raster's edge, the floor, or a
                // flat top at the tile's highest sample (the tile's tracer, which sees the ray
                // start there, cannot tell which).
                if hit.t == clip.t_enter && clip.face != BoxFace::Inside {
                    hit.normal = face_normal(clip.face, ray.dir);
                }
                Some(hit)
            }
            Node::Inner { children, .. } => {
                let mut order: Vec<(f64, u32)> = children
                    .iter()
                    .filter_map(|&c| {
                        let clip =
                            self.nodes[c as usize].bounds().clip_with_inverse(ray, inv_dir)?;
                        Some((clip.t_enter, c))
                    })
                    .collect();
                order.sort_by(|a, b| a.0.total_cmp(&b.0));
                order.into_iter().find_map(|(_, c)| self.trace(c, ray, inv_dir, any, steps))
            }
        }
    }
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

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        self.trace(0, ray, DVec3::ONE / ray.dir, false, steps)
    }

    fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
        !self.nodes.is_empty() && self.trace(0, ray, DVec3::ONE / ray.dir, true, steps).is_some()
    }
}
