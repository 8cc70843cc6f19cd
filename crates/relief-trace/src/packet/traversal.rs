//! Front-to-back depth-first traversal of the max mipmap by a packet of rays.
//!
//! The pyramid is walked as a tree of boxes: a node's box is its footprint below its maximum.
//! A node is opened when any ray of the packet may pass below its maximum over its
//! footprint, and its four children are tested at once with the rays that passed. Children
//! are visited in the order the packet's rays meet them (their direction signs are the same),
//! so along every ray the nodes come in the order of `t`: the first cell whose exact test
//! hits holds the ray's first hit, and the ray leaves the packet there.

use super::kernel::Kernel;
use super::ray_packet::{CellBox, Plane, Quad, RayPacket, LANES, ORDER, PACKET_RAYS};
use crate::cell_grid::CellGrid;
use crate::MaxMipmap;
use relief_core::{DVec3, Surface};

/// What the traversal reads of the terrain.
pub(crate) struct Terrain<'a> {
    /// The surface's cells and their exact test.
    pub grid: &'a CellGrid,
    /// The height field's samples.
    pub samples: &'a [f32],
    /// The pyramid of maxima over the cells.
    pub mipmap: &'a MaxMipmap,
}

/// A ray's first hit in cell space: the parameter and the grid-space normal, as
/// [`CellGrid::intersect_cell`] gives them.
pub(crate) type CellHit = Option<(f64, DVec3)>;

/// The positions 0..4 of [`ORDER`].
const ORDER_INDEX: [usize; 4] = [0, 1, 2, 3];

/// Depth of the traversal stack: three siblings waiting per level, for up to 32 levels.
pub(crate) const STACK: usize = 3 * 32 + 1;

/// A node waiting on the stack with the rays that passed its test.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Pending {
    rays: u64,
    x: u32,
    y: u32,
    level: u32,
}

/// One packet's walk through the pyramid, advanced a node at a time by [`trace`].
pub(crate) struct Traversal<'a> {
    /// The rays; their steps count node visits.
    pub packet: &'a mut RayPacket,
    /// The hits of the rays that hit, indexed as the packet's rays (the others are left as
    /// they are).
    pub hits: &'a mut [CellHit; PACKET_RAYS],
    stack: &'a mut [Pending; STACK],
    /// Nodes waiting on the stack.
    len: usize,
    /// The rays that hit.
    done: u64,
}

impl<'a> Traversal<'a> {
    /// The walk of `packet` from the top of `terrain`'s pyramid, with `stack` as scratch.
    pub fn new(
        terrain: &Terrain,
        packet: &'a mut RayPacket,
        hits: &'a mut [CellHit; PACKET_RAYS],
        stack: &'a mut [Pending; STACK],
    ) -> Self {
        // A grid of one cell has no stored level: start from a virtual level-1 node over it.
        let top = terrain.mipmap.top_level().max(1) as u32;
        stack[0] = Pending { level: top, x: 0, y: 0, rays: packet.all() };
        Traversal { packet, hits, stack, len: 1, done: 0 }
    }

    /// Visits the next node; `false` once the walk is over.
    #[inline(always)]
    fn step<K: Kernel>(&mut self, terrain: &Terrain) -> bool {
        let p = &mut *self.packet;
        let walk = Walk { terrain, flip_x: p.negative_x as usize, flip_y: p.negative_y as usize };
        let node = loop {
            if self.len == 0 {
                return false;
            }
            self.len -= 1;
            let node = self.stack[self.len];
            if node.rays & !self.done != 0 {
                break node;
            }
        };
        let rays = node.rays & !self.done;
        let (x, y) = (node.x as usize, node.y as usize);
        if node.level == 1 {
            walk.cells_of::<K>(p, x, y, rays, &mut self.done, self.hits);
            if self.done == p.all() {
                self.len = 0;
            }
            return self.len > 0;
        }
        let level = node.level as usize - 1;
        let block = terrain.mipmap.children(level, x, y);
        let quad = walk.quad(level, x, y, ORDER_INDEX.map(|c| block[c ^ walk.flip()]));
        let open = test_children::<K>(p, &quad, rays);
        for c in (0..4).rev() {
            if open[c] != 0 {
                let (i, j) = ORDER[c];
                let (cx, cy) = (2 * x + (i ^ walk.flip_x), 2 * y + (j ^ walk.flip_y));
                walk.prefetch_below(level, cx, cy);
                self.stack[self.len] =
                    Pending { level: level as u32, x: cx as u32, y: cy as u32, rays: open[c] };
                self.len += 1;
            }
        }
        self.len > 0
    }
}

