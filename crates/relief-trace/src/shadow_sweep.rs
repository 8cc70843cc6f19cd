//! Shadow rays towards one sun decided without tracing: a sweep along the sun's azimuth bounds,
//! per block of cells, the height of the shadow the terrain casts, so that a shadow ray that
//! rises above that bound after its first few cells is proven lit ([`SunShadows`]).
//!
//! # The bound
//!
//! Work in cell space (see [`CellGrid`]), where the ray towards the sun rises `k` per unit of
//! horizontal travel along the sun's dominant horizontal axis. Let `M(x)` be the highest
//! [`CellGrid::cell_max`] of the cells whose closed footprint lies within a small `ε` of the
//! horizontal point `x` (minus infinity away from the grid), and
//! `H(p) = sup over s >= 0 of M(p + s L) - s k` the height of the terrain's shadow over `p`
//! (`L` the horizontal direction towards the sun, scaled to one unit along the dominant axis).
//! A ray towards the sun from a point `q` with `q.z > H(q.xy)` stays above every cell it could
//! meet, so no tracer finds it occluded.
//!
//! The sweep computes, for square blocks of `B x B` cells, a bound `U >= H` over the block
//! (and `ε` around it). Step `B` cells along the dominant axis: from any point of block
//! `(I, J)` (indices mirrored so that the sun lies towards growing `I` and `J`), the ray's
//! ground track over that step stays within the 2 x 2 blocks `{I, I+1} x {J, J+1}` and lands
//! in block `(I+1, J)` or `(I+1, J+1)`, having risen `B k`. So
//!
//! `U(I, J) = max(max of D over the 2 x 2 blocks, max(U(I+1, J), U(I+1, J+1)) - B k)`
//!
//! where `D` is a block's maximum sample over its cells widened by one cell on every side
//! (which covers `ε`; holes keep their stored value, the lowest valid sample, so `D` only
//! overestimates). Blocks past the grid hold minus infinity. One pass from the sun's side
//! computes every `U`, in `f64` with `k` shrunk by a relative `1e-9` and the stored `f32`
//! raised by a relative `2^-22` (more than its rounding), so `U` never falls below `H`.
//!
//! Over the `triangles` surface of a field without holes, `D` is not widened: the maximum of
//! the block's own cells. The surface `S` is then continuous and the solid is everything below
//! it, so a point `x` needs only `S(x)`, which is at most the [`CellGrid::cell_max`] of the
//! one cell holding `x` (cells half-open in the mirrored indices, as the recursion's blocks),
//! and the cells within `ε` of `x` rise at most `2 ε (max - min)` above `S(x)`, far below the
//! margin (below) for the `ε` of `1e-9` cells this needs (still far above the rounding of any
//! tracer's cell boundaries).
//!
//! # Deciding a ray
//!
//! A ray whose direction is exactly the swept sun direction walks its first cells by a 2D DDA
//! from its start. At each cell's entry point it is proven lit when its height exceeds `U` of
//! the cell's block by a margin (`1e-7` of the heights' magnitude and range, far above the
//! rounding of any exact cell test). Otherwise the part of the ray over the cell must pass
//! above every cell within `ε` of it by the same margin (over a continuous `triangles`
//! surface: above the cell's two planes). Leaving the grid with every cell cleared also proves
//! the ray lit. A proven ray is not occluded for any exact tracer: each of its points is above
//! every cell the tracer could test there.
//!
//! A ray whose part over a cell does not clear it is proven occluded when the point halfway
//! along that part (or, through a wall, along its part over the next cell) lies at least `ε`
//! inside the cell's footprint, within the ray's range, and inside the cell's solid by the
//! margin: every exact tracer finds a point of the ray inside the solid.
//!
//! Any other ray is undecided: one that does not start over the grid or has another direction
//! (traced whole by the wrapped tracer), one that comes near the solid without a proof, and one
//! not decided within [`WALK_CELLS`] cells. The last two are traced from where the walk
//! stopped (their range's start moved there): no point before it is within `ε` of the solid by
//! the margin, so no exact cell test finds a hit there, and the cells from there on are tested
//! over the same segments as for the whole ray (the cell the ray is in there is entered at that
//! point, with the ray above its solid), so the answer is the whole ray's.
//!
//! # Speed
//!
//! Over the `triangles` surface of a field without holes, a batch
//! ([`Tracer::occluded_batch`]) first asks the memory system for the cells along every ray's
//! first steps, then walks the rays four at a time (in AVX2 registers where the processor has
//! them, else interleaved), and traces the undecided ones as one batch of the wrapped tracer.
//! A batch whose rays start densely (a close view) goes to the wrapped tracer whole: its
//! packets share their work between such rays. Over the `boxes` surface, or with holes, every
//! batch goes to the wrapped tracer whole ([`SunShadows::walks_batches`]): the walk there,
//! which tests the cells beside the ray for walls, was slower than the packets (0.7-0.9x), and
//! only single rays are walked.
//!
//! Measured on the 4096^2 fBm terrain at 1920x1080 under `relief bench`'s sun, in-process
//! against the mipmap tracer's packets alone (alternating, fastest of three or five, on a
//! shared 2-core machine), with blocks of 4 cells (the default; the sweep took 13 ms, 4 MiB):
//! the `triangles` surface's shadow rays 1.34-1.36x as fast in the three-quarter view,
//! 1.42-1.44x top-down and 0.99-1.03x in the flight view, so that a frame's shadow rays plus
//! the sweep take 93 against 105 ms (three-quarter) and 123 against 160 ms (top-down), but
//! 75 against 61 ms in the flight view. Blocks of 2 cells (40-45 ms, 16 MiB): 1.41-1.44x,
//! 1.56-1.58x and 1.04-1.14x, for a sun that lights many frames.

use crate::cell_grid::{CellGrid, CellRay};
use crate::{Hit, TraceError, Tracer};
use rayon::prelude::*;
use relief_core::{DVec3, HeightField, Ray, Surface};
use std::sync::Arc;

/// How many cells a shadow ray walks before it is handed to the wrapped tracer.
pub const WALK_CELLS: u32 = 16;

/// The side, in cells, of the blocks [`SunShadows::new`] bounds the shadow over: 4 builds in
/// a third of the time of 2 (13 against 40-45 ms at 4096^2) for 5-10% slower shadow rays, so
/// that the sweep pays within one frame (module documentation, "Speed").
pub const DEFAULT_SHADOW_BLOCK: usize = 4;

/// Rays a cell (over the box of a batch's starting points) above which the batch goes to
/// the wrapped tracer without walks: its packets share the work of rays that close (on the
/// fBm flight view the walks were 0.6x as fast; 0.25 measured best of 0.25, 1 and 4).
const DENSE_RAYS_PER_CELL: f64 = 0.25;

/// Rays whose walks [`SunShadows::decide_batch`] advances together.
const LANES: usize = 4;

/// How many cells along each ray of a batch are prefetched before the batch is walked.
const PREFETCH_CELLS: usize = 8;

/// Horizontal distance, in cells, within which a cell counts as under a ray's point: far
/// beyond the rounding of any tracer's cell boundaries.
const NEAR: f64 = 1e-6;

