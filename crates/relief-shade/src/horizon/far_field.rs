//! The far field of a window: the horizons of a window's samples are found by the lanes over the
//! window, and then, where a line leaves the window before it leaves the raster, along the rest
//! of the line through the whole raster, read on demand ([`FarTerrain`]). The points past the
//! window are the lanes' points (the same [`StencilLine`]) and their slopes the same f64
//! arithmetic, so a window's horizons are bit for bit those of the whole raster in memory.
//! Stretches too low to raise a horizon are skipped by the raster's [`CoarseBounds`].

use super::coarse_bounds::CoarseBounds;
use super::lane_frame::{LANES, OUTSIDE};
use super::lane_vector::{LaneVector, Portable};
#[cfg(target_arch = "x86_64")]
use super::lane_vector::Avx512;
use super::lanes::{test_step, Best, Grid};
use super::stencil::Stencil;
use super::stencil::StencilLine;
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

impl Patch {
    /// A patch that holds samples `first` and `last` (column, row) of the raster (and so the
    /// rectangle between), from those at hand or a new one; `None` where the patch of `first`
    /// does not hold `last`.
    #[inline(always)]
    fn holding(
        &mut self,
        terrain: &dyn FarTerrain,
        first: [isize; 2],
        last: [isize; 2],
    ) -> Result<Option<&SamplePatch>, ShadeError> {
        let holds = |p: &SamplePatch| p.get(first[0], first[1]).is_some() && p.get(last[0], last[1]).is_some();
        if let Some(i) = self.recent.iter().position(holds) {
            if i > 0 {
                self.recent.swap(0, i);
            }
            return Ok(Some(&self.recent[0]));
        }
        self.sample(terrain, first[0], first[1])?;
        Ok(self.recent.first().filter(|p| holds(p)))
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
        let bounds = far.terrain.bounds();
        let (width, height) = bounds.size();
        // The slopes' error bound counts heights differing by the whole raster's range.
        let [low, high] = bounds.span(0..width.max(1), 0..height.max(1));
        let height_range = (f64::from(high) - f64::from(low)).max(line.height_range);
        let (frame_width, frame_height) =
            if transposed { (height, width) } else { (width, height) };
        let (cols, rows) = (far.col0..far.col0 + window_width, far.row0..far.row0 + window_height);
        let (window_x, window_y) = if transposed { (rows, cols) } else { (cols, rows) };
        FarLine {
            line: StencilLine {
                stride: COPY_STRIDE,
                column_major: true,
                height_range,
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
    /// lines from (`x`, `y + i`), `i < LANES`, read (not clipped).
    fn reach(&self, x: usize, y: usize, from: usize, to: usize) -> ([isize; 2], [isize; 2]) {
        let (sx, m) = (self.line.step_x, self.line.rows_per_step);
        let (xa, xb) = (x as isize + sx * (from as isize - 1), x as isize + sx * to as isize);
        let (ya, yb) = (y as f64 + m * (from as f64 - 1.0), y as f64 + m * to as f64);
        let (low, high) = (ya.min(yb).floor() as isize - 1, ya.max(yb).floor() as isize + 2);
        let high = high + LANES as isize - 1;
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

    /// The highest signed sample the steps `from..=to` of the lines from (`x`, `y + i`), `i <
    /// LANES`, may read.
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

    /// Raises the `best` slopes of the wanted lanes (lane `i` the observer over frame sample
    /// (`x`, `y + i`), whose signed sample is `z0[i]`) to the steepest slopes to the points
    /// of their lines past the window. The lanes walk the far steps of any of them together:
    /// the rest of the steps read the window (whose points the lanes over the window found,
    /// by the same arithmetic) or nothing of the raster, so they change no lane's best.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn raise_lanes(
        &self,
        terrain: &dyn FarTerrain,
        patch: &mut Patch,
        x: usize,
        y: usize,
        z0: &[f32; LANES],
        wanted: &[bool; LANES],
        best: &mut [f64; LANES],
    ) -> Result<(), ShadeError> {
        let lanes = FarLanes { x, y, z0, wanted };
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor has AVX-512 F (checked just above).
            #[allow(unsafe_code)]
            return unsafe { self.walk_avx512(terrain, patch, &lanes, best) };
        }
        self.walk::<Portable>(terrain, patch, &lanes, best)
    }

    /// [`FarLine::walk`] in AVX-512 registers (the same operations, no fused multiply-add:
    /// the same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx2")]
    fn walk_avx512(
        &self,
        terrain: &dyn FarTerrain,
        patch: &mut Patch,
        lanes: &FarLanes,
        best: &mut [f64; LANES],
    ) -> Result<(), ShadeError> {
        self.walk::<Avx512>(terrain, patch, lanes, best)
    }

    /// See [`FarLine::raise_lanes`]: stretches of steps are skipped by the raster's bounds,
    /// and the points of the rest are tested as the lanes over a window test theirs, from a
    /// copy of the samples that the stretch's points read.
    #[inline(always)]
    fn walk<V: LaneVector>(
        &self,
        terrain: &dyn FarTerrain,
        patch: &mut Patch,
        lanes: &FarLanes,
        best: &mut [f64; LANES],
    ) -> Result<(), ShadeError> {
        let (x, y) = (lanes.x, lanes.y);
        let steps = (0..LANES)
            .filter(|&i| lanes.wanted[i])
            .map(|i| self.far_steps(x, y + i))
            .filter(|s| !s.is_empty())
            .reduce(|a, b| a.start.min(b.start)..a.end.max(b.end));
        let Some(steps) = steps else {
            return Ok(());
        };
        let bounds = terrain.bounds();
        let stencil = self.stencil();
        let last = (steps.end - 1).min(stencil.len());
        let z0_exact = lanes.z0.map(f64::from);
        let mut lanes_best = Best::<V>::new(*best);
        let mut copy = [OUTSIDE; COPY_COLUMNS * COPY_STRIDE];
        let mut k = steps.start;
        let mut level = TOP_LEVEL;
        while k <= last {
            let to = (k + (1 << level) - 1).min(last);
            if level > LEAF_LEVEL {
                let highest = f64::from(self.highest(bounds, x, y, k, to));
                if self.below_ceilings(lanes, &z0_exact, &lanes_best.exact, highest, k, to) {
                    k = to + 1;
                    level = (level + 1).min(TOP_LEVEL);
                } else {
                    level -= 1;
                }
                continue;
            }
            let ([x0, _], [y0, _]) = self.copy_reach(terrain, patch, x, y, k, to, &mut copy)?;
            let grid = Grid {
                z: &copy,
                base: ((x as isize - x0) * COPY_STRIDE as isize + (y as isize - y0)) as usize,
                stride: COPY_STRIDE,
                upside_down: self.upside_down,
                z0: V::from_array(*lanes.z0),
                z0_exact,
            };
            for j in k..=to {
                test_step(&grid, &stencil.steps[j], j as u32, &mut lanes_best);
            }
            k = to + 1;
            level = LEAF_LEVEL + 1;
        }
        *best = lanes_best.exact;
        Ok(())
    }

    /// Copies the signed samples that the points of steps `from..=to` of the lanes' lines
    /// read into `copy` (column after column, [`COPY_STRIDE`] rows a column, [`OUTSIDE`]
    /// beyond the raster); the first frame column and row copied.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn copy_reach(
        &self,
        terrain: &dyn FarTerrain,
        patch: &mut Patch,
        x: usize,
        y: usize,
        from: usize,
        to: usize,
        copy: &mut [f32; COPY_COLUMNS * COPY_STRIDE],
    ) -> Result<([isize; 2], [isize; 2]), ShadeError> {
        let ([x0, x1], [y0, y1]) = self.reach(x, y, from, to);
        let (columns, rows) = ((x1 - x0 + 1) as usize, (y1 - y0 + 1) as usize);
        debug_assert!(columns <= COPY_COLUMNS && rows <= COPY_STRIDE);
        let inside = x0 >= 0
            && y0 >= 0
            && (x1 as usize) < self.frame_width
            && (y1 as usize) < self.frame_height;
        let (col, row) = if self.transposed { (y0, x0) } else { (x0, y0) };
        let (end_col, end_row) = if self.transposed { (y1, x1) } else { (x1, y1) };
        let held = if inside { patch.holding(terrain, [col, row], [end_col, end_row])? } else { None };
        if let Some(p) = held {
            let at = |c: isize, r: isize| (c - p.x0) as usize + (r - p.y0) as usize * p.width;
            if self.transposed {
                // A frame column is a raster row: one run each.
                for u in 0..columns {
                    let run = &p.samples[at(col, row + u as isize)..][..rows];
                    for (v, &z) in copy[u * COPY_STRIDE..][..rows].iter_mut().zip(run) {
                        *v = self.sign * z;
                    }
                }
            } else {
                for v in 0..rows {
                    let run = &p.samples[at(col, row + v as isize)..][..columns];
                    for (u, &z) in run.iter().enumerate() {
                        copy[u * COPY_STRIDE + v] = self.sign * z;
                    }
                }
            }
        } else {
            for u in 0..columns {
                for v in 0..rows {
                    copy[u * COPY_STRIDE + v] =
                        self.frame_sample(terrain, patch, x0 + u as isize, y0 + v as isize)?;
                }
            }
        }
        Ok(([x0, x1], [y0, y1]))
    }

    /// Whether `highest` lies at or below every wanted lane's ceiling over steps `from..=to`:
    /// the lowest a signed sample may lie and still raise the lane's `best`, less a margin
    /// for rounding.
    #[inline(always)]
    fn below_ceilings(
        &self,
        lanes: &FarLanes,
        z0: &[f64; LANES],
        best: &[f64; LANES],
        highest: f64,
        from: usize,
        to: usize,
    ) -> bool {
        let line = &self.line;
        let near = (from as f64 - 1.0) * line.metres_per_step;
        let far = to as f64 * line.metres_per_step;
        (0..LANES).all(|i| {
            let t = if best[i] < 0.0 { far } else { near };
            let rise = (best[i] * t + line.observer_height) / line.z_scale;
            let ceiling = z0[i] + rise;
            let ceiling = ceiling - 1e-9 * (1.0 + z0[i].abs() + rise.abs());
            !lanes.wanted[i] || highest <= ceiling
        })
    }
}

/// Rows a column of a stretch's copy holds: the rows of eight steps' points (at most one row
/// a step) for sixteen lanes, with their margins.
const COPY_STRIDE: usize = 32;

/// Columns a stretch's copy holds: eight steps' and the one before.
const COPY_COLUMNS: usize = (1 << LEAF_LEVEL) + 1;

/// The lanes of a far walk: lane `i` the observer over frame sample (`x`, `y + i`), its signed
/// sample `z0[i]`.
pub(crate) struct FarLanes<'a> {
    x: usize,
    y: usize,
    z0: &'a [f32; LANES],
    wanted: &'a [bool; LANES],
}

/// A far field's lines, errors and scratch, for one engine.
pub(crate) struct FarContext<'a> {
    pub field: FarField<'a>,
    pub error: FarError,
}

impl FarContext<'_> {
    /// The wanted lanes' `best` slopes raised over the far parts of their lines, lane `i`
    /// from frame sample (`x`, `y + i`) of the window (signed sample `z0[i]`); on a read
    /// error, kept for the caller, as they were.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn raise_lanes(
        &self,
        line: &FarLine,
        patch: &mut Patch,
        x: usize,
        y: usize,
        z0: &[f32; LANES],
        wanted: &[bool; LANES],
        best: &mut [f64; LANES],
    ) {
        let (gx, gy) = if line.transposed {
            (x + self.field.row0, y + self.field.col0)
        } else {
            (x + self.field.col0, y + self.field.row0)
        };
        let mut raised = *best;
        match line.raise_lanes(self.field.terrain, patch, gx, gy, z0, wanted, &mut raised) {
            Ok(()) => *best = raised,
            Err(error) => self.error.keep(error),
        }
    }
}
