//! The far field of a window: the horizons of a window's samples are found by the lanes over the
//! window, and then, where a line leaves the window before it leaves the raster, along the rest
//! of the line through the whole raster, read on demand ([`FarTerrain`]). The points past the
//! window are the lanes' points (the same [`StencilLine`]) and their slopes the same f64
//! arithmetic, so a window's horizons are bit for bit those of the whole raster in memory.
//! A group's sixteen lines are walked together, as the lanes walk the window: stretches too
//! low to raise a horizon are skipped by the raster's [`CoarseBounds`], and the samples of
//! the rest are copied, eight steps at a time, into a small grid the lanes' step test reads.

use super::coarse_bounds::CoarseBounds;
use super::lane_frame::{LANES, OUTSIDE};
#[cfg(target_arch = "x86_64")]
use super::lane_vector::Avx512;
use super::lane_vector::{LaneVector, Portable};
use super::lanes::{ceiling, footprint, test_step, Best, Grid};
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
    /// The observer's height and the heights' scale, in f32 (as the lanes' ceilings take them).
    observer_and_scale: [f32; 2],
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
    /// A patch that holds sample (`col`, `row`) of the raster (which lies in it), from those
    /// at hand or a new one.
    #[inline(always)]
    fn holding(
        &mut self,
        terrain: &dyn FarTerrain,
        col: isize,
        row: isize,
    ) -> Result<&SamplePatch, ShadeError> {
        if let Some(i) = self.recent.iter().position(|p| p.get(col, row).is_some()) {
            if i > 0 {
                self.recent.swap(0, i);
            }
        } else {
            self.sample(terrain, col, row)?;
        }
        Ok(&self.recent[0])
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
            observer_and_scale: [line.observer_height as f32, line.z_scale as f32],
            frame_width,
            frame_height,
            window_x,
            window_y,
            stencil: Mutex::new(None),
        }
    }

    /// The line's steps over the whole raster.
    pub(crate) fn stencil(&self) -> Arc<Stencil> {
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

    /// The columns and rows of the raster's frame that the points of steps `from..=to` of the
    /// lines from (`x`, `y + i`), `i < LANES`, read (not clipped).
    #[inline(always)]
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
    #[inline(always)]
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
    #[inline(always)]
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

    /// Raises the `best` slopes of the wanted `lanes` to the steepest slopes to the points of
    /// their lines past the window (`stencil` the line's [`FarLine::stencil`]). The lanes
    /// walk the far steps of any of them together: the rest of the steps read the window
    /// (whose points the lanes over the window found, by the same arithmetic) or nothing of
    /// the raster, so they change no lane's best.
    pub(crate) fn raise_lanes(
        &self,
        terrain: &dyn FarTerrain,
        stencil: &Stencil,
        patch: &mut Patch,
        lanes: &FarLanes,
        best: &mut [f64; LANES],
    ) -> Result<[u32; LANES], ShadeError> {
        #[cfg(test)]
        if super::lanes::tests::PORTABLE_ONLY.get() {
            return self.walk::<Portable>(terrain, stencil, patch, lanes, best);
        }
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor has AVX-512 F (checked just above).
            #[allow(unsafe_code)]
            return unsafe { self.walk_avx512(terrain, stencil, patch, lanes, best) };
        }
        self.walk::<Portable>(terrain, stencil, patch, lanes, best)
    }

    /// [`FarLine::walk`] in AVX-512 registers (the same operations, no fused multiply-add:
    /// the same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx2")]
    fn walk_avx512(
        &self,
        terrain: &dyn FarTerrain,
        stencil: &Stencil,
        patch: &mut Patch,
        lanes: &FarLanes,
        best: &mut [f64; LANES],
    ) -> Result<[u32; LANES], ShadeError> {
        self.walk::<Avx512>(terrain, stencil, patch, lanes, best)
    }

    /// See [`FarLine::raise_lanes`]: stretches of steps are skipped by the raster's bounds,
    /// and the points of the rest are tested as the lanes over a window test theirs, from a
    /// copy of the samples that the stretch's points read.
    #[inline(always)]
    fn walk<V: LaneVector>(
        &self,
        terrain: &dyn FarTerrain,
        stencil: &Stencil,
        patch: &mut Patch,
        lanes: &FarLanes,
        best: &mut [f64; LANES],
    ) -> Result<[u32; LANES], ShadeError> {
        let (x, y) = (lanes.x, lanes.y);
        // The far steps of the first lane and the last: those of the lanes between lie
        // within (where they begin and end moves monotonically with the row).
        let (first, last_lane) = (self.far_steps(x, y), self.far_steps(x, y + LANES - 1));
        let steps = first.start.min(last_lane.start)..first.end.max(last_lane.end);
        if first.is_empty() && last_lane.is_empty() {
            return Ok([0; LANES]);
        }
        let bounds = terrain.bounds();
        let last = (steps.end - 1).min(stencil.len());
        let z0_exact = lanes.z0.map(f64::from);
        let mut lanes_best = Best::<V>::new(*best);
        let unwanted = V::from_array(lanes.wanted.map(|w| if w { 0.0 } else { f32::INFINITY }));
        let mut copy = [OUTSIDE; COPY_COLUMNS * COPY_STRIDE];
        let z0 = V::from_array(*lanes.z0);
        // First the steps where the hints say the horizons are.
        let mut tried = [0; 3];
        for (slot, hint) in [0, LANES / 2, LANES - 1].into_iter().enumerate() {
            let j = lanes.hints[hint] as usize;
            if j >= steps.start && j <= last && !tried.contains(&j) {
                tried[slot] = j;
                let corner = self.copy_reach(terrain, patch, x, y, j, j, &mut copy)?;
                let grid = self.copy_grid(&copy, corner, lanes, z0, z0_exact);
                test_step(&grid, &stencil.steps[j], j as u32, &mut lanes_best);
            }
        }
        let mut k = steps.start;
        let mut level = TOP_LEVEL;
        while k <= last {
            let to = (k + (1 << level) - 1).min(last);
            if level > LEAF_LEVEL {
                let highest = V::splat(self.highest(bounds, x, y, k, to));
                let ceiling = ceiling(
                    &stencil.steps,
                    self.observer_and_scale,
                    z0,
                    unwanted,
                    k..=to,
                    lanes_best.low(),
                );
                if !V::any_greater(highest, ceiling) {
                    k = to + 1;
                    level = (level + 1).min(TOP_LEVEL);
                } else {
                    level -= 1;
                }
                continue;
            }
            let corner = self.copy_reach(terrain, patch, x, y, k, to, &mut copy)?;
            let grid = self.copy_grid(&copy, corner, lanes, z0, z0_exact);
            // A step is tested where a lane's footprint rises above its ceiling.
            for j in k..=to {
                let step = &stencil.steps[j];
                let highest = footprint::<V>(
                    &copy,
                    grid.base.wrapping_add_signed(step.footprint),
                    COPY_STRIDE,
                );
                let ceiling = ceiling(
                    &stencil.steps,
                    self.observer_and_scale,
                    grid.z0,
                    unwanted,
                    j..=j,
                    lanes_best.low(),
                );
                if V::any_greater(highest, ceiling) {
                    test_step(&grid, step, j as u32, &mut lanes_best);
                }
            }
            k = to + 1;
            level = LEAF_LEVEL + 1;
        }
        *best = lanes_best.exact;
        Ok(lanes_best.steps)
    }

    /// The lanes reading a `copy` whose first sample is frame sample `corner`.
    #[inline(always)]
    fn copy_grid<'c, V: LaneVector>(
        &self,
        copy: &'c [f32],
        [x0, y0]: [isize; 2],
        lanes: &FarLanes,
        z0: V,
        z0_exact: [f64; LANES],
    ) -> Grid<'c, V> {
        let (x, y) = (lanes.x as isize, lanes.y as isize);
        Grid {
            z: copy,
            base: ((x - x0) * COPY_STRIDE as isize + (y - y0)) as usize,
            stride: COPY_STRIDE,
            upside_down: self.upside_down,
            z0,
            z0_exact,
        }
    }

    /// Copies the signed samples that the points of steps `from..=to` of the lanes' lines
    /// read into `copy` (column after column, [`COPY_STRIDE`] rows a column, [`OUTSIDE`]
    /// beyond the raster); the frame column and row of the first sample copied.
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
    ) -> Result<[isize; 2], ShadeError> {
        let ([x0, x1], [y0, y1]) = self.reach(x, y, from, to);
        let (columns, rows) = ((x1 - x0 + 1) as usize, (y1 - y0 + 1) as usize);
        debug_assert!(columns <= COPY_COLUMNS && rows <= COPY_STRIDE);
        for column in copy.chunks_exact_mut(COPY_STRIDE).take(columns) {
            column[..rows].fill(OUTSIDE);
        }
        // The raster's rows and columns of the frame's rectangle, within the raster.
        let ([c0, c1], [r0, r1]) =
            if self.transposed { ([y0, y1], [x0, x1]) } else { ([x0, x1], [y0, y1]) };
        let (width, height) = if self.transposed {
            (self.frame_height, self.frame_width)
        } else {
            (self.frame_width, self.frame_height)
        };
        let (c0, c1) = (c0.max(0), c1.min(width as isize - 1));
        for r in r0.max(0)..=r1.min(height as isize - 1) {
            // Row `r` from column `c0` to `c1`, a run per patch.
            let mut c = c0;
            while c <= c1 {
                let p = patch.holding(terrain, c, r)?;
                let end = c1.min(p.x0 + p.width as isize - 1);
                let at = (c - p.x0) as usize + (r - p.y0) as usize * p.width;
                let run = &p.samples[at..][..(end - c + 1) as usize];
                if self.transposed {
                    // A raster row is a frame column.
                    let v = (c - y0) as usize;
                    let column = &mut copy[(r - x0) as usize * COPY_STRIDE + v..][..run.len()];
                    for (out, &z) in column.iter_mut().zip(run) {
                        *out = self.sign * z;
                    }
                } else {
                    let (u, v) = ((c - x0) as usize, (r - y0) as usize);
                    for (i, &z) in run.iter().enumerate() {
                        copy[(u + i) * COPY_STRIDE + v] = self.sign * z;
                    }
                }
                c = end + 1;
            }
        }
        Ok([x0, y0])
    }
}

