//! Shared helpers of the step kernels: disjoint per-cell writes to layer-major planes from
//! parallel rows, the four neighbour directions, and fitting a column under its ceiling.

use super::lanes::Real;
use relief_core::MlhmColumn;
use std::marker::PhantomData;

/// Directions of the pipes, in the reference's order: right (+x), up (+y), left, down.
pub(crate) const OFFSETS: [(isize, isize); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// The direction opposite direction `i`.
#[inline]
pub(crate) fn opposite(i: usize) -> usize {
    (i + 2) % 4
}

/// The cell index of the neighbour of `(x, y)` in direction `i`, `None` beyond the domain's
/// walls.
#[inline]
pub(crate) fn neighbour(
    x: usize,
    y: usize,
    i: usize,
    width: usize,
    height: usize,
) -> Option<usize> {
    let (dx, dy) = OFFSETS[i];
    let nx = x.checked_add_signed(dx)?;
    let ny = y.checked_add_signed(dy)?;
    (nx < width && ny < height).then_some(nx + ny * width)
}

/// The cell indices of the four neighbours of `(x, y)` (as [`neighbour`]).
#[inline]
pub(crate) fn neighbours(x: usize, y: usize, width: usize, height: usize) -> [Option<usize>; 4] {
    let i = x + y * width;
    [
        (x + 1 < width).then_some(i + 1),
        (y + 1 < height).then_some(i + width),
        (x > 0).then(|| i - 1),
        (y > 0).then(|| i - width),
    ]
}

/// A plane that parallel rows write at disjoint slots: each kernel writes only the slots of
/// the cells of its own row (slot `x + y * width + k * width * height`), and reads through
/// the same handle only slots it writes, so no slot is touched by two threads.
pub(crate) struct Slots<'a, T> {
    ptr: *mut T,
    len: usize,
    _plane: PhantomData<&'a mut [T]>,
}

// SAFETY: the handle is shared between rayon's threads, which access disjoint slots only
// (see the type's documentation); T itself is sent between threads.
unsafe impl<T: Send> Sync for Slots<'_, T> {}
// SAFETY: as above.
unsafe impl<T: Send> Send for Slots<'_, T> {}

impl<'a, T: Copy> Slots<'a, T> {
    /// A handle on `plane`, borrowed mutably for the handle's life.
    pub(crate) fn new(plane: &'a mut [T]) -> Self {
        Slots { ptr: plane.as_mut_ptr(), len: plane.len(), _plane: PhantomData }
    }

    /// The value at slot `i`.
    ///
    /// # Safety
    /// `i` is in the plane, and no other thread writes slot `i` during the handle's life.
    #[inline]
    pub(crate) unsafe fn get(&self, i: usize) -> T {
        debug_assert!(i < self.len, "slot {i} of {}", self.len);
        // SAFETY: in bounds and no concurrent write (the caller's promise).
        unsafe { *self.ptr.add(i) }
    }

    /// Slots `start..start + len` as a slice, for a kernel's loop over a row of cells.
    ///
    /// # Safety
    /// The range is in the plane, and no other thread reads or writes its slots during the
    /// slice's life.
    #[inline]
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn row(&self, start: usize, len: usize) -> &mut [T] {
        debug_assert!(start + len <= self.len, "slots {start}..+{len} of {}", self.len);
        // SAFETY: in bounds and exclusive access (the caller's promise).
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(start), len) }
    }

    /// Writes `v` at slot `i`.
    ///
    /// # Safety
    /// `i` is in the plane, and no other thread reads or writes slot `i` during the handle's
    /// life.
    #[inline]
    pub(crate) unsafe fn set(&self, i: usize, v: T) {
        debug_assert!(i < self.len, "slot {i} of {}", self.len);
        // SAFETY: in bounds and exclusive access (the caller's promise).
        unsafe { *self.ptr.add(i) = v }
    }
}

