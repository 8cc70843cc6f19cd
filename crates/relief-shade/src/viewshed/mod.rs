//! Viewsheds: which samples of a height field an observer sees, or how many of several
//! observers see each one (a cumulative viewshed), exact for the surface a tracer intersects.
//!
//! A sample is seen by an observer when the segment from the observer's eye to the target
//! point (the sample point raised by the target height) does not pass below the surface.
//! Touching counts as seen: a line of sight that grazes a ridge exactly sees over it. Both
//! ends of the segment are raised by the lift of the shade map's rays
//! ([`crate::shade_map::SURFACE_LIFT`], a millionth of a cell), so that a target on the ground
//! is not hidden by the surface it lies on, and the segment is traced by the exact tracer
//! handed in, as one ray from the eye to the target.
//!
//! Most hidden samples are not traced: a sweep outward from the eye (`hidden_sweep.rs`) proves
//! them hidden, exactly, from lower bounds of the terrain's horizon; the answer is the one the
//! tracer would give.

mod hidden_sweep;
mod observer;
mod target_points;
mod unit_runs;

pub use observer::{Observer, DEFAULT_OBSERVER_HEIGHT};

use crate::ShadeError;
use rayon::prelude::*;
use relief_core::{DVec3, HeightField, Ray};
use relief_trace::Tracer;
use std::sync::atomic::{AtomicU64, Ordering};

/// Most observers one viewshed may have.
pub const MAX_OBSERVERS: usize = 65_536;

/// What a viewshed is asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewshedParams {
    /// The observers (at least one).
    pub observers: Vec<Observer>,
    /// Height of the target point above each sample point, in metres (finite, >= 0).
    pub target_height: f64,
    /// Horizontal distance in metres beyond which an observer sees nothing; `None` for no
    /// limit.
    pub radius: Option<f64>,
}

impl ViewshedParams {
    /// Checks every parameter but the observers' places (which need the field), naming the
    /// one that is wrong.
    pub fn validate(&self) -> Result<(), ShadeError> {
        if self.observers.is_empty() {
            return Err(ShadeError::parameter("observers", "a viewshed needs at least one"));
        }
        if self.observers.len() > MAX_OBSERVERS {
            return Err(ShadeError::parameter(
                "observers",
                format!("{} is more than {MAX_OBSERVERS}", self.observers.len()),
            ));
        }
        for observer in &self.observers {
            if !(observer.x.is_finite() && observer.y.is_finite()) {
                return Err(ShadeError::parameter(
                    "observer",
                    format!("({}, {}) is not a finite point", observer.x, observer.y),
                ));
            }
            if !(observer.height.is_finite() && observer.height >= 0.0) {
                return Err(ShadeError::parameter(
                    "observer height",
                    format!("{} is not a finite number >= 0", observer.height),
                ));
            }
        }
        if !(self.target_height.is_finite() && self.target_height >= 0.0) {
            return Err(ShadeError::parameter(
                "target height",
                format!("{} is not a finite number >= 0", self.target_height),
            ));
        }
        if let Some(radius) = self.radius {
            if !(radius.is_finite() && radius > 0.0) {
                return Err(ShadeError::parameter(
                    "radius",
                    format!("{radius} is not a finite number > 0"),
                ));
            }
        }
        Ok(())
    }
}

/// A viewshed on a height field's grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Viewshed {
    /// Samples per row (the height field's width).
    pub width: usize,
    /// Rows (the height field's height).
    pub height: usize,
    /// Per sample (row-major, row 0 south), the number of observers that see it (0 or 1 for
    /// one observer); NaN on a void.
    pub counts: Vec<f32>,
    /// Lines of sight traced.
    pub rays: u64,
}

/// Rows of samples traced together: one parallel task.
const BAND_ROWS: usize = 8;
/// Samples per row of a tile, whose rays are traced as one batch.
const TILE_COLS: usize = 8;

