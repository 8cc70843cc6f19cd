//! The suite itself: builds the tracer under test on every terrain and surface, casts every
//! kind of ray (single and in batches, full and limited ranges, coherent camera rays) and
//! holds each answer against the reference.

use super::brute_force::Floor;
use super::rays::{ray, RAY_KINDS};
use super::report::{Check, Failure, Report};
use super::seeded::Seeded;
use super::terrains::terrain;
use super::verdict::{same_hit, Reference};
use crate::{Hit, Tracer};
use relief_core::{Camera, HeightField, Ray, Surface};
use std::sync::Arc;

/// How many terrains and rays one run checks, and the seed that draws them.
#[derive(Debug, Clone, Copy)]
pub struct Suite {
    floor: Floor,
    terrains: usize,
    rays_per_kind: usize,
    seed: u64,
}

impl Default for Suite {
    /// 40 terrains, 4 rays of each kind per terrain and surface, solids down to the lowest
    /// sample.
    fn default() -> Self {
        Suite { floor: Floor::LowestSample, terrains: 40, rays_per_kind: 4, seed: 36 }
    }
}

impl Suite {
    /// The default suite ([`Suite::default`]).
    pub fn new() -> Self {
        Suite::default()
    }

    /// The same suite for tracers whose solid reaches down to `floor`.
    pub fn floor(self, floor: Floor) -> Self {
        Suite { floor, ..self }
    }

    /// The same suite on `terrains` terrains (the first eight are the small fixed sizes).
    pub fn terrains(self, terrains: usize) -> Self {
        Suite { terrains, ..self }
    }

    /// The same suite with `rays` rays of each kind per terrain and surface.
    pub fn rays_per_kind(self, rays: usize) -> Self {
        Suite { rays_per_kind: rays, ..self }
    }

    /// The same suite drawn from another seed.
    pub fn seed(self, seed: u64) -> Self {
        Suite { seed, ..self }
    }

    /// The terrain `index` of this suite, as [`Suite::run`] draws it (to reproduce a failure).
    pub fn terrain(&self, index: usize) -> HeightField {
        terrain(index, &mut Seeded::new(self.seed ^ (index as u64) << 32))
    }

    /// Checks the tracers `build` makes, one per terrain and surface; `build` returns `None`
    /// for what its tracer cannot stand for (a surface it does not trace, holes, cells that
    /// are not square), which is then skipped.
    pub fn run<F>(&self, build: F) -> Report
    where
        F: Fn(&Arc<HeightField>, Surface) -> Option<Box<dyn Tracer>>,
    {
        let mut report = Report::default();
        for index in 0..self.terrains {
            let field = Arc::new(self.terrain(index));
            for surface in Surface::ALL {
                let Some(tracer) = build(&field, surface) else { continue };
                report.tracer = tracer.name().to_string();
                report.cases += 1;
                let mut numbers = Seeded::new(self.seed ^ (index as u64) << 32 ^ surface as u64);
                let case = Case {
                    index,
                    reference: Reference::new(&field, surface, self.floor),
                    tracer: tracer.as_ref(),
                };
                let rays = self.rays(&case, &mut numbers);
                report.rays += rays.len();
                case.check(&rays, &mut report.failures);
            }
        }
        report
    }

    /// The rays of one case: each kind's random rays over their whole range and limited to
    /// a random part of it, then a small camera's coherent rays.
    fn rays(&self, case: &Case, numbers: &mut Seeded) -> Vec<Ray> {
        let field = case.reference.field;
        let mut rays = Vec::new();
        for kind in RAY_KINDS {
            for _ in 0..self.rays_per_kind {
                let whole = ray(field, kind, numbers);
                rays.push(whole);
                rays.push(limited(&case.reference, whole, numbers));
            }
        }
        let bounds = field.world_bounds(Surface::Boxes);
        if let Ok(camera) = Camera::frame(&bounds, 12, 8) {
            rays.extend(
                (0..8).flat_map(|j| (0..12).map(move |i| (i, j))).map(|(i, j)| camera.ray(i, j)),
            );
        }
        rays
    }
}

/// `ray` limited to a part of its range: from a start before or past its first hit, to an
/// end kept 5% or more away from the first hit after that start (an end at the hit itself
/// would be a tie).
fn limited(reference: &Reference, ray: Ray, numbers: &mut Seeded) -> Ray {
    let reach = |r: &Ray| reference.first_hit(r, 0.0).map_or(1.0, |e| e.t.max(1e-3));
    let t_min = reach(&ray) * numbers.range(0.0, 1.5);
    let started = ray.with_range(t_min, f64::INFINITY);
    let span = reach(&started).max(t_min + 1e-3);
    let fraction =
        if numbers.unit() < 0.5 { numbers.range(0.05, 0.95) } else { numbers.range(1.05, 1.5) };
    ray.with_range(t_min, t_min + (span - t_min) * fraction)
}

/// One tracer on one terrain and surface.
struct Case<'a> {
    index: usize,
    reference: Reference<'a>,
    tracer: &'a dyn Tracer,
}

impl Case<'_> {
    /// Checks every promise of the trait on `rays`, adding what fails to `failures`.
    fn check(&self, rays: &[Ray], failures: &mut Vec<Failure>) {
        let bounds = self.tracer.bounds();
        let single: Vec<Option<Hit>> = rays.iter().map(|r| self.tracer.intersect(r)).collect();
        let occluded: Vec<bool> = rays.iter().map(|r| self.tracer.occluded(r)).collect();
        let mut batch = vec![None; rays.len()];
        let mut batch_occluded = vec![false; rays.len()];
        self.tracer.intersect_batch(rays, &mut batch, &mut vec![0; rays.len()]);
        self.tracer.occluded_batch(rays, &mut batch_occluded, &mut vec![0; rays.len()]);
        for (k, ray) in rays.iter().enumerate() {
            let fail = |check: Check, detail: String| Failure {
                terrain: self.index,
                size: (self.reference.field.width(), self.reference.field.height()),
                surface: self.reference.surface,
                ray: *ray,
                check,
                detail,
            };
            if let Some((check, detail)) = self.reference.judge(ray, single[k]) {
                failures.push(fail(check, detail));
            }
            if let Some((check, detail)) = self.reference.judge_occluded(ray, occluded[k]) {
                failures.push(fail(check, detail));
            }
            let span = self.reference.extent / ray.dir.length();
            if !same_hit(batch[k], single[k], span) {
                let detail = format!("batch {:?}, single {:?}", batch[k], single[k]);
                failures.push(fail(Check::IntersectBatch, detail));
            }
            if batch_occluded[k] != occluded[k] {
                let detail = format!("batch {}, single {}", batch_occluded[k], occluded[k]);
                failures.push(fail(Check::OccludedBatch, detail));
            }
            for hit in [single[k], batch[k]].into_iter().flatten() {
                if !self.reference.within(&bounds, &hit) {
                    failures.push(fail(Check::Bounds, format!("hit {hit:?} outside {bounds:?}")));
                }
            }
        }
    }
}
