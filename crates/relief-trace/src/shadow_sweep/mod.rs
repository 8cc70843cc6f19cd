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
//! ([`Tracer::occluded_batch`]) first asks the memory system for every ray's first cell,
//! then walks the rays four at a time (in AVX2 registers where the processor has
//! them, two groups of four lanes in turn, a lane taking the next ray as soon as its own is
//! decided; else interleaved), and traces the undecided ones as one batch of the wrapped
//! tracer.
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
//! 1.56-1.58x and 1.04-1.14x, for a sun that lights many frames. Since then the sweep is
//! built in place in its final layout and a batch prefetches one cell a ray instead of eight,
//! which made the top-down view's shadow rays 15% faster; where the wrapped tracer keeps a
//! max mipmap ([`Tracer::max_mipmap`]), `D` is read from its level of the blocks' side (over
//! a `triangles` surface without holes the two are the same maxima) and the bounds are laid
//! out so that the sweep's rows are contiguous: about 5 ms at 4096^2, against 14.4
//! (docs/performance.md).

mod batch;
mod bound;
mod walk;

use crate::cell_grid::{CellGrid, CellRay};
use crate::{Hit, TraceError, Tracer};
use rayon::prelude::*;
use relief_core::{Aabb, DVec3, HeightField, Ray, Surface};
use std::sync::Arc;

/// How many cells a shadow ray walks before it is handed to the wrapped tracer (`relief
/// bench`'s shadow rays on the fBm views at 4096^2, with the walk's lanes refilled: 32 cells
/// 3-5% faster than 16 on the three-quarter and top-down views, 8 slower, 64 no faster).
pub const WALK_CELLS: u32 = 32;

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

/// How many cells along each ray of a batch are prefetched before the batch is walked (on
/// the fBm views at 1920x1080, `relief bench`'s shadow time: 1 measured best of 0, 1, 2, 3
/// and 8, the top-down view's 99 ms against 104 with none and 116 with 8).
const PREFETCH_CELLS: usize = 1;

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
    /// Where block `(bx, by)`'s bound is stored: at `bx * stride_x + by * stride_y`, so that
    /// the sweep's rows (along the sun's dominant axis) are contiguous: row by row along x
    /// (`stride_x` 1) when y is the dominant axis, column by column when it is x.
    stride_x: usize,
    stride_y: usize,
    /// Whether the sun's dominant horizontal axis (in cell space) is x.
    major_is_x: bool,
    /// Whether the sun lies towards decreasing x (resp. y): the sweep index is mirrored.
    flip_x: bool,
    flip_y: bool,
    /// `U` of every block, laid out by `stride_x` and `stride_y`.
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
            stride_x: if major_is_x { blocks_y } else { 1 },
            stride_y: if major_is_x { 1 } else { blocks_x },
            major_is_x,
            flip_x: dir.x < 0.0,
            flip_y: dir.y < 0.0,
            bound: Vec::new(),
            margin: 1e-7 * (1.0 + lo.abs().max(hi.abs()) + (hi - lo)),
            walk: WALK_CELLS,
            fast_triangles,
            avx2: avx2_available()
                && block.is_power_of_two()
                && field.samples().len() < i32::MAX as usize / 2,
            field,
        };
        if blocks_x > 0 && blocks_y > 0 {
            // The ray's rise over one block along the dominant axis, shrunk against rounding.
            let major = if major_is_x { dir.x.abs() } else { dir.y.abs() };
            let rise = block as f64 * (dir.z / major) * (1.0 - 1e-9);
            let maxima = shadows.block_maxima();
            shadows.bound = shadows.sweep(maxima, rise);
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

    /// Whether a sweep over `surface` of `field` pays for about `rays` shadow rays: it walks
    /// batches there ([`SunShadows::walks_batches_over`]), and the rays are at least one per
    /// 64 samples, below which its build (from the tracer's max mipmap, about 5 ms at 4096^2)
    /// costs more than it saves (at 1280x720 over 4096^2, 921,600 pixels, it saves about 25
    /// ms of shadow rays; docs/performance.md).
    pub fn pays_for(field: &HeightField, surface: Surface, rays: usize) -> bool {
        Self::walks_batches_over(field, surface) && rays >= field.width() * field.height() / 64
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

impl<T: Tracer> Tracer for SunShadows<T> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn surface(&self) -> Surface {
        self.inner.surface()
    }

    fn bounds(&self) -> Aabb {
        self.inner.bounds()
    }

    fn max_mipmap(&self) -> Option<&crate::MaxMipmap> {
        self.inner.max_mipmap()
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