/// A tracer whose shadow rays towards one sun are decided, where a sweep along the sun's
/// azimuth proves them lit, without tracing; every other ray (and every undecided one) goes
/// to the wrapped tracer `T`. See the module documentation (`shadow_sweep.rs`) for the bound and why the
/// answers equal the wrapped tracer's.
///
/// ```
/// use std::sync::Arc;
/// use relief_core::{DVec3, GridGeometry, HeightField, Ray, Surface};
/// use relief_trace::{MipmapTracer, SunShadows, Tracer};
/// let field = Arc::new(HeightField::new(8, 8, vec![1.0; 64], GridGeometry::unit()).unwrap());
/// let sun = DVec3::new(0.6, 0.0, 0.8);
/// let tracer = MipmapTracer::new(field.clone(), Surface::Triangles);
/// let shadows = SunShadows::new(tracer, field, sun).unwrap();
/// let ray = Ray::new(DVec3::new(4.0, 4.0, 1.001), sun);
/// assert!(!shadows.occluded(&ray));
/// assert!(shadows.proves_lit(&ray, &mut 0));
/// ```
#[derive(Debug, Clone)]
pub struct SunShadows<T> {
    inner: T,
    field: Arc<HeightField>,
    grid: CellGrid,
    /// The swept world direction towards the sun.
    towards_sun: DVec3,
    /// The reciprocal of the sun direction in cell space.
    cell_inv_dir: DVec3,
    /// Block side in cells.
    block: usize,
    /// `log2(block)` when the side is a power of two (a shift instead of a division).
    block_shift: Option<u32>,
    blocks_x: usize,
    blocks_y: usize,
    /// Whether the sun's dominant horizontal axis (in cell space) is x.
    major_is_x: bool,
    /// Whether the sun lies towards decreasing x (resp. y): the sweep index is mirrored.
    flip_x: bool,
    flip_y: bool,
    /// Blocks along the minor axis: the length of a row of `bound`.
    minor_len: usize,
    /// `U` of every block, row by row along x (block `(bx, by)` at `bx + by * blocks_x`).
    bound: Vec<f32>,
    /// How far above a bound a ray must pass to count as above it.
    margin: f64,
    /// How many cells a ray walks before it is traced ([`WALK_CELLS`]).
    walk: u32,
    /// Whether the walk takes [`SunShadows::walk_triangles`]: the `triangles` surface of a
    /// field without holes.
    fast_triangles: bool,
    /// Whether batches of such walks run in AVX2 registers: the processor has AVX2, the
    /// blocks' side is a power of two and every index fits in 32 bits.
    avx2: bool,
}

impl<T: Tracer> SunShadows<T> {
    /// Sweeps the shadow of `field` under the sun in world direction `towards_sun` (any length;
    /// shadow rays must use exactly this vector as their direction to be decided here) over
    /// blocks of [`DEFAULT_SHADOW_BLOCK`] cells, wrapping `inner`, which must trace the same
    /// `field` (its surface is taken from `inner`).
    ///
    /// Errors: [`TraceError::Options`] when `towards_sun` is not finite or does not point
    /// above the horizon.
    pub fn new(inner: T, field: Arc<HeightField>, towards_sun: DVec3) -> Result<Self, TraceError> {
        Self::with_block(inner, field, towards_sun, DEFAULT_SHADOW_BLOCK)
    }

    /// [`SunShadows::new`] over blocks of `block x block` cells: smaller blocks bound the
    /// shadow more tightly, larger ones build faster and take less memory
    /// (`4 / block^2` bytes a cell).
    ///
    /// Errors: as [`SunShadows::new`], and [`TraceError::Options`] when `block` is 0.
    pub fn with_block(
        inner: T,
        field: Arc<HeightField>,
        towards_sun: DVec3,
        block: usize,
    ) -> Result<Self, TraceError> {
        if !towards_sun.is_finite() || towards_sun.z <= 0.0 {
            return Err(TraceError::Options(format!(
                "the sun direction {towards_sun} must be finite and point above the horizon"
            )));
        }
        if block == 0 {
            return Err(TraceError::Options("shadow sweep blocks of 0 cells".into()));
        }
        let grid = CellGrid::new(&field, inner.surface());
        let dir = towards_sun * field.geometry().grid_scale();
        let major_is_x = dir.x.abs() >= dir.y.abs();
        let (blocks_x, blocks_y) = (grid.cells_x().div_ceil(block), grid.cells_y().div_ceil(block));
        let (major_len, minor_len) =
            if major_is_x { (blocks_x, blocks_y) } else { (blocks_y, blocks_x) };
        let (lo, hi) = (field.min_sample() as f64, field.max_sample() as f64);
        let fast_triangles = Self::walks_batches_over(&field, grid.surface());
        let mut shadows = SunShadows {
            inner,
            grid,
            towards_sun,
            cell_inv_dir: DVec3::ONE / dir,
            block,
            block_shift: block.is_power_of_two().then(|| block.trailing_zeros()),
            blocks_x,
            blocks_y,
            major_is_x,
            flip_x: dir.x < 0.0,
            flip_y: dir.y < 0.0,
            minor_len,
            bound: Vec::new(),
            margin: 1e-7 * (1.0 + lo.abs().max(hi.abs()) + (hi - lo)),
            walk: WALK_CELLS,
            fast_triangles,
            avx2: avx2_available()
                && block.is_power_of_two()
                && field.samples().len() < i32::MAX as usize / 2,
            field,
        };
        if major_len > 0 && minor_len > 0 {
            // The ray's rise over one block along the dominant axis, shrunk against rounding.
            let major = if major_is_x { dir.x.abs() } else { dir.y.abs() };
            let rise = block as f64 * (dir.z / major) * (1.0 - 1e-9);
            let widened = shadows.widened_block_maxima();
            let swept = shadows.sweep(widened, major_len, rise);
            shadows.bound = shadows.unmirrored(&swept);
        }
        Ok(shadows)
    }

    /// The same sweep with rays walking at most `cells` cells (by default [`WALK_CELLS`])
    /// before the wrapped tracer traces the rest of them.
    pub fn with_walk_cells(mut self, cells: u32) -> Self {
        self.walk = cells;
        self
    }

    /// Whether [`Tracer::occluded_batch`] walks its rays before tracing the undecided ones:
    /// over the `triangles` surface of a field without holes, where that was measured to pay.
    /// Otherwise (the `boxes` surface, whose walks test the cells beside the ray for walls;
    /// holes) batches go to the wrapped tracer whole, and only single rays are walked.
    pub fn walks_batches(&self) -> bool {
        self.fast_triangles
    }

    /// [`SunShadows::walks_batches`] of a sweep over `surface` of `field`, known before
    /// building it.
    pub fn walks_batches_over(field: &HeightField, surface: Surface) -> bool {
        surface == Surface::Triangles && field.holes().is_none()
    }

    /// The wrapped tracer.
    pub fn inner(&self) -> &T {
        &self.inner
    }

    /// The world direction towards the sun the shadow was swept for.
    pub fn towards_sun(&self) -> DVec3 {
        self.towards_sun
    }

