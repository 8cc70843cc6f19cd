//! The vertex-centred lattice a level's density is sampled on ([`Lattice`]) and boxes of its
//! points ([`Block`]).

use relief_core::{DVec3, MaterialStacks};

/// Where a level's lattice points lie: point `(i, j, k)` at the centre of stack `(i, j)`
/// horizontally and at height `z0 + k * step` vertically, `step` doubling with every level so
/// that a coarser level's points coincide with every other point of the finer one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Lattice {
    /// World x, y of point (0, 0).
    pub origin: DVec3,
    /// World distance between neighbouring points along x, y, z.
    pub step: DVec3,
}

impl Lattice {
    /// The lattice of `level` (0 finest) of stacks whose level 0 is `stacks0`, with vertical
    /// step `dz0` at level 0 and point k = 0 at height `z0`.
    pub fn new(level_stacks: &MaterialStacks, level: usize, z0: f64, dz0: f64) -> Self {
        let s = level_stacks.spacing();
        let o = level_stacks.origin();
        Lattice {
            origin: DVec3::new(o.x + 0.5 * s.x, o.y + 0.5 * s.y, z0),
            step: DVec3::new(s.x, s.y, dz0 * (1u64 << level) as f64),
        }
    }

    /// A height in lattice units along z.
    #[inline]
    pub fn to_k(self, z: f32) -> f64 {
        (z as f64 - self.origin.z) / self.step.z
    }

    /// World position of fractional lattice coordinates.
    #[inline]
    pub fn world(&self, p: [f64; 3]) -> DVec3 {
        self.origin + DVec3::new(p[0], p[1], p[2]) * self.step
    }
}

/// A box of lattice points: `size[a]` points from `min[a]` along each axis, x fastest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Block {
    /// The first point.
    pub min: [i32; 3],
    /// Points along each axis.
    pub size: [usize; 3],
}

impl Block {
    /// The points from `min` (inclusive) to `max` (exclusive).
    pub fn between(min: [i32; 3], max: [i32; 3]) -> Self {
        Block { min, size: std::array::from_fn(|a| (max[a] - min[a]).max(0) as usize) }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.size[0] * self.size[1] * self.size[2]
    }

    /// Index of local coordinates.
    #[inline]
    pub fn index(&self, l: [usize; 3]) -> usize {
        l[0] + self.size[0] * (l[1] + self.size[1] * l[2])
    }

    /// Index of lattice point `p`, which must lie in the block.
    #[inline]
    pub fn index_of(&self, p: [i32; 3]) -> usize {
        debug_assert!(self.contains(p), "{p:?} outside {self:?}");
        self.index(std::array::from_fn(|a| (p[a] - self.min[a]) as usize))
    }

    /// Lattice point of index `i`.
    #[inline]
    pub fn point(&self, i: usize) -> [i32; 3] {
        let x = i % self.size[0];
        let y = (i / self.size[0]) % self.size[1];
        let z = i / (self.size[0] * self.size[1]);
        [self.min[0] + x as i32, self.min[1] + y as i32, self.min[2] + z as i32]
    }

    /// Whether `p` lies in the block.
    #[inline]
    pub fn contains(&self, p: [i32; 3]) -> bool {
        (0..3).all(|a| p[a] >= self.min[a] && p[a] < self.min[a] + self.size[a] as i32)
    }
}
