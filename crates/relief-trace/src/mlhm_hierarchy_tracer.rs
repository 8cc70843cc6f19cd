//! Hierarchical MLHM box ray tracing: a 2D DDA per level of an [`MlhmHierarchy`], descending
//! into nodes whose bounds the ray meets, with two ways back up (Nilles & Müller 2025, 4.2).

use crate::cell_grid::axis_cell;
use crate::mlhm_cells::{first_hit_in_cell, ray_to_cells, segment};
use crate::{Hit, MlhmHierarchy, MlhmHit, MlhmMode, MlhmTracer, Tracer};
use relief_core::{Aabb, DVec2, DVec3, Mlhm, Precision, Ray, Surface};
use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

/// How the hierarchical traversal climbs back to coarser levels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MlhmBacktrack {
    /// A per-level array of the distances at which the ray leaves each node it descended
    /// from: after a step, climb while the step reached the parent's exit.
    #[default]
    ExitStack,
    /// A miss counter: climb one level after 8 missed nodes in a row (16 on level 0).
    MissCounter,
}

impl MlhmBacktrack {
    /// Both variants, in a fixed order.
    pub const ALL: [MlhmBacktrack; 2] = [MlhmBacktrack::ExitStack, MlhmBacktrack::MissCounter];

    /// The name used in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            MlhmBacktrack::ExitStack => "stack",
            MlhmBacktrack::MissCounter => "miss",
        }
    }
}

impl fmt::Display for MlhmBacktrack {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MlhmBacktrack {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MlhmBacktrack::ALL
            .into_iter()
            .find(|b| b.name() == s)
            .ok_or_else(|| format!("unknown backtracking '{s}' (expected stack or miss)"))
    }
}

/// Misses in a row after which the miss counter climbs, above level 0 and on level 0.
pub(crate) const MISSES: u32 = 8;
pub(crate) const FINE_MISSES: u32 = 16;

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

/// One horizontal axis of the ray in cell space.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Axis {
    pub(crate) o: f64,
    pub(crate) d: f64,
    pub(crate) inv: f64,
    /// The start cell along this axis.
    pub(crate) start: usize,
}

impl Axis {
    /// The parameter where the ray leaves node `n` of `level` along this axis (`+inf` when
    /// it does not move along it): the crossing of the integer boundary, computed as the
    /// naive tracer computes a cell's.
    #[inline]
    pub(crate) fn exit(self, n: usize, level: usize) -> f64 {
        if self.d > 0.0 {
            (((n + 1) << level) as f64 - self.o) * self.inv
        } else if self.d < 0.0 {
            ((n << level) as f64 - self.o) * self.inv
        } else {
            f64::INFINITY
        }
    }

    /// The child at `level` of node `n` (one level up) holding the ray's point at `t`; the
    /// start cell's ancestor before the ray has moved. At a node boundary crossed by a step,
    /// the child past the boundary between the two once it has been reached; at a point the
    /// ray advanced to inside a node (`advanced`), the child before it until it is passed,
    /// since a cell whose part of the ray ends at `t` may still be hit there.
    #[inline]
    pub(crate) fn child(
        self,
        n: usize,
        level: usize,
        t: f64,
        at_start: bool,
        advanced: bool,
    ) -> usize {
        if at_start || self.d == 0.0 {
            return self.start >> level;
        }
        let mid = (2 * n + 1) << level;
        let t_mid = (mid as f64 - self.o) * self.inv;
        let crossed = if advanced { t > t_mid } else { t >= t_mid };
        if self.d > 0.0 {
            2 * n + crossed as usize
        } else {
            2 * n + 1 - crossed as usize
        }
    }