    /// Bytes the swept bound takes.
    pub fn memory_bytes(&self) -> usize {
        self.bound.len() * std::mem::size_of::<f32>()
    }

    /// Whether the sweep proves `ray` not occluded without tracing it: only a ray whose
    /// direction is exactly [`SunShadows::towards_sun`] and which starts over the grid can be
    /// proven lit. `false` means undecided (the ray may or may not be occluded). Adds the
    /// cells walked to `steps`.
    pub fn proves_lit(&self, ray: &Ray, steps: &mut u32) -> bool {
        self.decide(ray, steps) == Some(false)
    }

    /// What the walk of the ray's first cells proves without tracing: `Some(false)` when the
    /// ray is lit (see [`SunShadows::proves_lit`]), `Some(true)` when one of its points within
    /// its range lies inside the solid by the margin (so every exact tracer finds it
    /// occluded), `None` when it is undecided. Adds the cells walked to `steps`.
    pub fn decide(&self, ray: &Ray, steps: &mut u32) -> Option<bool> {
        self.walk(ray, steps).decision()
    }

    /// The walk of `ray`: what it proves, or from where on the ray it proves nothing.
    fn walk(&self, ray: &Ray, steps: &mut u32) -> Walked {
        match self.start(ray) {
            Some((r, t0, cell)) => self.walk_from(&r, t0, cell, steps),
            None => Walked::From(ray.t_min),
        }
    }

    /// A ray the walk can decide, in cell space with the sun's reciprocal direction, with
    /// where it starts (`t_min`) and the cell under that point; `None` for a ray of another
    /// direction, with an empty or non-finite range, or not starting over the grid.
    #[inline]
    fn start(&self, ray: &Ray) -> Option<Start> {
        if ray.dir != self.towards_sun || self.bound.is_empty() {
            return None;
        }
        // The ray in cell space, as the tracers map it, with the sun's reciprocal direction.
        let mut r = self.grid.to_cell_space_dir_only(ray);
        r.inv_dir = self.cell_inv_dir;
        let t0 = r.t_min;
        if !(t0.is_finite() && t0 <= r.t_max) {
            return None;
        }
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (o, d) = (r.origin, r.dir);
        let (xa, ya, za) = (o.x + t0 * d.x, o.y + t0 * d.y, o.z + t0 * d.z);
        if !(xa >= 0.0 && xa <= cells_x as f64 && ya >= 0.0 && ya <= cells_y as f64) {
            return None;
        }
        if za.is_nan() {
            return None;
        }
        Some((r, t0, ((xa as usize).min(cells_x - 1), (ya as usize).min(cells_y - 1))))
    }

    /// The walk of [`SunShadows::decide`] from `t0`, over cell `(cx, cy)`.
    fn walk_from(
        &self,
        r: &CellRay,
        t0: f64,
        (mut cx, mut cy): (usize, usize),
        steps: &mut u32,
    ) -> Walked {
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (o, d, inv) = (r.origin, r.dir, r.inv_dir);
        let (mut xa, mut ya, mut za) = (o.x + t0 * d.x, o.y + t0 * d.y, o.z + t0 * d.z);
        if self.fast_triangles && (d.x != 0.0 || d.y != 0.0) {
            return self.walk_triangles(r, t0, (cx, cy), steps);
        }
        let samples = self.field.samples();
        let mut t_a = t0;
        let leave = |c: usize, o: f64, d: f64, inv: f64| {
            if d > 0.0 {
                ((c + 1) as f64 - o) * inv
            } else if d < 0.0 {
                (c as f64 - o) * inv
            } else {
                f64::INFINITY
            }
        };
        for _ in 0..self.walk {
            *steps += 1;
            if za - self.margin > self.bound_at(cx, cy) as f64 {
                return Walked::Lit;
            }
            let (tx, ty) = (leave(cx, o.x, d.x, inv.x), leave(cy, o.y, d.y, inv.y));
            let t_b = tx.min(ty);
            // A vertical ray stays over its point.
            let (xb, yb) =
                if t_b.is_finite() { (o.x + t_b * d.x, o.y + t_b * d.y) } else { (xa, ya) };
            let zb = if t_b.is_finite() { o.z + t_b * d.z } else { f64::INFINITY };
            if !self.passes_above(samples, (cx, cy), r, t_a, [xa, ya, za], [xb, yb, zb]) {
                // Near the solid: inside it over this cell, or (through a wall) over the next?
                if self.inside(samples, (cx, cy), r, t_a, t_b) {
                    return Walked::Occluded;
                }
                let (nx, ny) = (
                    if tx == t_b { step(cx, d.x, cells_x) } else { Some(cx) },
                    if ty == t_b { step(cy, d.y, cells_y) } else { Some(cy) },
                );
                let (Some(nx), Some(ny)) = (nx, ny) else { return Walked::From(t_a) };
                let t_c = leave(nx, o.x, d.x, inv.x).min(leave(ny, o.y, d.y, inv.y));
                return if self.inside(samples, (nx, ny), r, t_b, t_c) {
                    Walked::Occluded
                } else {
                    Walked::From(t_a)
                };
            }
            if !t_b.is_finite() {
                return Walked::Lit;
            }
            // Step to the next cell; leaving the grid with every cell cleared proves the ray.
            if tx == t_b {
                match step(cx, d.x, cells_x) {
                    Some(c) => cx = c,
                    None => return Walked::Lit,
                }
            }
            if ty == t_b {
                match step(cy, d.y, cells_y) {
                    Some(c) => cy = c,
                    None => return Walked::Lit,
                }
            }
            (t_a, xa, ya, za) = (t_b, xb, yb, zb);
        }
        Walked::From(t_a)
    }

