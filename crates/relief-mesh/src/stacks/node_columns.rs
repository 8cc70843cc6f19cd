//! Where the layers within a node's reach lie, per column of nodes of one level: what tells
//! the mesher, without a density, that a node holds no surface (all air or all solid).

use super::lattice::Lattice;
use relief_core::{MaterialStacks, StackLayer, StackMaterial};

/// How far beyond its points a node's density reaches with filter `kernel`: its cells' ring,
/// the Sobel neighbours and the filter's half-width.
pub(crate) fn node_reach(kernel: &[f32]) -> i32 {
    3 + (kernel.len() / 2) as i32
}

/// The node columns of one level (nodes `-1 ..= size / n` along x and y, x fastest), each
/// the union of the ranges of the stacks within `reach` of its points; a node column reaching
/// beyond the grid is never solid throughout.
pub(crate) fn node_columns(
    stacks: &MaterialStacks,
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
pub(crate) struct ColumnRange {
    /// The bottom of the lowest layer.
    pub start: f32,
    /// The top of the highest layer.
    pub end: f32,
    /// The bottom of the solid run (`+inf` where there is none).
    pub solid_start: f32,
    /// The top of the solid run (`-inf` where there is none).
    pub solid_end: f32,
}

impl ColumnRange {
    /// A column with no layer.
    const EMPTY: ColumnRange = ColumnRange {
        start: f32::INFINITY,
        end: f32::NEG_INFINITY,
        solid_start: f32::INFINITY,
        solid_end: f32::NEG_INFINITY,
    };

    /// The range of `stack`, whose layers are of `materials`, on `lattice`.
    fn of(stack: &[StackLayer], materials: &[StackMaterial], lattice: &Lattice) -> Self {
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
