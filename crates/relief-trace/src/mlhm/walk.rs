//! The walk of a ray through an MLHM hierarchy (Nilles & Müller 2025, 4.2) that both
//! hierarchical tracers share: a 2D DDA per level from the coarsest, descending where a
//! node layer's interval meets the ray, climbing back by an exit stack or a miss counter,
//! and handing the nodes of the leaf level to the tracer: cells for boxes, level-1 nodes for
//! the smooth surface.

use crate::cell_grid::axis_cell;
use crate::{MlhmBacktrack, MlhmHierarchy, MlhmMode, MAX_HIERARCHY_LEVELS};
use relief_core::{DVec3, Ray};

/// Misses in a row after which the miss counter climbs, above the leaf level and on it.
const MISSES: u32 = 8;
const FINE_MISSES: u32 = 16;

/// One horizontal axis of the ray in cell space.
#[derive(Debug, Clone, Copy)]
struct Axis {
    o: f64,
    d: f64,
    inv: f64,
    /// The start cell along this axis.
    start: usize,
}

impl Axis {
    /// The parameter where the ray leaves node `n` of `level` along this axis (`+inf` when
    /// it does not move along it): the crossing of the integer boundary, computed as the
    /// naive tracer computes a cell's.
    #[inline]
    fn exit(self, n: usize, level: usize) -> f64 {
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
    fn child(self, n: usize, level: usize, t: f64, at_start: bool, advanced: bool) -> usize {
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
    fn step(self, n: usize) -> Option<usize> {
        if self.d > 0.0 {
            Some(n + 1)
        } else {
            n.checked_sub(1)
        }
    }
}

/// The ray's part inside the node being visited, `[t, t_leave]`, and its vertical motion.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeSpan {
    t: f64,
    t_leave: f64,
    oz: f64,
    dz: f64,
    inv_z: f64,
}

impl NodeSpan {
    /// The ray's parameter range inside the node within the interval `[lo, hi]` of heights,
    /// by the naive tracer's slab formula; `None` when it does not meet it.
    #[inline]
    pub(crate) fn part(&self, lo: f64, hi: f64) -> Option<(f64, f64)> {
        let (t, t_leave, oz, dz) = (self.t, self.t_leave, self.oz, self.dz);
        if dz == 0.0 {
            (lo <= oz && oz <= hi && t <= t_leave).then_some((t, t_leave))
        } else {
            let (t_lo, t_hi) = ((lo - oz) * self.inv_z, (hi - oz) * self.inv_z);
            let (ta, tb) = if dz < 0.0 { (t_hi, t_lo) } else { (t_lo, t_hi) };
            let (t0, t1) = (ta.max(t), tb.min(t_leave));
            (t0 <= t1).then_some((t0, t1))
        }
    }
}

/// A walk through `hierarchy` down to `leaf_level` for rays of `mode`.
///
/// Node slab tests use bounds enclosing everything below them, so they never reject what a
/// leaf would hit, and the first parameter at which the ray is inside a node interval bounds
/// every hit in the node from below: on descending, the walk advances to it. Otherwise it
/// moves only to node boundaries, computed by one formula on every level, and picks children
/// from the same crossings, so the leaves it visits are leaves a DDA over the leaf level
/// visits, in the same order, minus leaves that cannot be hit. Climbing never skips a part of
/// the ray: the exit stack climbs exactly when a step reaches the parent's exit, and the miss
/// counter re-tests the parent from the current point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct HierarchyWalk<'a> {
    pub(crate) hierarchy: &'a MlhmHierarchy,
    /// 0 (the cells) or a level of the hierarchy.
    pub(crate) leaf_level: usize,
    pub(crate) backtrack: MlhmBacktrack,
    pub(crate) mode: MlhmMode,
}

impl HierarchyWalk<'_> {
    /// Walks the cell-space `ray` (`inv` its reciprocal direction) over `[t_enter, t_exit]`,
    /// which lies over the grid, counting nodes visited into `steps`, and returns the first
    /// answer of `leaf(nx, ny, span, steps)` on the leaf nodes it reaches, in order.
    pub(crate) fn walk<R>(
        &self,
        ray: &Ray,
        inv: DVec3,
        t_enter: f64,
        t_exit: f64,
        steps: &mut u32,
        mut leaf: impl FnMut(usize, usize, &NodeSpan, &mut u32) -> Option<R>,
    ) -> Option<R> {
        let hierarchy = self.hierarchy;
        let (w, h) = hierarchy.cells();
        let ax = Axis {
            o: ray.origin.x,
            d: ray.dir.x,
            inv: inv.x,
            start: axis_cell(ray.origin.x, ray.dir.x, inv.x, t_enter, w),
        };
        let ay = Axis {
            o: ray.origin.y,
            d: ray.dir.y,
            inv: inv.y,
            start: axis_cell(ray.origin.y, ray.dir.y, inv.y, t_enter, h),
        };
        let (oz, dz, inv_z) = (ray.origin.z, ray.dir.z, inv.z);
        let top_level = hierarchy.level_count();
        let mut level = top_level;
        let (mut nx, mut ny) = (ax.start >> level, ay.start >> level);
        let mut t = t_enter;
        let mut at_start = true;
        // Whether `t` was advanced inside a node rather than reached by a step.
        let mut advanced = false;
        let mut misses = 0u32;
        // exits[l]: where the ray leaves the node of level l it last descended from.
        let mut exits = [f64::INFINITY; MAX_HIERARCHY_LEVELS + 1];
        loop {
            *steps = steps.saturating_add(1);
            let tx = ax.exit(nx, level);
            let ty = ay.exit(ny, level);
            let t_next = tx.min(ty);
            let span = NodeSpan { t, t_leave: t_exit.min(t_next), oz, dz, inv_z };
            if level == self.leaf_level {
                if let Some(answer) = leaf(nx, ny, &span, steps) {
                    return Some(answer);
                }
            } else {
                let mut t_first = f64::INFINITY;
                hierarchy.for_each_interval(level, nx, ny, self.mode, |lo, hi| {
                    if let Some((t0, _)) = span.part(lo, hi) {
                        t_first = t_first.min(t0);
                    }
                    t_first <= t
                });
                if t_first <= span.t_leave {
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
                    let (nodes_x, nodes_y) = self.nodes(level);
                    nx = nx.min(nodes_x - 1);
                    ny = ny.min(nodes_y - 1);
                    continue;
                }
            }
            if t_next >= t_exit || t_next.is_nan() {
                return None;
            }
            // Through a corner, step both axes at once, as the naive DDA does.
            if tx == t_next {
                nx = ax.step(nx)?;
            }
            if ty == t_next {
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
                    let limit = if level == self.leaf_level { FINE_MISSES } else { MISSES };
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
            self.hierarchy.cells()
        } else {
            self.hierarchy.nodes(level)
        }
    }
}