    /// The walk of [`SunShadows::decide`] over the `triangles` surface of a field without
    /// holes, for a ray that moves horizontally, from `t0` over cell `(cx, cy)`: the same tests
    /// (the bound at each cell's entry point, both planes of the cell at both ends of the
    /// ray's part over it), with few branches the processor could mispredict.
    #[inline]
    fn walk_triangles(
        &self,
        r: &CellRay,
        t0: f64,
        (mut cx, mut cy): (usize, usize),
        steps: &mut u32,
    ) -> Walked {
        let (o, d, inv) = (r.origin, r.dir, r.inv_dir);
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (w, samples, margin) = (self.field.width(), self.field.samples(), self.margin);
        // The boundary a cell is left through along each axis (`cx + up_x`), and the step.
        let (up_x, up_y) = ((d.x > 0.0) as usize, (d.y > 0.0) as usize);
        let (step_x, step_y) =
            (if d.x > 0.0 { 1 } else { usize::MAX }, if d.y > 0.0 { 1 } else { usize::MAX });
        let leave = |c: usize, up: usize, o: f64, d: f64, inv: f64| {
            if d != 0.0 {
                ((c + up) as f64 - o) * inv
            } else {
                f64::INFINITY
            }
        };
        let (mut t_a, mut xa, mut ya, mut za) =
            (t0, o.x + t0 * d.x, o.y + t0 * d.y, o.z + t0 * d.z);
        for _ in 0..self.walk {
            *steps += 1;
            if za - margin > self.bound_at(cx, cy) as f64 {
                return Walked::Lit;
            }
            let (tx, ty) = (leave(cx, up_x, o.x, d.x, inv.x), leave(cy, up_y, o.y, d.y, inv.y));
            let t_b = tx.min(ty);
            let (xb, yb, zb) = (o.x + t_b * d.x, o.y + t_b * d.y, o.z + t_b * d.z);
            let i = cx + cy * w;
            let (a, b) = (samples[i] as f64, samples[i + 1] as f64);
            let (c, e) = (samples[i + w] as f64, samples[i + w + 1] as f64);
            // The two planes of `passes_above`, chosen without a branch.
            let ad = relief_core::splits_along_ad(a, b, c, e);
            let planes = [
                (a, b - a, if ad { e - b } else { c - a }),
                (if ad { a } else { b + c - e }, e - c, if ad { c - a } else { e - b }),
            ];
            let (ua, va, ub, vb) = (xa - cx as f64, ya - cy as f64, xb - cx as f64, yb - cy as f64);
            let mut above = true;
            for (p0, pu, pv) in planes {
                above &= (za - (p0 + pu * ua + pv * va) > margin)
                    & (zb - (p0 + pu * ub + pv * vb) > margin);
            }
            if !above {
                let samples = self.field.samples();
                if self.inside(samples, (cx, cy), r, t_a, t_b) {
                    return Walked::Occluded;
                }
                return Walked::From(t_a);
            }
            if tx == t_b {
                cx = cx.wrapping_add(step_x);
            }
            if ty == t_b {
                cy = cy.wrapping_add(step_y);
            }
            // Leaving the grid with every cell cleared proves the ray.
            if cx >= cells_x || cy >= cells_y {
                return Walked::Lit;
            }
            (t_a, xa, ya, za) = (t_b, xb, yb, zb);
        }
        Walked::From(t_a)
    }

    /// [`SunShadows::decide`] for every ray of `rays` into `decided`, adding the cells
    /// walked to `steps`: over the `triangles` surface of a field without holes, the walks of
    /// four rays advance together, a cell of each in turn, so that the processor overlaps
    /// their work; the decisions are the same.
    pub fn decide_batch(&self, rays: &[Ray], decided: &mut [Option<bool>], steps: &mut [u32]) {
        assert!(rays.len() == decided.len() && rays.len() == steps.len(), "batch slices differ");
        let mut walked = vec![Walked::Lit; rays.len()];
        self.walk_batch(rays, &mut walked, steps);
        for (out, walked) in decided.iter_mut().zip(walked) {
            *out = walked.decision();
        }
    }

    /// [`SunShadows::walk`] of every ray of `rays` into `walked`.
    fn walk_batch(&self, rays: &[Ray], walked: &mut [Walked], steps: &mut [u32]) {
        let d = self.cell_inv_dir;
        if !(self.fast_triangles && (d.x.is_finite() || d.y.is_finite())) {
            for ((ray, out), steps) in rays.iter().zip(walked.iter_mut()).zip(steps.iter_mut()) {
                *out = self.walk(ray, steps);
            }
            return;
        }
        for ((rays, walked), steps) in
            rays.chunks(LANES).zip(walked.chunks_mut(LANES)).zip(steps.chunks_mut(LANES))
        {
            let mut lanes = [None; LANES];
            for (lane, ray) in lanes.iter_mut().zip(rays) {
                *lane = self.start(ray);
            }
            #[cfg(target_arch = "x86_64")]
            if self.avx2 && walked.len() == LANES {
                // SAFETY: `avx2` holds only where the processor has AVX2 (see `with_block`).
                unsafe { self.walk_triangles_avx2(&lanes, walked, steps) };
            } else {
                self.walk_triangles_lanes(&lanes, walked, steps);
            }
            #[cfg(not(target_arch = "x86_64"))]
            self.walk_triangles_lanes(&lanes, walked, steps);
            for (out, (lane, ray)) in walked.iter_mut().zip(lanes.iter().zip(rays)) {
                if lane.is_none() {
                    *out = Walked::From(ray.t_min);
                }
            }
        }
    }

