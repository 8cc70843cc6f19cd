//! The hypsometric ramp's table in `f32`, looked up as `HypsometricRamp::albedo` does.

use std::sync::LazyLock;

use crate::colour_ramp::{ramp_table, stop_fractions, SAMPLES_PER_STRETCH};

/// Stops of the ramp.
const STOPS: usize = 9;

/// The ramp's samples in `f32`: for each stretch between two stops, `SAMPLES_PER_STRETCH + 1`
/// linear colours, and where the stretch lies.
pub(crate) struct RampLanes {
    /// The stops' elevation fractions.
    stops: [f32; STOPS],
    /// `1 / (t1 - t0)` of each stretch, at the index of its upper stop.
    inverse_width: [f32; STOPS],
    /// The samples, stretch after stretch.
    samples: Vec<[f32; 3]>,
}

impl RampLanes {
    /// The table, built once from the `f64` one.
    pub(crate) fn get() -> &'static RampLanes {
        static TABLE: LazyLock<RampLanes> = LazyLock::new(|| {
            let fractions = stop_fractions();
            assert_eq!(fractions.len(), STOPS, "the ramp's stops");
            let stops = fractions.map(|t| t as f32);
            let mut inverse_width = [0.0f32; STOPS];
            for k in 1..STOPS {
                inverse_width[k] = (1.0 / (fractions[k] - fractions[k - 1])) as f32;
            }
            let samples = ramp_table()
                .iter()
                .flat_map(|stretch| stretch.iter().map(|c| c.as_vec3().to_array()))
                .collect();
            RampLanes { stops, inverse_width, samples }
        });
        &TABLE
    }

    /// The ramp's linear colour at elevation fraction `t` (clamped to `[0, 1]`, NaN taken as
    /// 0), interpolated between the two nearest samples as `hypsometric_colour` does.
    #[inline(always)]
    pub(crate) fn colour(&self, t: f32) -> [f32; 3] {
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        // The first stop at or above t, at least the second (as `stretch` finds it).
        let mut k = 1;
        while k < STOPS - 1 && self.stops[k] < t {
            k += 1;
        }
        let w = ((t - self.stops[k - 1]) * self.inverse_width[k]).clamp(0.0, 1.0);
        let x = w * SAMPLES_PER_STRETCH as f32;
        let n = (x as usize).min(SAMPLES_PER_STRETCH - 1);
        let f = x - n as f32;
        let base = (k - 1) * (SAMPLES_PER_STRETCH + 1) + n;
        let (a, b) = (self.samples[base], self.samples[base + 1]);
        [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f]
    }
}