/// Walks every traversal to its end, a node of each in turn: the packets' work does not
/// depend on each other, so the processor can overlap it.
#[inline(always)]
pub(crate) fn trace<K: Kernel>(terrain: &Terrain, walks: &mut [Traversal]) {
    let mut busy = true;
    while busy {
        busy = false;
        for walk in walks.iter_mut() {
            busy |= walk.step::<K>(terrain);
        }
    }
}

/// For each child of `quad`, the rays among `rays` that pass `K::children`, group by group.
#[inline(always)]
fn test_children<K: Kernel>(p: &mut RayPacket, quad: &Quad, rays: u64) -> [u64; 4] {
    let mut open = [0u64; 4];
    for g in groups(rays) {
        let active = (rays >> (g * LANES)) as u8;
        let passed = K::children(p, g, quad, active);
        for c in 0..4 {
            open[c] |= (passed[c] as u64) << (g * LANES);
        }
    }
    open
}

/// The groups of [`LANES`] rays that hold at least one ray of `rays`, in order.
#[inline(always)]
fn groups(rays: u64) -> impl Iterator<Item = usize> {
    // Fold each byte onto its lowest bit, then gather those eight bits into one byte: bit
    // 8g times bit 7(8 - g) of the constant lands on bit 56 + g, and no two products meet.
    let mut folded = rays | (rays >> 4);
    folded |= folded >> 2;
    folded |= folded >> 1;
    let mut mask =
        ((folded & 0x0101_0101_0101_0101).wrapping_mul(0x0102_0408_1020_4080) >> 56) as u32;
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let g = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            g
        })
    })
}

/// The walk's constants: the terrain and the packet's mirroring.
struct Walk<'a> {
    terrain: &'a Terrain<'a>,
    /// 1 when the packet runs towards decreasing x: children are then met right to left.
    flip_x: usize,
    /// 1 when the packet runs towards decreasing y.
    flip_y: usize,
}

impl Walk<'_> {
    /// `i + 2 j` of a child `(i, j)` of [`ORDER`] in the packet's mirroring: the child met
    /// `c`-th is the one at `c ^ flip()` in a block of [`MaxMipmap::children`].
    #[inline(always)]
    fn flip(&self) -> usize {
        self.flip_x + 2 * self.flip_y
    }

    /// The four children at `level` (cells at 0) of node (x, y) one level up, clamped to the
    /// grid, with their tops in [`ORDER`].
    #[inline(always)]
    fn quad(&self, level: usize, x: usize, y: usize, top: [f32; 4]) -> Quad {
        let grid = self.terrain.grid;
        let (cells_x, cells_y) = (grid.cells_x(), grid.cells_y());
        let side = 1usize << level;
        let (x0, y0) = (2 * x * side, 2 * y * side);
        let xs = [x0, (x0 + side).min(cells_x), (x0 + 2 * side).min(cells_x)];
        let ys = [y0, (y0 + side).min(cells_y), (y0 + 2 * side).min(cells_y)];
        let order = |b: [usize; 3], flip: usize| {
            let b = b.map(|v| v as f32);
            if flip == 1 {
                [b[2], b[1], b[0]]
            } else {
                b
            }
        };
        Quad { x: order(xs, self.flip_x), y: order(ys, self.flip_y), top }
    }

    /// Asks the memory system early for what testing the children of node (x, y) of `level`
    /// will read: their maxima, or for a level-1 node the samples of its cells.
    #[inline(always)]
    fn prefetch_below(&self, level: usize, x: usize, y: usize) {
        if level >= 2 {
            prefetch(self.terrain.mipmap.children(level - 1, x, y));
        } else {
            let (grid, samples) = (self.terrain.grid, self.terrain.samples);
            for row in 2 * y..2 * y + 3 {
                if let Some(sample) = grid.sample_ref(samples, 2 * x, row) {
                    prefetch(sample);
                }
            }
        }
    }

    /// Tests the (up to four) cells of level-1 node (x, y) in the order the rays meet them.
    #[inline(always)]
    fn cells_of<K: Kernel>(
        &self,
        p: &mut RayPacket,
        x: usize,
        y: usize,
        rays: u64,
        done: &mut u64,
        hits: &mut [CellHit; PACKET_RAYS],
    ) {
        let Terrain { grid, samples, .. } = *self.terrain;
        let corners = grid.quad_corners(samples, x, y);
        let top = ORDER_INDEX
            .map(|k| corners[k ^ self.flip()].into_iter().fold(f32::NEG_INFINITY, f32::max));
        let quad = self.quad(0, x, y, top);
        let open = test_children::<K>(p, &quad, rays);
        for (c, &(i, j)) in ORDER.iter().enumerate() {
            let rays = open[c] & !*done;
            if rays == 0 {
                continue;
            }
            let (cx, cy) = (2 * x + (i ^ self.flip_x), 2 * y + (j ^ self.flip_y));
            let candidates = match grid.surface() {
                Surface::Boxes => rays,
                Surface::Triangles => {
                    let cell = CellBox {
                        near_x: quad.x[i],
                        far_x: quad.x[i + 1],
                        near_y: quad.y[j],
                        far_y: quad.y[j + 1],
                    };
                    below_planes::<K>(p, corners[c ^ self.flip()], (cx, cy), &cell, rays)
                }
            };
            self.exact(p, cx, cy, candidates, done, hits);
        }
    }

    /// The exact test of cell (cx, cy) for every ray of `candidates`; a ray that hits is done.
    #[inline(always)]
    fn exact(
        &self,
        p: &RayPacket,
        cx: usize,
        cy: usize,
        mut candidates: u64,
        done: &mut u64,
        hits: &mut [CellHit; PACKET_RAYS],
    ) {
        let Terrain { grid, samples, .. } = *self.terrain;
        while candidates != 0 {
            let k = candidates.trailing_zeros() as usize;
            candidates &= candidates - 1;
            let (ray, clip) = (&p.rays[k], &p.clips[k]);
            let seg = grid.segment(ray, clip, cx, cy);
            if let Some(hit) = grid.intersect_cell(samples, ray, cx, cy, &seg) {
                hits[k] = Some(hit);
                *done |= 1 << k;
            }
        }
    }
}

