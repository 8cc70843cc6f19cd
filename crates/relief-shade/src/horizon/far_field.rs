//! The far field of a window: the horizons of a window's samples are found by the lanes over the
//! window, and then, where a line leaves the window before it leaves the raster, along the rest
//! of the line through the whole raster, read on demand ([`FarTerrain`]). The points past the
//! window are the lanes' points (the same [`StencilLine`]) and their slopes the same f64
//! arithmetic, so a window's horizons are bit for bit those of the whole raster in memory.
//! Stretches too low to raise a horizon are skipped by the raster's [`CoarseBounds`].

use super::coarse_bounds::CoarseBounds;
use super::lane_frame::OUTSIDE;
use super::lanes::main_split;
use super::stencil::Stencil;
use super::stencil::{Coefficients, StencilLine, Step};
use crate::ShadeError;
use std::ops::Range;
use std::sync::{Arc, Mutex};

/// A rectangle of a raster's samples, shared: a tile of a store with its ring, or a whole
/// raster in memory. Sample (`col`, `row`) of the raster is `samples[(col - x0) + (row - y0) *
/// width]` where it lies in the rectangle and in the raster.
#[derive(Clone)]
pub struct SamplePatch {
    /// The samples, row-major, rows from the south, NaN a void.
    pub samples: Arc<Vec<f32>>,
    /// The raster column and row of the first sample (the first may lie just outside the
    /// raster: a ring).
    pub x0: isize,
    /// See `x0`.
    pub y0: isize,
    /// Samples a row, and rows.
    pub width: usize,
    /// See `width`.
    pub height: usize,
}

impl SamplePatch {
    #[inline(always)]
    fn get(&self, col: isize, row: isize) -> Option<f32> {
        let (x, y) = (col - self.x0, row - self.y0);
        (x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height)
            .then(|| self.samples[x as usize + y as usize * self.width])
    }
}

/// The whole raster around a window, read on demand: a tile store, or an array in memory.
pub trait FarTerrain: Sync {
    /// The raster's bounds (and through them, its size).
    fn bounds(&self) -> &CoarseBounds;
    /// A patch that holds sample (`col`, `row`) of the raster (which lies in it).
    fn patch(&self, col: usize, row: usize) -> Result<SamplePatch, ShadeError>;
}

/// A raster in memory as a [`FarTerrain`].
pub struct FarSamples {
    whole: SamplePatch,
    bounds: CoarseBounds,
}

impl FarSamples {
    /// The row-major `width x height` grid `samples`.
    pub fn new(samples: Arc<Vec<f32>>, width: usize, height: usize) -> FarSamples {
        let bounds = CoarseBounds::of_samples(&samples, width, height);
        FarSamples { whole: SamplePatch { samples, x0: 0, y0: 0, width, height }, bounds }
    }
}

impl FarTerrain for FarSamples {
    fn bounds(&self) -> &CoarseBounds {
        &self.bounds
    }

    fn patch(&self, _col: usize, _row: usize) -> Result<SamplePatch, ShadeError> {
        Ok(self.whole.clone())
    }
}

/// Where a window lies in the raster of a [`FarTerrain`]: its first column and row.
#[derive(Clone, Copy)]
pub struct FarField<'a> {
    /// The whole raster.
    pub terrain: &'a dyn FarTerrain,
    /// The window's first column in the raster.
    pub col0: usize,
    /// The window's first row in the raster.
    pub row0: usize,
}

/// The first error met reading a far field (the horizons found after it are not used).
#[derive(Default)]
pub(crate) struct FarError(Mutex<Option<ShadeError>>);

impl FarError {
    fn keep(&self, error: ShadeError) {
        let mut slot = self.0.lock().unwrap_or_else(|e| e.into_inner());
        slot.get_or_insert(error);
    }

    /// The error met, if any.
    pub(crate) fn take(&self) -> Option<ShadeError> {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).take()
    }
}

/// Steps of the largest stretch tested against the bounds at once (as a power of two).
const TOP_LEVEL: u32 = 12;
/// Steps whose points are read and tested one by one, together (as a power of two).
const LEAF_LEVEL: u32 = 3;
/// The stride of the offsets of a far line's points: columns are offsets modulo it.
const FAR_STRIDE_BITS: u32 = 32;