/// Rows a column of a stretch's copy holds: the rows of eight steps' points (at most one row
/// a step) for sixteen lanes, with their margins.
const COPY_STRIDE: usize = 32;

/// Columns a stretch's copy holds: eight steps' and the one before.
const COPY_COLUMNS: usize = (1 << LEAF_LEVEL) + 1;

/// The lanes of a far walk: lane `i` the observer over frame sample (`x`, `y + i`), its signed
/// sample `z0[i]`, its horizon wanted where `wanted[i]`.
pub(crate) struct FarLanes<'a> {
    pub x: usize,
    pub y: usize,
    pub z0: &'a [f32; LANES],
    pub wanted: &'a [bool; LANES],
    /// Steps where the horizons of the lanes one column before were found past the window
    /// (0 for none): tested first, they change how fast the answer is found, never the
    /// answer.
    pub hints: &'a [u32; LANES],
}

/// A far field's lines, errors and scratch, for one engine.
pub(crate) struct FarContext<'a> {
    pub field: FarField<'a>,
    pub error: FarError,
}

impl FarContext<'_> {
    /// The wanted `lanes`' `best` slopes raised over the far parts of their lines (`lanes` in
    /// the window's frame), and the steps that raised them (0 where none did); on a read
    /// error, kept for the caller, the slopes as they were.
    pub(crate) fn raise_lanes(
        &self,
        line: &FarLine,
        stencil: &Stencil,
        patch: &mut Patch,
        lanes: &FarLanes,
        best: &mut [f64; LANES],
    ) -> [u32; LANES] {
        let (x, y) = if line.transposed {
            (lanes.x + self.field.row0, lanes.y + self.field.col0)
        } else {
            (lanes.x + self.field.col0, lanes.y + self.field.row0)
        };
        let lanes = FarLanes { x, y, ..*lanes };
        let mut raised = *best;
        match line.raise_lanes(self.field.terrain, stencil, patch, &lanes, &mut raised) {
            Ok(steps) => {
                *best = raised;
                steps
            }
            Err(error) => {
                self.error.keep(error);
                [0; LANES]
            }
        }
    }
}