/// The rays among `rays` that may pass below the two planes of the `triangles` cell with
/// corner heights `corners` (see [`triangle_planes`]).
#[inline(always)]
fn below_planes<K: Kernel>(
    p: &mut RayPacket,
    corners: [f32; 4],
    (cx, cy): (usize, usize),
    cell: &CellBox,
    rays: u64,
) -> u64 {
    let (planes, magnitude) = triangle_planes(corners);
    let slack = [p.plane_slack(&planes[0], magnitude), p.plane_slack(&planes[1], magnitude)];
    let corner = (cx as f32, cy as f32);
    let mut passed = 0;
    for g in groups(rays) {
        let active = (rays >> (g * LANES)) as u8;
        let m = K::below_planes(p, g, cell, corner, &planes, slack, active);
        passed |= (m as u64) << (g * LANES);
    }
    passed
}

/// The two planes of a `triangles` cell with corner heights `[a, b, c, d]` (lower left, lower
/// right, upper left, upper right), split as [`CellGrid`]'s exact test splits it, and the sum
/// of the corners' magnitudes (for the rounding slack).
#[inline(always)]
fn triangle_planes([a, b, c, d]: [f32; 4]) -> ([Plane; 2], f32) {
    // The diagonal is chosen in f64, exactly as the exact test chooses it.
    let planes = if a as f64 + d as f64 <= b as f64 + c as f64 {
        [Plane { p0: a, pu: b - a, pv: d - b }, Plane { p0: a, pu: d - c, pv: c - a }]
    } else {
        [Plane { p0: a, pu: b - a, pv: c - a }, Plane { p0: b + c - d, pu: d - c, pv: d - b }]
    };
    (planes, a.abs() + b.abs() + c.abs() + d.abs())
}

/// A hint that `value` will be read soon.
#[inline(always)]
pub(crate) fn prefetch<T>(value: &T) {
    prefetch_address(value as *const T);
}

/// A hint that the memory at `address` will be read soon: any address, in bounds or not (a
/// prefetch never faults and reads nothing into the program).
#[inline(always)]
pub(crate) fn prefetch_address<T>(address: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: prefetching is a hint that never faults; SSE is part of x86-64.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(address as *const i8);
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = address;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_are_the_bytes_holding_rays() {
        for rays in [0u64, 1, 0x80, 0x100, u64::MAX, 0x8000_0000_0000_0000, 0x00ff_0000_0100_0001] {
            let want: Vec<usize> = (0..8).filter(|g| (rays >> (8 * g)) & 0xff != 0).collect();
            assert_eq!(groups(rays).collect::<Vec<_>>(), want, "{rays:#x}");
        }
    }
}
