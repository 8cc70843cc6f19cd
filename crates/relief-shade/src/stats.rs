//! Counters of the rays a pass traced: how many, how many hit, how many traversal steps.

/// Ray and traversal-step counts of a rendering pass; merge the counts of parts with
/// [`TraceStats::merge`] (sums and a maximum, so the order of merging does not matter).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TraceStats {
    /// Rays traced.
    pub rays: u64,
    /// Rays that hit the terrain (for shadow rays: that were occluded).
    pub hits: u64,
    /// Traversal steps (cells or nodes visited) over all rays.
    pub total_steps: u64,
    /// Most steps any one ray took.
    pub max_steps: u32,
}

impl TraceStats {
    /// Counts one ray that took `steps` steps and hit (or was occluded) when `hit`.
    #[inline]
    pub fn record(&mut self, steps: u32, hit: bool) {
        self.rays += 1;
        self.hits += u64::from(hit);
        self.total_steps += u64::from(steps);
        self.max_steps = self.max_steps.max(steps);
    }

    /// The counts of both `self` and `other`.
    #[must_use]
    pub fn merge(self, other: TraceStats) -> TraceStats {
        TraceStats {
            rays: self.rays + other.rays,
            hits: self.hits + other.hits,
            total_steps: self.total_steps + other.total_steps,
            max_steps: self.max_steps.max(other.max_steps),
        }
    }

    /// Mean steps per ray (0 when no ray was traced).
    pub fn mean_steps(&self) -> f64 {
        if self.rays == 0 {
            0.0
        } else {
            self.total_steps as f64 / self.rays as f64
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merging_sums_counts_and_keeps_the_largest_step_count() {
        let mut a = TraceStats::default();
        a.record(3, true);
        a.record(5, false);
        let mut b = TraceStats::default();
        b.record(9, true);
        let m = a.merge(b);
        assert_eq!(m, TraceStats { rays: 3, hits: 2, total_steps: 17, max_steps: 9 });
        assert_eq!(m, b.merge(a));
        assert!((m.mean_steps() - 17.0 / 3.0).abs() < 1e-12);
        assert_eq!(TraceStats::default().mean_steps(), 0.0);
    }
}