/// The viewshed of `params`'s observers over every sample of `field`, tracing with `tracer`,
/// which must trace `field` (the answer is exact for the tracer's surface).
///
/// A sample that is a hole of `field`, or flagged in `void` (indexed like the samples), is
/// NaN. Every other sample counts the observers whose eye sees its target point (see the
/// module's documentation), within `radius` of the observer horizontally when one is given.
///
/// `progress` is called with the number of rows done, over all observers (`observers *
/// height` in all), from any thread. The result is the same whatever the number of threads.
/// Errors: parameters out of range, an observer outside the field or on a void, a `void`
/// mask of the wrong length, or a viewshed too large to allocate.
pub fn viewshed(
    field: &HeightField,
    tracer: &dyn Tracer,
    void: Option<&[bool]>,
    params: &ViewshedParams,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Viewshed, ShadeError> {
    params.validate()?;
    let (width, height) = (field.width(), field.height());
    let samples = width * height;
    crate::error::check_void_mask(void, width, height)?;
    let eyes = params
        .observers
        .iter()
        .map(|o| o.eye(field, tracer, void))
        .collect::<Result<Vec<_>, _>>()?;
    let mut counts = Vec::new();
    counts.try_reserve_exact(samples).map_err(|_| {
        ShadeError::Limits(format!("a {width}x{height} viewshed does not fit in memory"))
    })?;
    counts.resize(samples, 0u32);

    let targets = target_points::TargetPoints::new(field, void, params);
    let done_rows = AtomicU64::new(0);
    let mut rays = 0;
    // The sweeps are one pass each: those of several observers run side by side, as many at
    // a time as there are threads.
    let group = rayon::current_num_threads().max(1);
    for eyes in eyes.chunks(group) {
        let sweeps: Vec<SightLines> = eyes
            .par_iter()
            .map(|&eye| {
                let hidden = hidden_sweep::proven_hidden(field, tracer.surface(), eye, &targets);
                SightLines { field, tracer, targets: &targets, eye, hidden }
            })
            .collect();
        for sights in &sweeps {
            rays += counts
                .par_chunks_mut(BAND_ROWS * width)
                .enumerate()
                .map(|(band, band_counts)| {
                    let rows = band * BAND_ROWS..((band + 1) * BAND_ROWS).min(height);
                    let cast = sights.count_band(rows.clone(), band_counts);
                    let done = rows.len() as u64;
                    progress(done_rows.fetch_add(done, Ordering::Relaxed) + done);
                    cast
                })
                .sum::<u64>();
        }
    }
    let counts = counts
        .iter()
        .enumerate()
        .map(|(index, &count)| {
            let (col, row) = (index % width, index / width);
            if field.is_hole(col, row) || void.is_some_and(|v| v[index]) {
                f32::NAN
            } else {
                count as f32
            }
        })
        .collect();
    Ok(Viewshed { width, height, counts, rays })
}

/// The lines of sight from the samples of a field to one eye.
struct SightLines<'a> {
    field: &'a HeightField,
    tracer: &'a dyn Tracer,
    targets: &'a target_points::TargetPoints<'a>,
    eye: DVec3,
    /// Per sample, whether its line of sight is proven hidden without tracing.
    hidden: Vec<bool>,
}

impl SightLines<'_> {
    /// Adds 1 to `counts` (the samples of `rows`) where the eye sees the sample; returns the
    /// rays traced.
    fn count_band(&self, rows: std::ops::Range<usize>, counts: &mut [u32]) -> u64 {
        let width = self.field.width();
        let mut batch = SightBatch::default();
        let mut cast = 0;
        for first_col in (0..width).step_by(TILE_COLS) {
            let cols = first_col..(first_col + TILE_COLS).min(width);
            batch.clear();
            for row in rows.clone() {
                for col in cols.clone() {
                    if let Some(ray) = self.sight_line(col, row) {
                        batch.push(col + (row - rows.start) * width, ray);
                    }
                }
            }
            cast += batch.trace(self.tracer, counts);
        }
        cast
    }

    /// The ray from the eye to the target point of sample (`col`, `row`), or `None` when
    /// the sample is void, out of the radius, or proven hidden.
    fn sight_line(&self, col: usize, row: usize) -> Option<Ray> {
        if self.hidden.get(col + row * self.field.width()) == Some(&true) {
            return None;
        }
        let target = self.targets.point(col, row, self.eye)?;
        Some(Ray::new(self.eye, target - self.eye).with_range(0.0, 1.0))
    }
}

/// The lines of sight of one tile, traced as one batch.
#[derive(Default)]
struct SightBatch {
    /// Each ray's sample, as an index into the band's counts.
    indices: Vec<usize>,
    rays: Vec<Ray>,
    occluded: Vec<bool>,
    steps: Vec<u32>,
}

impl SightBatch {
    fn clear(&mut self) {
        self.indices.clear();
        self.rays.clear();
    }

    fn push(&mut self, index: usize, ray: Ray) {
        self.indices.push(index);
        self.rays.push(ray);
    }

    /// Traces the batch and counts the unobstructed rays' samples; returns the rays traced.
    fn trace(&mut self, tracer: &dyn Tracer, counts: &mut [u32]) -> u64 {
        let n = self.rays.len();
        if n == 0 {
            return 0;
        }
        self.occluded.clear();
        self.occluded.resize(n, false);
        self.steps.clear();
        self.steps.resize(n, 0);
        tracer.occluded_batch(&self.rays, &mut self.occluded, &mut self.steps);
        for (&index, &blocked) in self.indices.iter().zip(&self.occluded) {
            counts[index] += u32::from(!blocked);
        }
        n as u64
    }
}
