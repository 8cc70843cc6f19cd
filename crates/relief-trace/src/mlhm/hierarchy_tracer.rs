//! Hierarchical MLHM box ray tracing: a 2D DDA per level of an [`MlhmHierarchy`], descending
//! into nodes whose bounds the ray meets, with two ways back up (Nilles & Müller 2025, 4.2).

use super::cells::{first_hit_in_cell, ray_to_cells, segment, world_box};
use super::walk::HierarchyWalk;
use crate::{Hit, MlhmBacktrack, MlhmHierarchy, MlhmHit, MlhmMode, MlhmTracer, Tracer};
use relief_core::{Aabb, DVec2, DVec3, Mlhm, Precision, Ray, Surface};
use std::sync::Arc;

/// Box ray tracing of an [`Mlhm`] through its [`MlhmHierarchy`], exact: it returns the same
/// hits as [`crate::MlhmNaiveTracer`], bit for bit.
///
/// The ray is clipped to the scene's box and starts at the coarsest level. On each level a 2D
/// DDA walks the nodes; in each, every node layer's interval (see
/// [`crate::MlhmNodeLayer`]) is slab-tested over the ray's parameter range inside the node. On
/// a hit the traversal descends to the child holding the current point; at level 0 the cell's
/// boxes are tested exactly as the naive tracer tests them. It climbs back by
/// [`MlhmBacktrack`].
///
/// Exactness, without epsilons: node and cell boundaries are integers, and the parameter
/// where the ray crosses one is computed by one formula on every level, so a cell's part of
/// the ray lies within its node's part. Node slab tests use the naive tracer's slab formula on
/// bounds enclosing the cells' boxes (exact f32 or f16 rounded outward, see
/// [`MlhmHierarchy`]), so they never reject a box the naive tracer would hit,
/// and the first parameter at which the ray is inside a node interval bounds every hit in the
/// node from below: on descending, the traversal advances to it (as a max-mipmap traversal
/// advances to a node's maximum). Otherwise it moves only to node boundaries, and picks
/// children from the same crossings (at an advanced point, a cell whose part ends exactly
/// there is kept, since it may be hit there). So the cells it tests are cells the naive DDA
/// visits, in the same order, minus cells that cannot be hit, and level 0 runs the naive
/// tracer's own cell test: the hits are bit-identical. Climbing never skips a part of the ray:
/// the exit stack climbs exactly when a step reaches the parent's exit (the same crossing
/// parameter), and the miss counter re-tests the parent from the current point.
///
/// Placement and cell conventions are those of [`crate::MlhmNaiveTracer`].
///
/// ```
/// use std::sync::Arc;
/// use relief_core::{DVec2, DVec3, Mlhm, MlhmColumn, Ray};
/// use relief_trace::{MlhmHierarchyTracer, MlhmMaterial, MlhmMode, MlhmTracer};
/// let mut map = Mlhm::new(16, 16, 2, 1.0)?;
/// map.set_cell(9, 4, &[
///     MlhmColumn::new(1.0, 0.0, 1.0, 3.0),
///     MlhmColumn::new(4.0, 0.0, 0.0, f32::INFINITY),
/// ])?;
/// let tracer = MlhmHierarchyTracer::new(Arc::new(map), DVec2::ZERO);
/// let down = Ray::new(DVec3::new(9.5, 4.5, 2.5), -DVec3::Z);
/// let hit = tracer.intersect_mode(&down, MlhmMode::SolidsWater).unwrap();
/// assert_eq!((hit.hit.t, hit.material), (0.5, MlhmMaterial::Water));
/// let across = Ray::new(DVec3::new(0.5, 4.5, 3.5), DVec3::X);
/// assert_eq!(tracer.intersect_mode(&across, MlhmMode::Solids).unwrap().hit.t, 8.5);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone)]
pub struct MlhmHierarchyTracer {
    map: Arc<Mlhm>,
    hierarchy: MlhmHierarchy,
    origin: DVec2,
    mode: MlhmMode,
    backtrack: MlhmBacktrack,
}

impl MlhmHierarchyTracer {
    /// Builds the hierarchy of `map`, placed with its south-west corner at world `origin`;
    /// intersects [`MlhmMode::SolidsWater`] as a [`Tracer`] and climbs by
    /// [`MlhmBacktrack::ExitStack`].
    pub fn new(map: Arc<Mlhm>, origin: DVec2) -> Self {
        let hierarchy = MlhmHierarchy::build(&map);
        Self::with_hierarchy(map, hierarchy, origin)
    }