/// The largest f32 below the positive, finite `v`.
#[inline]
fn below(v: f32) -> f32 {
    if v > 0.0 {
        f32::from_bits(v.to_bits() - 1)
    } else {
        0.0
    }
}

/// Makes `c` a valid column under its own ceiling after f32 rounding: negative sand or water
/// becomes 0, and a water top above the ceiling lowers the water, then the sand, to fit.
/// Returns the water and sand removed, m (negative when a negative value was raised to 0).
pub(crate) fn fit_column(c: &mut MlhmColumn) -> (f32, f32) {
    let (mut water, mut sand) = (0.0, 0.0);
    if c.water.is_nan() || c.water < 0.0 {
        water += c.water;
        c.water = 0.0;
    }
    if c.sand.is_nan() || c.sand < 0.0 {
        sand += c.sand;
        c.sand = 0.0;
    }
    if c.water_top() > c.ceiling {
        let old = c.water;
        c.water = (c.ceiling - c.solid_top()).max(0.0);
        while c.water > 0.0 && c.water_top() > c.ceiling {
            c.water = below(c.water);
        }
        water += old - c.water;
    }
    if c.solid_top() > c.ceiling {
        let old = c.sand;
        c.sand = (c.ceiling - c.bedrock).max(0.0);
        while c.sand > 0.0 && c.solid_top() > c.ceiling {
            c.sand = below(c.sand);
        }
        sand += old - c.sand;
    }
    (water, sand)
}

/// GLSL's smoothstep: 0 below `e0`, 1 above `e1`, a cubic in between.
#[inline]
pub(crate) fn smoothstep<R: Real>(e0: f32, e1: f32, x: R) -> R {
    let t = ((x - R::splat(e0)) / R::splat(e1 - e0)).clamp(0.0, 1.0);
    t * t * (R::splat(3.0) - R::splat(2.0) * t)
}

/// Runs `row` for every row `y` in parallel and sums what the rows return, in row order
/// (so the sum does not depend on the thread count).
pub(crate) fn par_rows<F>(height: usize, row: F) -> super::StepVolumes
where
    F: Fn(usize) -> super::StepVolumes + Sync + Send,
{
    use rayon::prelude::*;
    let parts: Vec<super::StepVolumes> = (0..height).into_par_iter().map(row).collect();
    super::StepVolumes::sum(&parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_stop_at_the_walls() {
        assert_eq!(neighbour(0, 0, 0, 3, 2), Some(1));
        assert_eq!(neighbour(0, 0, 1, 3, 2), Some(3));
        assert_eq!(neighbour(0, 0, 2, 3, 2), None);
        assert_eq!(neighbour(0, 0, 3, 3, 2), None);
        assert_eq!(neighbour(2, 1, 0, 3, 2), None);
        assert_eq!(neighbour(2, 1, 1, 3, 2), None);
        assert_eq!(opposite(1), 3);
        for (x, y) in [(0, 0), (2, 1), (1, 0), (1, 1)] {
            let all = neighbours(x, y, 3, 2);
            for (d, n) in all.into_iter().enumerate() {
                assert_eq!(n, neighbour(x, y, d, 3, 2));
            }
        }
    }

    #[test]
    fn fit_lowers_water_then_sand() {
        let mut c = MlhmColumn::new(1.0, 1.0, 2.0, 3.5);
        assert_eq!(fit_column(&mut c), (0.5, 0.0));
        assert!(c.water_top() <= c.ceiling);
        let mut c = MlhmColumn::new(1.0, 3.0, 1.0, 3.0);
        assert_eq!(fit_column(&mut c), (1.0, 1.0));
        assert_eq!(c, MlhmColumn::new(1.0, 2.0, 0.0, 3.0));
        let mut c = MlhmColumn::new(0.1, 0.7, 0.3, 1.1);
        fit_column(&mut c);
        assert!(c.water_top() <= c.ceiling);
    }
}
