//! What a run of the suite found: how much it checked and every disagreement, each with what
//! reproduces it.

use relief_core::{Ray, Surface};
use std::fmt;

/// Which promise of [`crate::Tracer`] a failure broke.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Check {
    /// `intersect`: a hit where the reference has none, none where it has one, or another `t`.
    Intersect,
    /// The hit's position is not the ray's point at the reference's `t`.
    Position,
    /// The hit's normal is none of the normals of the faces the reference meets there.
    Normal,
    /// `occluded` differs from whether the reference meets the ray within its range.
    Occluded,
    /// `intersect_batch` differs from `intersect` ray by ray.
    IntersectBatch,
    /// `occluded_batch` differs from `occluded` ray by ray.
    OccludedBatch,
    /// A hit lies outside the tracer's `bounds()`.
    Bounds,
}

/// One disagreement between a tracer and the reference.
#[derive(Debug, Clone)]
pub struct Failure {
    /// Index of the suite's terrain (with the suite's seed, what draws it again).
    pub terrain: usize,
    /// The terrain's size, `(width, height)`.
    pub size: (usize, usize),
    /// The surface traced.
    pub surface: Surface,
    /// The ray.
    pub ray: Ray,
    /// The promise broken.
    pub check: Check,
    /// What the tracer answered and what the reference expected.
    pub detail: String,
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:?} on terrain {} ({}x{}, {}), {:?}: {}",
            self.check, self.terrain, self.size.0, self.size.1, self.surface, self.ray, self.detail
        )
    }
}

/// What one run of the suite checked and found.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// The tracer's name, as [`crate::Tracer::name`] gives it.
    pub tracer: String,
    /// Terrain and surface pairs the tracer was built for and checked on.
    pub cases: usize,
    /// Rays checked, over all cases.
    pub rays: usize,
    /// Every disagreement found.
    pub failures: Vec<Failure>,
}

impl Report {
    /// Panics, listing the first failures, unless the tracer was checked on some case and
    /// nothing disagreed.
    pub fn assert_conforms(&self) {
        assert!(self.cases > 0, "{}: the constructor built no tracer for any terrain", self.tracer);
        if self.failures.is_empty() {
            return;
        }
        let listed: Vec<String> = self.failures.iter().take(12).map(|f| f.to_string()).collect();
        panic!(
            "{}: {} of {} rays on {} cases disagree with the reference:\n{}",
            self.tracer,
            self.failures.len(),
            self.rays,
            self.cases,
            listed.join("\n")
        );
    }
}