    /// The next node along the axis, `None` past the grid's low end.
    #[inline]
    pub(crate) fn step(self, n: usize) -> Option<usize> {
        if self.d > 0.0 {
            Some(n + 1)
        } else {
            n.checked_sub(1)
        }
    }
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
        let bounds =
            Aabb::new(DVec3::new(0.0, 0.0, f64::NEG_INFINITY), DVec3::new(w as f64, h as f64, top));
        let clip = bounds.clip(&ray)?;
        let ax = Axis {
            o: ray.origin.x,
            d: ray.dir.x,
            inv: inv.x,
            start: axis_cell(ray.origin.x, ray.dir.x, inv.x, clip.t_enter, w),
        };
        let ay = Axis {
            o: ray.origin.y,
            d: ray.dir.y,
            inv: inv.y,
            start: axis_cell(ray.origin.y, ray.dir.y, inv.y, clip.t_enter, h),
        };
        let (oz, dz, inv_z) = (ray.origin.z, ray.dir.z, inv.z);
        let top_level = self.hierarchy.level_count();
        let mut level = top_level;
        let (mut nx, mut ny) = (ax.start >> level, ay.start >> level);
        let mut t = clip.t_enter;
        let mut at_start = true;
        // Whether `t` was advanced inside a node rather than reached by a step.
        let mut advanced = false;
        let mut misses = 0u32;
        // exits[l]: where the ray leaves the node of level l it last descended from.
        let mut exits = [f64::INFINITY; MAX_LEVELS + 1];
        loop {
            *steps = steps.saturating_add(1);
            let tx = ax.exit(nx, level);
            let ty = ay.exit(ny, level);
            let t_next = tx.min(ty);
            if level == 0 {
                let seg = segment(&ray, inv, &clip, nx, ny);
                if let Some(hit) =
                    first_hit_in_cell(&self.map, world_ray, &ray, inv, mode, nx, ny, &seg)
                {
                    return Some(hit);
                }
            } else {
                let t_leave = clip.t_exit.min(t_next);
                // The naive tracer's slab formula on enclosing bounds: never rejects a box
                // that a cell of this node would hit within its part of [t, t_leave]. The
                // first parameter at which the ray is inside an interval bounds every hit
                // in the node from below, so the traversal may advance to it.
                let mut t_first = f64::INFINITY;
                self.hierarchy.for_each_interval(level, nx, ny, mode, |lo, hi| {
                    if dz == 0.0 {
                        if lo <= oz && oz <= hi && t <= t_leave {
                            t_first = t;
                        }
                    } else {
                        let (t_lo, t_hi) = ((lo - oz) * inv_z, (hi - oz) * inv_z);
                        let (ta, tb) = if dz < 0.0 { (t_hi, t_lo) } else { (t_lo, t_hi) };
                        let t_in = ta.max(t);
                        if t_in <= tb.min(t_leave) {
                            t_first = t_first.min(t_in);
                        }
                    }
                    t_first <= t
                });
                let hit = t_first <= t_leave;
                if hit {
                    if t_first > t {
                        t = t_first;
                        at_start = false;
                        advanced = true;
                    }
                    exits[level] = t_next;
                    level -= 1;
                    misses = 0;
                    nx = ax.child(nx, level, t, at_start, advanced);
                    ny = ay.child(ny, level, t, at_start, advanced);
                    // At the grid's ragged edge rounding cannot pick a child past it; guard
                    // anyway by taking its sibling.
                    let (cells_x, cells_y) = self.nodes(level);
                    nx = nx.min(cells_x - 1);
                    ny = ny.min(cells_y - 1);
                    continue;
                }
            }
            if t_next >= clip.t_exit || t_next.is_nan() {
                return None;
            }
            // Through a corner, step both axes at once, as the naive DDA does.
            let (cross_x, cross_y) = (tx == t_next, ty == t_next);
            if cross_x {
                nx = ax.step(nx)?;
            }
            if cross_y {
                ny = ay.step(ny)?;
            }
            let (nodes_x, nodes_y) = self.nodes(level);
            if nx >= nodes_x || ny >= nodes_y {
                return None;
            }
            t = t_next;
            at_start = false;
            advanced = false;
            match self.backtrack {
                MlhmBacktrack::ExitStack => {
                    // The node boundaries of a level are boundaries of the level below, with
                    // the same crossing parameters: the step left the parent exactly when it
                    // reached the parent's exit.
                    while level < top_level && t >= exits[level + 1] {
                        level += 1;
                        nx >>= 1;
                        ny >>= 1;
                    }
                }
                MlhmBacktrack::MissCounter => {
                    misses += 1;
                    let limit = if level == 0 { FINE_MISSES } else { MISSES };
                    if misses >= limit && level < top_level {
                        level += 1;
                        nx >>= 1;
                        ny >>= 1;
                        misses = 0;
                    }
                }
            }
        }
    }

    /// Nodes along x and y of `level`, cells for level 0.
    #[inline]
    fn nodes(&self, level: usize) -> (usize, usize) {
        if level == 0 {
            (self.map.width(), self.map.height())
        } else {
            self.hierarchy.nodes(level)
        }
    }
}

/// Room for every level of the hierarchy and level 0.
const MAX_LEVELS: usize = crate::mlhm_hierarchy::MAX_HIERARCHY_LEVELS;

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

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        self.intersect_mode_counted(ray, self.mode, steps).map(|h| h.hit)
    }
}