    /// [`SunShadows::walk_triangles_lanes`] of exactly [`LANES`] rays in AVX2 registers: the
    /// same operations in the same order (no fused multiply-adds), so the same decisions.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn walk_triangles_avx2(
        &self,
        lanes: &[Option<Start>; LANES],
        walked: &mut [Walked],
        steps: &mut [u32],
    ) {
        use std::arch::x86_64::*;
        let Some(first) = lanes.iter().flatten().next() else { return };
        let (d, inv) = (first.0.dir, first.0.inv_dir);
        let (cells_x, cells_y) = (self.grid.cells_x() as i32, self.grid.cells_y() as i32);
        let (w, samples) = (self.field.width() as i32, self.field.samples());
        let shift = _mm_cvtsi32_si128(self.block_shift.unwrap_or(0) as i32);
        let blocks_x = _mm_set1_epi32(self.blocks_x as i32);
        let margin = _mm256_set1_pd(self.margin);
        // 64-bit and 32-bit lane masks from four bits.
        let bits64 = _mm256_setr_epi64x(1, 2, 4, 8);
        let bits32 = _mm_setr_epi32(1, 2, 4, 8);
        let mask64 = |m: i32| {
            let v = _mm256_and_si256(_mm256_set1_epi64x(m as i64), bits64);
            _mm256_castsi256_pd(_mm256_cmpeq_epi64(v, bits64))
        };
        let mask32 = |m: i32| _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(m), bits32), bits32);
        let (mut o, mut at, mut cell) = ([[0.0f64; 4]; 3], [[0.0f64; 4]; 4], [[0i32; 4]; 2]);
        let mut active = 0i32;
        for (k, lane) in lanes.iter().enumerate() {
            if let Some((r, t0, (cx, cy))) = lane {
                let p = r.origin;
                (o[0][k], o[1][k], o[2][k]) = (p.x, p.y, p.z);
                at[0][k] = *t0;
                (at[1][k], at[2][k], at[3][k]) = (p.x + t0 * d.x, p.y + t0 * d.y, p.z + t0 * d.z);
                (cell[0][k], cell[1][k]) = (*cx as i32, *cy as i32);
                walked[k] = Walked::From(*t0);
                active |= 1 << k;
            }
        }
        let load = |v: &[f64; 4]| _mm256_loadu_pd(v.as_ptr());
        let (ox, oy, oz) = (load(&o[0]), load(&o[1]), load(&o[2]));
        let (mut t_a, mut xa, mut ya, mut za) =
            (load(&at[0]), load(&at[1]), load(&at[2]), load(&at[3]));
        let mut cx = _mm_loadu_si128(cell[0].as_ptr() as *const __m128i);
        let mut cy = _mm_loadu_si128(cell[1].as_ptr() as *const __m128i);
        let (dx, dy, dz) = (_mm256_set1_pd(d.x), _mm256_set1_pd(d.y), _mm256_set1_pd(d.z));
        let (inv_x, inv_y) = (_mm256_set1_pd(inv.x), _mm256_set1_pd(inv.y));
        let (up_x, up_y) = (_mm_set1_epi32((d.x > 0.0) as i32), _mm_set1_epi32((d.y > 0.0) as i32));
        let step_x = _mm256_set1_pd(if d.x > 0.0 { 1.0 } else { -1.0 });
        let step_y = _mm256_set1_pd(if d.y > 0.0 { 1.0 } else { -1.0 });
        let infinity = _mm256_set1_pd(f64::INFINITY);
        let zero = _mm256_setzero_pd();
        let (last_x, last_y) = (_mm_set1_epi32(cells_x - 1), _mm_set1_epi32(cells_y - 1));
        let lane_t = |v: __m256d, k: usize| {
            let mut out = [0.0f64; 4];
            _mm256_storeu_pd(out.as_mut_ptr(), v);
            out[k]
        };
        for _ in 0..self.walk {
            if active == 0 {
                return;
            }
            for (k, steps) in steps.iter_mut().enumerate() {
                *steps += (active >> k & 1) as u32;
            }
            // The bound at each cell's entry point.
            let block = _mm_add_epi32(
                _mm_mullo_epi32(_mm_srl_epi32(cy, shift), blocks_x),
                _mm_srl_epi32(cx, shift),
            );
            let bound = _mm256_cvtps_pd(_mm_i32gather_ps::<4>(self.bound.as_ptr(), block));
            let lit =
                _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(za, margin), bound))
                    & active;
            // Where each ray leaves its cell.
            let (fx, fy) = (_mm256_cvtepi32_pd(cx), _mm256_cvtepi32_pd(cy));
            let tx = if d.x != 0.0 {
                _mm256_mul_pd(_mm256_sub_pd(_mm256_cvtepi32_pd(_mm_add_epi32(cx, up_x)), ox), inv_x)
            } else {
                infinity
            };
            let ty = if d.y != 0.0 {
                _mm256_mul_pd(_mm256_sub_pd(_mm256_cvtepi32_pd(_mm_add_epi32(cy, up_y)), oy), inv_y)
            } else {
                infinity
            };
            let t_b = _mm256_min_pd(tx, ty);
            let xb = _mm256_add_pd(ox, _mm256_mul_pd(t_b, dx));
            let yb = _mm256_add_pd(oy, _mm256_mul_pd(t_b, dy));
            let zb = _mm256_add_pd(oz, _mm256_mul_pd(t_b, dz));
            // The cell's corners and its two planes.
            let i = _mm_add_epi32(cx, _mm_mullo_epi32(cy, _mm_set1_epi32(w)));
            let base = samples.as_ptr();
            let gather = |offset: i32| {
                let index = _mm_add_epi32(i, _mm_set1_epi32(offset));
                _mm256_cvtps_pd(_mm_i32gather_ps::<4>(base, index))
            };
            let (a, b, c, e) = (gather(0), gather(1), gather(w), gather(w + 1));
            let ad = _mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_add_pd(a, e), _mm256_add_pd(b, c));
            let (c_a, e_b) = (_mm256_sub_pd(c, a), _mm256_sub_pd(e, b));
            let planes = [
                (a, _mm256_sub_pd(b, a), _mm256_blendv_pd(c_a, e_b, ad)),
                (
                    _mm256_blendv_pd(_mm256_sub_pd(_mm256_add_pd(b, c), e), a, ad),
                    _mm256_sub_pd(e, c),
                    _mm256_blendv_pd(e_b, c_a, ad),
                ),
            ];
            let (ua, va) = (_mm256_sub_pd(xa, fx), _mm256_sub_pd(ya, fy));
            let (ub, vb) = (_mm256_sub_pd(xb, fx), _mm256_sub_pd(yb, fy));
            let mut above = _mm256_cmp_pd::<_CMP_EQ_OQ>(zero, zero);
            for (p0, pu, pv) in planes {
                let at_a =
                    _mm256_add_pd(_mm256_add_pd(p0, _mm256_mul_pd(pu, ua)), _mm256_mul_pd(pv, va));
                let at_b =
                    _mm256_add_pd(_mm256_add_pd(p0, _mm256_mul_pd(pu, ub)), _mm256_mul_pd(pv, vb));
                above = _mm256_and_pd(
                    above,
                    _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(za, at_a), margin),
                );
                above = _mm256_and_pd(
                    above,
                    _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(zb, at_b), margin),
                );
            }
            let above = _mm256_movemask_pd(above);
            let failed = active & !lit & !above;
            for k in (0..LANES).filter(|k| lit >> k & 1 != 0) {
                walked[k] = Walked::Lit;
            }
            for k in (0..LANES).filter(|k| failed >> k & 1 != 0) {
                let r = &lanes[k].as_ref().expect("an active lane has a ray").0;
                let cell =
                    (_mm_extract_epi32_dyn(cx, k) as usize, _mm_extract_epi32_dyn(cy, k) as usize);
                let (ta, tb) = (lane_t(t_a, k), lane_t(t_b, k));
                walked[k] = if self.inside(samples, cell, r, ta, tb) {
                    Walked::Occluded
                } else {
                    Walked::From(ta)
                };
            }
            let going = active & !lit & above;
            // Step to the next cell; leaving the grid with every cell cleared proves the ray.
            let sx = _mm256_cvtpd_epi32(_mm256_blendv_pd(
                zero,
                step_x,
                _mm256_cmp_pd::<_CMP_EQ_OQ>(tx, t_b),
            ));
            let sy = _mm256_cvtpd_epi32(_mm256_blendv_pd(
                zero,
                step_y,
                _mm256_cmp_pd::<_CMP_EQ_OQ>(ty, t_b),
            ));
            let (nx, ny) = (_mm_add_epi32(cx, sx), _mm_add_epi32(cy, sy));
            let outside = _mm_or_si128(
                _mm_or_si128(_mm_cmplt_epi32(nx, _mm_setzero_si128()), _mm_cmpgt_epi32(nx, last_x)),
                _mm_or_si128(_mm_cmplt_epi32(ny, _mm_setzero_si128()), _mm_cmpgt_epi32(ny, last_y)),
            );
            let left = _mm_movemask_ps(_mm_castsi128_ps(outside)) & going;
            for k in (0..LANES).filter(|k| left >> k & 1 != 0) {
                walked[k] = Walked::Lit;
            }
            let moving = going & !left;
            let (m64, m32) = (mask64(moving), mask32(moving));
            cx = _mm_blendv_epi8(cx, nx, m32);
            cy = _mm_blendv_epi8(cy, ny, m32);
            t_a = _mm256_blendv_pd(t_a, t_b, m64);
            xa = _mm256_blendv_pd(xa, xb, m64);
            ya = _mm256_blendv_pd(ya, yb, m64);
            za = _mm256_blendv_pd(za, zb, m64);
            for k in (0..LANES).filter(|k| moving >> k & 1 != 0) {
                walked[k] = Walked::From(lane_t(t_b, k));
            }
            active = moving;
        }
    }

    /// [`SunShadows::walk_triangles`] of up to [`LANES`] rays (`None`: undecided) at once.
    #[inline]
    fn walk_triangles_lanes(
        &self,
        lanes: &[Option<Start>; LANES],
        decided: &mut [Walked],
        steps: &mut [u32],
    ) {
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (w, samples, margin) = (self.field.width(), self.field.samples(), self.margin);
        let (Some(first), n) = (lanes.iter().flatten().next(), decided.len()) else {
            return;
        };
        // Every ray has the sun's direction.
        let (d, inv) = (first.0.dir, first.0.inv_dir);
        let (up_x, up_y) = ((d.x > 0.0) as usize, (d.y > 0.0) as usize);
        let step_x = if d.x > 0.0 { 1 } else { usize::MAX };
        let step_y = if d.y > 0.0 { 1 } else { usize::MAX };
        let leave = |c: usize, up: usize, o: f64, d: f64, inv: f64| {
            if d != 0.0 {
                ((c + up) as f64 - o) * inv
            } else {
                f64::INFINITY
            }
        };
        let mut origin = [DVec3::ZERO; LANES];
        let mut at = [[0.0f64; 4]; LANES];
        let mut cell = [(0usize, 0usize); LANES];
        let mut active = [false; LANES];
        for k in 0..n {
            if let Some((r, t0, c)) = &lanes[k] {
                decided[k] = Walked::From(*t0);
                let o = r.origin;
                origin[k] = o;
                at[k] = [*t0, o.x + t0 * d.x, o.y + t0 * d.y, o.z + t0 * d.z];
                cell[k] = *c;
                active[k] = true;
            }
        }
        for _ in 0..self.walk {
            if !active.iter().any(|&a| a) {
                return;
            }
            for k in 0..n {
                if !active[k] {
                    continue;
                }
                steps[k] += 1;
                let (o, (cx, cy)) = (origin[k], cell[k]);
                let [t_a, xa, ya, za] = at[k];
                if za - margin > self.bound_at(cx, cy) as f64 {
                    (decided[k], active[k]) = (Walked::Lit, false);
                    continue;
                }
                let (tx, ty) = (leave(cx, up_x, o.x, d.x, inv.x), leave(cy, up_y, o.y, d.y, inv.y));
                let t_b = tx.min(ty);
                let (xb, yb, zb) = (o.x + t_b * d.x, o.y + t_b * d.y, o.z + t_b * d.z);
                let i = cx + cy * w;
                let (a, b) = (samples[i] as f64, samples[i + 1] as f64);
                let (c, e) = (samples[i + w] as f64, samples[i + w + 1] as f64);
                let ad = relief_core::splits_along_ad(a, b, c, e);
                let planes = [
                    (a, b - a, if ad { e - b } else { c - a }),
                    (if ad { a } else { b + c - e }, e - c, if ad { c - a } else { e - b }),
                ];
                let (ua, va, ub, vb) =
                    (xa - cx as f64, ya - cy as f64, xb - cx as f64, yb - cy as f64);
                let mut above = true;
                for (p0, pu, pv) in planes {
                    above &= (za - (p0 + pu * ua + pv * va) > margin)
                        & (zb - (p0 + pu * ub + pv * vb) > margin);
                }
                if !above {
                    let r = &lanes[k].as_ref().expect("an active lane has a ray").0;
                    decided[k] = if self.inside(samples, (cx, cy), r, t_a, t_b) {
                        Walked::Occluded
                    } else {
                        Walked::From(t_a)
                    };
                    active[k] = false;
                    continue;
                }
                let (nx, ny) = (
                    if tx == t_b { cx.wrapping_add(step_x) } else { cx },
                    if ty == t_b { cy.wrapping_add(step_y) } else { cy },
                );
                if nx >= cells_x || ny >= cells_y {
                    (decided[k], active[k]) = (Walked::Lit, false);
                    continue;
                }
                cell[k] = (nx, ny);
                at[k] = [t_b, xb, yb, zb];
                decided[k] = Walked::From(t_b);
            }
        }
    }

    /// Whether the rays start so close together (more than [`DENSE_RAYS_PER_CELL`] a cell
    /// over the box of their starting points) that the wrapped tracer's batch, which shares
    /// its work between neighbouring rays, traces them faster than the walks decide them.
    fn dense(&self, rays: &[Ray]) -> bool {
        if rays.len() < 2 {
            return false;
        }
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for ray in rays {
            let p = ray.at(ray.t_min);
            (lo, hi) = (lo.min(p), hi.max(p));
        }
        let cells = (hi - lo) * self.field.geometry().grid_scale();
        let area = (cells.x.abs() + 1.0) * (cells.y.abs() + 1.0);
        rays.len() as f64 > DENSE_RAYS_PER_CELL * area
    }

    /// Whether the ray's point halfway between `t_a` and `t_b` (its part over cell
    /// `(cx, cy)`) lies within the ray's range, at least [`NEAR`] inside the cell's footprint,
    /// and inside the cell's solid by the margin: above the solid's bottom, below its top
    /// (boxes) or below the larger of the two triangles' planes (triangles). Then every exact
    /// tracer finds the ray occluded.
    #[inline]
    fn inside(
        &self,
        samples: &[f32],
        (cx, cy): (usize, usize),
        r: &CellRay,
        t_a: f64,
        t_b: f64,
    ) -> bool {
        let t = 0.5 * (t_a + t_b);
        if !(t.is_finite() && t <= r.t_max) || self.grid.is_empty_cell(cx, cy) {
            return false;
        }
        let p = r.origin + t * r.dir;
        let (u, v) = (p.x - cx as f64, p.y - cy as f64);
        let interior = |u: f64| u > NEAR && u < 1.0 - NEAR;
        if !(interior(u) && interior(v) && p.z - self.margin > self.grid.bounds().min.z) {
            return false;
        }
        let w = self.field.width();
        let i = cx + cy * w;
        let top = match self.grid.surface() {
            Surface::Boxes => samples[i] as f64,
            Surface::Triangles => {
                let (a, b) = (samples[i] as f64, samples[i + 1] as f64);
                let (c, d) = (samples[i + w] as f64, samples[i + w + 1] as f64);
                let planes = if relief_core::splits_along_ad(a, b, c, d) {
                    [(a, b - a, d - b), (a, d - c, c - a)]
                } else {
                    [(a, b - a, c - a), (b + c - d, d - c, d - b)]
                };
                planes.map(|(p0, pu, pv)| p0 + pu * u + pv * v).into_iter().fold(f64::MIN, f64::max)
            }
        };
        p.z + self.margin < top
    }

    /// Asks the memory system early for what deciding `ray` will read: the samples of the
    /// cells under its first [`PREFETCH_CELLS`] steps along the sun's dominant axis and the
    /// bounds of their blocks.
    #[inline]
    fn prefetch(&self, ray: &Ray) {
        if ray.dir != self.towards_sun || self.bound.is_empty() {
            return;
        }
        let r = self.grid.to_cell_space_dir_only(ray);
        let p = r.origin + r.t_min * r.dir;
        let (cells_x, cells_y) = (self.grid.cells_x() as f64, self.grid.cells_y() as f64);
        if !(p.x >= 0.0 && p.x <= cells_x && p.y >= 0.0 && p.y <= cells_y) {
            return;
        }
        let major = if self.major_is_x { r.dir.x.abs() } else { r.dir.y.abs() };
        let (sx, sy) = (r.dir.x / major, r.dir.y / major);
        let (w, samples) = (self.field.width(), self.field.samples());
        let rows = match self.grid.surface() {
            Surface::Boxes => 1,
            Surface::Triangles => 2,
        };
        for s in 0..PREFETCH_CELLS {
            let x = (p.x + s as f64 * sx).clamp(0.0, cells_x - 1.0) as usize;
            let y = (p.y + s as f64 * sy).clamp(0.0, cells_y - 1.0) as usize;
            prefetch(&self.bound[self.bound_index(x, y)]);
            for row in y..y + rows {
                if let Some(sample) = samples.get(x + row * w) {
                    prefetch(sample);
                }
            }
        }
    }

    /// Whether the ray's part from `a` (at `t_a`) to `b` (cell space, rising), over cell
    /// `(cx, cy)`, passes above the solid of every cell within [`NEAR`] of it by the margin.
    ///
    /// For `triangles`, over a cell with a surface, the ray must pass above both planes of
    /// the cell (the surface is the larger, and the planes are linear along the ray, so both
    /// ends decide): the surface is continuous across the cell's edges (its neighbours with
    /// a surface share the edge samples; the others hold nothing), so the neighbours' solid
    /// within [`NEAR`] is below the ray too. Otherwise (`boxes`, or a cell over a hole,
    /// beside whose walls the ray may pass) the ray must pass above the highest point of
    /// every cell within [`NEAR`] of the part from where it comes that near.
    #[inline]
    fn passes_above(
        &self,
        samples: &[f32],
        (cx, cy): (usize, usize),
        r: &CellRay,
        t_a: f64,
        [xa, ya, za]: [f64; 3],
        [xb, yb, zb]: [f64; 3],
    ) -> bool {
        if self.grid.surface() == Surface::Triangles && !self.grid.is_empty_cell(cx, cy) {
            let w = self.field.width();
            let i = cx + cy * w;
            let (sa, sb) = (samples[i] as f64, samples[i + 1] as f64);
            let (sc, sd) = (samples[i + w] as f64, samples[i + w + 1] as f64);
            // The two planes z = p0 + pu u + pv v over local (u, v), as the exact test has them.
            let planes = if relief_core::splits_along_ad(sa, sb, sc, sd) {
                [(sa, sb - sa, sd - sb), (sa, sd - sc, sc - sa)]
            } else {
                [(sa, sb - sa, sc - sa), (sb + sc - sd, sd - sc, sd - sb)]
            };
            let (ua, va) = (xa - cx as f64, ya - cy as f64);
            let (ub, vb) = (xb - cx as f64, yb - cy as f64);
            return planes.iter().all(|&(p0, pu, pv)| {
                za - (p0 + pu * ua + pv * va) > self.margin
                    && zb - (p0 + pu * ub + pv * vb) > self.margin
            });
        }
        // (Truncation is the floor of the non-negative values.)
        let span = |lo: f64, hi: f64, cells: usize| {
            let first = (lo - NEAR).max(0.0) as usize;
            let last = ((hi + NEAR).max(0.0) as usize).min(cells - 1);
            first..=last
        };
        // When the ray comes within NEAR of cell m along one axis (before `t_a`: already).
        let near_from = |m: usize, o: f64, d: f64, inv: f64| {
            if d > 0.0 {
                (m as f64 - NEAR - o) * inv
            } else if d < 0.0 {
                ((m + 1) as f64 + NEAR - o) * inv
            } else {
                f64::NEG_INFINITY
            }
        };
        let (o, d, inv) = (r.origin, r.dir, r.inv_dir);
        for my in span(ya.min(yb), ya.max(yb), self.grid.cells_y()) {
            let ty = near_from(my, o.y, d.y, inv.y);
            for mx in span(xa.min(xb), xa.max(xb), self.grid.cells_x()) {
                let top = self.grid.cell_max(samples, mx, my) as f64;
                let t = ty.max(near_from(mx, o.x, d.x, inv.x));
                let z = if t > t_a { o.z + t * d.z } else { za };
                // (Not `<=`: a NaN height proves nothing.)
                if (z - self.margin).partial_cmp(&top) != Some(std::cmp::Ordering::Greater) {
                    return false;
                }
            }
        }
        true
    }

    /// The swept bound `U` of the block holding cell (cx, cy).
    #[inline]
    fn bound_at(&self, cx: usize, cy: usize) -> f32 {
        self.bound[self.bound_index(cx, cy)]
    }

    /// Where [`SunShadows::bound_at`] of cell (cx, cy) is stored.
    #[inline]
    fn bound_index(&self, cx: usize, cy: usize) -> usize {
        let (bx, by) = match self.block_shift {
            Some(shift) => (cx >> shift, cy >> shift),
            None => (cx / self.block, cy / self.block),
        };
        bx + by * self.blocks_x
    }

    /// The blocks' values of `swept` (in sweep order: row `I` along the dominant axis,
    /// mirrored, holds the blocks `J` along the other, mirrored) row by row along x.
    fn unmirrored(&self, swept: &[f32]) -> Vec<f32> {
        let (blocks_x, blocks_y) = (self.blocks_x, self.blocks_y);
        let mut bound = vec![0.0; swept.len()];
        bound.par_chunks_mut(blocks_x).enumerate().for_each(|(by, row)| {
            let my = if self.flip_y { blocks_y - 1 - by } else { by };
            for (bx, out) in row.iter_mut().enumerate() {
                let mx = if self.flip_x { blocks_x - 1 - bx } else { bx };
                let (i, j) = if self.major_is_x { (mx, my) } else { (my, mx) };
                *out = swept[i * self.minor_len + j];
            }
        });
        bound
    }

    /// `D` of every block in sweep order: the highest sample any cell of the block, widened
    /// by one cell on every side, reads.
    fn widened_block_maxima(&self) -> Vec<f32> {
        let (b, w) = (self.block, self.field.width());
        let reach = match self.grid.surface() {
            Surface::Boxes => 0,
            Surface::Triangles => 1,
        };
        // The samples read by the cells of block `k` widened by one cell, along one axis; not
        // widened over a continuous surface (see the module documentation).
        let widen = !self.fast_triangles as usize;
        let samples_of = |k: usize, cells: usize| {
            let first = (k * b).saturating_sub(widen);
            let last = ((k + 1) * b + widen - 1).min(cells - 1) + reach;
            first..=last
        };
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (blocks_x, blocks_y) = (self.blocks_x, self.blocks_y);
        let samples = self.field.samples();
        // Rows of blocks, mirrored along both axes as the sweep has them: down the sample
        // rows first (whole rows at a time), then along the row.
        let mut widened = vec![f32::NEG_INFINITY; blocks_x * blocks_y];
        widened.par_chunks_mut(blocks_x).enumerate().for_each_init(
            || vec![f32::NEG_INFINITY; w],
            |column_max, (my, out)| {
                let by = if self.flip_y { blocks_y - 1 - my } else { my };
                column_max.fill(f32::NEG_INFINITY);
                for r in samples_of(by, cells_y) {
                    for (m, &v) in column_max.iter_mut().zip(&samples[r * w..(r + 1) * w]) {
                        *m = m.max(v);
                    }
                }
                for (bx, m) in column_max
                    .chunks(b)
                    .map(|c| c.iter().fold(f32::NEG_INFINITY, |a, &v| a.max(v)))
                    .enumerate()
                    .take(blocks_x)
                {
                    let range = samples_of(bx, cells_x);
                    let (first, last) = (*range.start(), *range.end());
                    // The block's own samples, and those just outside it that its widened cells read.
                    let mut d = m;
                    for c in (first..bx * b).chain((bx + 1) * b..=last) {
                        d = d.max(column_max[c]);
                    }
                    let mx = if self.flip_x { blocks_x - 1 - bx } else { bx };
                    out[mx] = d;
                }
            },
        );
        if !self.major_is_x {
            return widened;
        }
        // Rows of the sweep run along y: transpose, in tiles that stay in cache.
        const TILE: usize = 32;
        let mut transposed = vec![f32::NEG_INFINITY; blocks_x * blocks_y];
        transposed.par_chunks_mut(TILE * blocks_y).enumerate().for_each(|(ti, band)| {
            let rows = band.len() / blocks_y;
            for j0 in (0..blocks_y).step_by(TILE) {
                for j in j0..(j0 + TILE).min(blocks_y) {
                    let source =
                        &widened[j * blocks_x + ti * TILE..j * blocks_x + ti * TILE + rows];
                    for (r, &v) in source.iter().enumerate() {
                        band[r * blocks_y + j] = v;
                    }
                }
            }
        });
        transposed
    }

    /// The sweep, in place over the blocks' `widened` maxima in sweep order: `U` of every
    /// block, with the ray rising `rise` per block along the dominant axis.
    fn sweep(&self, mut bound: Vec<f32>, major_len: usize, rise: f64) -> Vec<f32> {
        let n = self.minor_len;
        // From the sun's side: U(I, J) = max(S(I, J), max(U(I+1, J), U(I+1, J+1)) - rise) with
        // S the largest D over {I, I+1} x {J, J+1}. In f64, with a finite stand-in for minus
        // infinity (past the last J, and before the first row) so that the stored value can
        // be rounded up without branches: raised by a relative 2^-22, more than the f32
        // rounding takes off.
        const NOTHING: f64 = -1e300;
        let mut next = vec![NOTHING; n + 1];
        let mut current = vec![NOTHING; n + 1];
        // D of the row on the sun's side (before the sweep overwrote it), and of this one.
        let mut there = vec![f32::NEG_INFINITY; n + 1];
        let mut here = vec![f32::NEG_INFINITY; n + 1];
        for i in (0..major_len).rev() {
            let out = &mut bound[i * n..(i + 1) * n];
            here[..n].copy_from_slice(out);
            for j in 0..n {
                let s = here[j].max(here[j + 1]).max(there[j]).max(there[j + 1]) as f64;
                let u = s.max(NOTHING).max(next[j].max(next[j + 1]) - rise);
                current[j] = u;
                out[j] = (u + u.abs() * (1.0 / 4194304.0) + 1e-44) as f32;
            }
            std::mem::swap(&mut next, &mut current);
            std::mem::swap(&mut there, &mut here);
        }
        bound
    }
}