    /// [`MlhmHierarchyTracer::new`] with the hierarchy's bounds stored at `precision` (see
    /// [`MlhmHierarchy::build_with_precision`]); the hits are the same at either.
    pub fn new_with_precision(map: Arc<Mlhm>, origin: DVec2, precision: Precision) -> Self {
        let hierarchy = MlhmHierarchy::build_with_precision(&map, precision);
        Self::with_hierarchy(map, hierarchy, origin)
    }

    /// A tracer from a hierarchy built from `map` (say, rebuilt by the caller).
    ///
    /// # Panics
    /// When the hierarchy's grid is not the map's.
    pub fn with_hierarchy(map: Arc<Mlhm>, hierarchy: MlhmHierarchy, origin: DVec2) -> Self {
        assert_eq!(hierarchy.cells(), (map.width(), map.height()), "hierarchy of another map");
        MlhmHierarchyTracer {
            map,
            hierarchy,
            origin,
            mode: MlhmMode::SolidsWater,
            backtrack: MlhmBacktrack::ExitStack,
        }
    }

    /// The same tracer intersecting `mode` when used as a [`Tracer`].
    pub fn with_mode(self, mode: MlhmMode) -> Self {
        MlhmHierarchyTracer { mode, ..self }
    }

    /// The same tracer climbing back up by `backtrack`.
    pub fn with_backtrack(self, backtrack: MlhmBacktrack) -> Self {
        MlhmHierarchyTracer { backtrack, ..self }
    }

    /// The hierarchy walked.
    pub fn hierarchy(&self) -> &MlhmHierarchy {
        &self.hierarchy
    }

    /// The mode intersected as a [`Tracer`].
    pub fn mode(&self) -> MlhmMode {
        self.mode
    }

    /// How the traversal climbs.
    pub fn backtrack(&self) -> MlhmBacktrack {
        self.backtrack
    }

    /// The hierarchical traversal, counting the nodes and cells visited into `steps`.
    fn traverse_counted(
        &self,
        world_ray: &Ray,
        mode: MlhmMode,
        steps: &mut u32,
    ) -> Option<MlhmHit> {
        let mut count = 0u32;
        let hit = self.traverse(world_ray, mode, &mut count);
        *steps = steps.saturating_add(count);
        hit
    }

    fn traverse(&self, world_ray: &Ray, mode: MlhmMode, steps: &mut u32) -> Option<MlhmHit> {
        let ray = ray_to_cells(&self.map, self.origin, world_ray)?;
        let inv = DVec3::ONE / ray.dir;
        let (w, h) = (self.map.width(), self.map.height());
        let top = self.hierarchy.top(mode);
        let bounds = Aabb::new(
            DVec3::new(0.0, 0.0, self.map.base() as f64),
            DVec3::new(w as f64, h as f64, top),
        );
        let clip = bounds.clip(&ray)?;
        let walk = HierarchyWalk {
            hierarchy: &self.hierarchy,
            leaf_level: 0,
            backtrack: self.backtrack,
            mode,
        };
        // The leaves are the cells, tested exactly as the naive tracer tests them.
        walk.walk(&ray, inv, clip.t_enter, clip.t_exit, steps, |nx, ny, _, _| {
            let seg = segment(&ray, inv, &clip, nx, ny);
            first_hit_in_cell(&self.map, world_ray, &ray, inv, mode, nx, ny, &seg)
        })
    }
}

impl MlhmTracer for MlhmHierarchyTracer {
    fn map(&self) -> &Arc<Mlhm> {
        &self.map
    }

    fn origin(&self) -> DVec2 {
        self.origin
    }

    fn intersect_mode_counted(
        &self,
        ray: &Ray,
        mode: MlhmMode,
        steps: &mut u32,
    ) -> Option<MlhmHit> {
        self.traverse_counted(ray, mode, steps)
    }
}

impl Tracer for MlhmHierarchyTracer {
    fn name(&self) -> &'static str {
        "mlhm-hierarchy"
    }

    /// MLHM columns are flat-topped boxes.
    fn surface(&self) -> Surface {
        Surface::Boxes
    }

    /// The footprint, from minus infinity up to the hierarchy's top in the tracer's mode.
    fn bounds(&self) -> Aabb {
        world_box(&self.map, self.origin, self.hierarchy.top(self.mode))
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        self.intersect_mode_counted(ray, self.mode, steps).map(|h| h.hit)
    }
}