/// Splits a far line's point offset into its column and row offsets.
#[inline]
fn decode(offset: isize) -> (isize, isize) {
    let row = (offset + (1 << (FAR_STRIDE_BITS - 1))) >> FAR_STRIDE_BITS;
    (offset - (row << FAR_STRIDE_BITS), row)
}

/// One direction's line through the whole raster, as the lanes' frame of that direction sees
/// it (rows and columns swapped where `transposed`), and the window within it.
pub(crate) struct FarLine {
    line: StencilLine,
    transposed: bool,
    sign: f32,
    upside_down: bool,
    /// The raster's frame: columns and rows.
    frame_width: usize,
    frame_height: usize,
    /// The window in the raster's frame: its columns and rows.
    window_x: Range<usize>,
    window_y: Range<usize>,
    /// The line's steps over the whole raster, made on first use and dropped by
    /// [`FarLine::release`].
    stencil: Mutex<Option<Arc<Stencil>>>,
}

/// The patches a far walk reads its samples from, the most recent first.
#[derive(Default)]
pub(crate) struct Patch {
    recent: Vec<SamplePatch>,
}

/// Patches a walk keeps at hand.
const KEPT_PATCHES: usize = 4;

impl Patch {
    /// Sample (`col`, `row`) of the raster (which lies in it), from a patch at hand or a new
    /// one.
    #[inline(always)]
    fn sample(
        &mut self,
        terrain: &dyn FarTerrain,
        col: isize,
        row: isize,
    ) -> Result<f32, ShadeError> {
        for (i, patch) in self.recent.iter().enumerate() {
            if let Some(v) = patch.get(col, row) {
                if i > 0 {
                    self.recent.swap(0, i);
                }
                return Ok(v);
            }
        }
        let patch = terrain.patch(col as usize, row as usize)?;
        let v = patch.get(col, row).ok_or_else(|| {
            ShadeError::Limits(format!("the far field's patch misses sample ({col}, {row})"))
        })?;
        if self.recent.len() == KEPT_PATCHES {
            self.recent.pop();
        }
        self.recent.insert(0, patch);
        Ok(v)
    }
}

impl FarLine {
    /// The far line of a direction whose line in the window's frame is `line`, for a window of
    /// `window_width x window_height` samples placed by `far`, seen `facing` up (`sign`).
    pub(crate) fn new(
        line: &StencilLine,
        transposed: bool,
        sign: f32,
        far: &FarField,
        window_width: usize,
        window_height: usize,
    ) -> FarLine {
        let (width, height) = far.terrain.bounds().size();
        let (frame_width, frame_height) =
            if transposed { (height, width) } else { (width, height) };
        let (cols, rows) = (far.col0..far.col0 + window_width, far.row0..far.row0 + window_height);
        let (window_x, window_y) = if transposed { (rows, cols) } else { (cols, rows) };
        FarLine {
            line: StencilLine {
                stride: 1 << FAR_STRIDE_BITS,
                column_major: false,
                radius_steps: None,
                ..*line
            },
            transposed,
            sign,
            upside_down: sign < 0.0,
            frame_width,
            frame_height,
            window_x,
            window_y,
            stencil: Mutex::new(None),
        }
    }

    /// The line's steps over the whole raster.
    fn stencil(&self) -> Arc<Stencil> {
        let mut kept = self.stencil.lock().unwrap_or_else(|e| e.into_inner());
        kept.get_or_insert_with(|| {
            Arc::new(Stencil::new(&self.line, self.frame_width.saturating_sub(1).max(1)))
        })
        .clone()
    }

    /// Drops the line's steps (made again if needed).
    pub(crate) fn release(&self) {
        *self.stencil.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }

    /// The signed sample at (`x`, `y`) of the raster's frame, [`OUTSIDE`] beyond the raster.
    #[inline(always)]
    fn frame_sample(
        &self,
        terrain: &dyn FarTerrain,
        patch: &mut Patch,
        x: isize,
        y: isize,
    ) -> Result<f32, ShadeError> {
        if x < 0 || y < 0 || x as usize >= self.frame_width || y as usize >= self.frame_height {
            return Ok(OUTSIDE);
        }
        let (col, row) = if self.transposed { (y, x) } else { (x, y) };
        Ok(self.sign * patch.sample(terrain, col, row)?)
    }