/// The next cell index along an axis the ray moves along with sign `d`, or `None` past the
/// grid's `cells`.
#[inline]
fn step(c: usize, d: f64, cells: usize) -> Option<usize> {
    if d > 0.0 {
        Some(c + 1).filter(|&c| c < cells)
    } else {
        c.checked_sub(1)
    }
}

/// A ray ready to walk ([`SunShadows::start`]): in cell space, where it starts, the cell there.
type Start = (CellRay, f64, (usize, usize));

/// What a walk proves.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Walked {
    /// The ray is not occluded.
    Lit,
    /// The ray is occluded.
    Occluded,
    /// Nothing: but no point of the ray before this parameter is in or near the solid, so
    /// the ray is occluded exactly when its part from there on is.
    From(f64),
}

impl Walked {
    /// The decision of [`SunShadows::decide`].
    fn decision(self) -> Option<bool> {
        match self {
            Walked::Lit => Some(false),
            Walked::Occluded => Some(true),
            Walked::From(_) => None,
        }
    }
}

/// Whether this processor runs AVX2 instructions.
fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Lane `k` of four 32-bit integers.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn _mm_extract_epi32_dyn(v: std::arch::x86_64::__m128i, k: usize) -> i32 {
    let mut out = [0i32; 4];
    // SAFETY: an unaligned store of 16 bytes into a 16-byte array (SSE2, part of x86-64).
    unsafe { std::arch::x86_64::_mm_storeu_si128(out.as_mut_ptr() as *mut _, v) };
    out[k]
}

/// A hint that `value` will be read soon.
#[inline(always)]
fn prefetch<V>(value: &V) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: prefetching is a hint that never faults; SSE is part of x86-64.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(value as *const V as *const i8);
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

impl<T: Tracer> Tracer for SunShadows<T> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn surface(&self) -> Surface {
        self.inner.surface()
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        self.inner.intersect_counted(ray, steps)
    }

    fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
        match self.walk(ray, steps) {
            Walked::Lit => false,
            Walked::Occluded => true,
            Walked::From(t) if t > ray.t_max => false,
            Walked::From(t) => {
                self.inner.occluded_counted(&Ray { t_min: t.max(ray.t_min), ..*ray }, steps)
            }
        }
    }

    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], steps: &mut [u32]) {
        self.inner.intersect_batch(rays, hits, steps)
    }

    /// Decides what the walk proves (lit or occluded) and traces the other rays as one batch of the
    /// wrapped tracer.
    fn occluded_batch(&self, rays: &[Ray], occluded: &mut [bool], steps: &mut [u32]) {
        assert!(rays.len() == occluded.len() && rays.len() == steps.len(), "batch slices differ");
        if !self.walks_batches() || self.dense(rays) {
            return self.inner.occluded_batch(rays, occluded, steps);
        }
        // The batch's first cells are fetched from memory together, not one ray at a time.
        for ray in rays {
            self.prefetch(ray);
        }
        let mut walked = vec![Walked::Lit; rays.len()];
        self.walk_batch(rays, &mut walked, steps);
        let mut undecided = Vec::with_capacity(rays.len());
        let mut traced = Vec::with_capacity(rays.len());
        for (k, walked) in walked.into_iter().enumerate() {
            match walked {
                Walked::Lit => occluded[k] = false,
                Walked::Occluded => occluded[k] = true,
                // Cleared up to its end.
                Walked::From(t) if t > rays[k].t_max => occluded[k] = false,
                Walked::From(t) => {
                    undecided.push(k);
                    traced.push(Ray { t_min: t.max(rays[k].t_min), ..rays[k] });
                }
            }
        }
        if undecided.is_empty() {
            return;
        }
        let mut blocked = vec![false; traced.len()];
        let mut traced_steps = vec![0; traced.len()];
        self.inner.occluded_batch(&traced, &mut blocked, &mut traced_steps);
        for ((&k, b), s) in undecided.iter().zip(blocked).zip(traced_steps) {
            occluded[k] = b;
            steps[k] += s;
        }
    }
}