    /// The columns and rows of the raster's frame that the points of steps `from..=to` of the
    /// line from (`x`, `y`) read (not clipped).
    fn reach(&self, x: usize, y: usize, from: usize, to: usize) -> ([isize; 2], [isize; 2]) {
        let (sx, m) = (self.line.step_x, self.line.rows_per_step);
        let (xa, xb) = (x as isize + sx * (from as isize - 1), x as isize + sx * to as isize);
        let (ya, yb) = (y as f64 + m * (from as f64 - 1.0), y as f64 + m * to as f64);
        let (low, high) = (ya.min(yb).floor() as isize - 1, ya.max(yb).floor() as isize + 2);
        ([xa.min(xb), xa.max(xb)], [low, high])
    }

    /// The steps of the line from frame sample (`x`, `y`) that may read a sample outside the
    /// window and inside the raster.
    fn far_steps(&self, x: usize, y: usize) -> Range<usize> {
        let (sx, m) = (self.line.step_x, self.line.rows_per_step);
        let (x, y) = (x as f64, y as f64);
        // Steps before `inside` read only samples of the window (with a margin of a step);
        // steps up to `last` read some sample of the raster.
        let (wx, wy) = (&self.window_x, &self.window_y);
        let mut inside = if sx > 0 { wx.end as f64 - 1.0 - x } else { x - wx.start as f64 };
        let mut last = if sx > 0 { self.frame_width as f64 - x } else { x + 1.0 };
        if m > 0.0 {
            inside = inside.min((wy.end as f64 - 3.0 - y) / m);
            last = last.min((self.frame_height as f64 + 1.0 - y) / m + 1.0);
        } else if m < 0.0 {
            inside = inside.min((y - wy.start as f64 - 2.0) / -m);
            last = last.min((y + 2.0) / -m + 1.0);
        }
        let first = (inside.floor() - 1.0).max(1.0) as usize;
        let last = last.ceil().max(0.0) as usize + 1;
        first..last.max(first)
    }

    /// The highest signed sample the steps `from..=to` of the line from (`x`, `y`) may read.
    fn highest(&self, bounds: &CoarseBounds, x: usize, y: usize, from: usize, to: usize) -> f32 {
        let ([x0, x1], [y0, y1]) = self.reach(x, y, from, to);
        let clip = |a: isize, b: isize, n: usize| {
            let (a, b) = (a.max(0) as usize, (b + 1).clamp(0, n as isize) as usize);
            (a < b).then_some(a..b)
        };
        let (Some(xs), Some(ys)) =
            (clip(x0, x1, self.frame_width), clip(y0, y1, self.frame_height))
        else {
            return OUTSIDE;
        };
        let (cols, rows) = if self.transposed { (ys, xs) } else { (xs, ys) };
        let [low, high] = bounds.span(cols, rows);
        if self.sign > 0.0 {
            high
        } else {
            -low
        }
    }

    /// The steepest slope from the observer over frame sample (`x`, `y`), whose signed sample
    /// is `z0`, to the points of its line past the window, or `best` if none is steeper.
    pub(crate) fn raise(
        &self,
        terrain: &dyn FarTerrain,
        patch: &mut Patch,
        x: usize,
        y: usize,
        z0: f32,
        mut best: f64,
    ) -> Result<f64, ShadeError> {
        let steps = self.far_steps(x, y);
        if steps.is_empty() {
            return Ok(best);
        }
        let bounds = terrain.bounds();
        let stencil = self.stencil();
        let last = (steps.end - 1).min(stencil.len());
        let z0_64 = f64::from(z0);
        let mut k = steps.start;
        let mut level = TOP_LEVEL;
        while k <= last {
            let to = (k + (1 << level) - 1).min(last);
            if level > LEAF_LEVEL {
                let highest = self.highest(bounds, x, y, k, to);
                if f64::from(highest) <= self.ceiling(z0_64, best, k, to) {
                    k = to + 1;
                    level = (level + 1).min(TOP_LEVEL);
                } else {
                    level -= 1;
                }
                continue;
            }
            for step in &stencil.steps[k..=to] {
                best = self.test_step(terrain, patch, step, x as isize, y as isize, z0_64, best)?;
            }
            k = to + 1;
            level = LEAF_LEVEL + 1;
        }
        Ok(best)
    }

    /// The lowest a signed sample of steps `from..=to` may lie and still raise `best` from an
    /// observer over `z0`, less a margin for rounding.
    fn ceiling(&self, z0: f64, best: f64, from: usize, to: usize) -> f64 {
        let line = &self.line;
        let t = if best < 0.0 { to as f64 } else { from as f64 - 1.0 } * line.metres_per_step;
        let rise = (best * t + line.observer_height) / line.z_scale;
        let ceiling = z0 + rise;
        ceiling - 1e-9 * (1.0 + z0.abs() + rise.abs())
    }

    /// Raises `best` to the steepest slope of a point of `step` of the line from (`x`, `y`).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn test_step(
        &self,
        terrain: &dyn FarTerrain,
        patch: &mut Patch,
        step: &Step,
        x: isize,
        y: isize,
        z0: f64,
        mut best: f64,
    ) -> Result<f64, ShadeError> {
        let mut sample = |offset: isize, dx: isize, dy: isize| {
            let (c, r) = decode(offset);
            self.frame_sample(terrain, patch, x + c + dx, y + r + dy)
        };
        let slope = |a: f32, b: f32, w: f64, c: &Coefficients| {
            let (da, db) = (f64::from(a) - z0, f64::from(b) - z0);
            (da + w * (db - da)) * c.scale64 - c.lift64
        };
        for e in &step.edges {
            if e.coefficients.lift64 == f64::INFINITY {
                continue;
            }
            // A point beside the raster's edge reads the padding as the lanes do (at `w` 0
            // its slope is the sample's own).
            let (a, b) = (sample(e.a, 0, 0)?, sample(e.b, 0, 0)?);
            best = best.max(slope(a, b, e.w64, &e.coefficients));
        }
        for d in &step.diagonals {
            if d.main_coefficients.lift64 == f64::INFINITY
                && d.anti_coefficients.lift64 == f64::INFINITY
            {
                continue;
            }
            let z00 = sample(d.corner, 0, 0)?;
            let z10 = sample(d.corner, 1, 0)?;
            let z01 = sample(d.corner, 0, 1)?;
            let z11 = sample(d.corner, 1, 1)?;
            let s = if main_split(z00, z10, z01, z11, self.upside_down) {
                slope(z00, z11, d.main, &d.main_coefficients)
            } else {
                slope(z01, z10, d.anti, &d.anti_coefficients)
            };
            best = best.max(s);
        }
        Ok(best)
    }
}

/// A far field's lines, errors and scratch, for one engine.
pub(crate) struct FarContext<'a> {
    pub field: FarField<'a>,
    pub error: FarError,
}

impl FarContext<'_> {
    /// `best` raised over the far part of the line of `line` from frame sample (`x`, `y`) of
    /// the window (signed sample `z0`); on a read error, kept for the caller, `best`.
    pub(crate) fn raise(
        &self,
        line: &FarLine,
        patch: &mut Patch,
        x: usize,
        y: usize,
        z0: f32,
        best: f64,
    ) -> f64 {
        let (gx, gy) = if line.transposed {
            (x + self.field.row0, y + self.field.col0)
        } else {
            (x + self.field.col0, y + self.field.row0)
        };
        match line.raise(self.field.terrain, patch, gx, gy, z0, best) {
            Ok(best) => best,
            Err(error) => {
                self.error.keep(error);
                best
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_decode_to_their_column_and_row() {
        for (c, r) in [(0, 0), (-1, 0), (5, -3), (-7, -2), (40_000, 30_000), (-40_000, 1)] {
            let offset = c + (r << FAR_STRIDE_BITS);
            assert_eq!(decode(offset), (c, r));
        }
    }
}
