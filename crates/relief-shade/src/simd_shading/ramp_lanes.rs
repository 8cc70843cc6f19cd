//! The hypsometric ramp's table in `f32`, looked up as `HypsometricRamp::albedo` does, `N`
//! pixels at a time (indices computed in lanes, then one gather per sample and channel).

use std::sync::LazyLock;

use crate::colour_ramp::{ramp_table, stop_fractions, SAMPLES_PER_STRETCH};

/// Stops of the ramp.
const STOPS: usize = 9;

/// Entries of each channel's table: every stretch's samples, both stops included.
const ENTRIES: usize = (STOPS - 1) * (SAMPLES_PER_STRETCH + 1);

/// The ramp's samples in `f32`: for each stretch between two stops, `SAMPLES_PER_STRETCH + 1`
/// linear colours, and where the stretch lies. Fixed-size arrays, so that lookups at clamped
/// indices need no bounds checks and the kernel's loops stay in lanes.
pub(crate) struct RampLanes {
    /// The stops' elevation fractions, padded to 16 with 2 (above every fraction).
    stops: [f32; 16],
    /// `1 / (t1 - t0)` of each stretch, at the index of its upper stop.
    inverse_width: [f32; 16],
    /// The samples, stretch after stretch, one table per channel.
    samples: [Box<[f32; ENTRIES]>; 3],
}

impl RampLanes {
    /// The table, built once from the `f64` one.
    pub(crate) fn get() -> &'static RampLanes {
        static TABLE: LazyLock<RampLanes> = LazyLock::new(|| {
            let fractions = stop_fractions();
            assert_eq!(fractions.len(), STOPS, "the ramp's stops");
            let mut stops = [2.0f32; 16];
            let mut inverse_width = [0.0f32; 16];
            for k in 0..STOPS {
                stops[k] = fractions[k] as f32;
                if k > 0 {
                    inverse_width[k] = (1.0 / (fractions[k] - fractions[k - 1])) as f32;
                }
            }
            let colours: Vec<[f32; 3]> = ramp_table()
                .iter()
                .flat_map(|stretch| stretch.iter().map(|c| c.as_vec3().to_array()))
                .collect();
            assert_eq!(colours.len(), ENTRIES, "the ramp's samples");
            let samples = [0, 1, 2].map(|ch| {
                let mut table = Box::new([0.0f32; ENTRIES]);
                for (entry, colour) in table.iter_mut().zip(&colours) {
                    *entry = colour[ch];
                }
                table
            });
            RampLanes { stops, inverse_width, samples }
        });
        &TABLE
    }

    /// The ramp's linear colour at elevation fractions `t` (clamped to `[0, 1]`, NaN taken as
    /// 0), by channel, interpolated between the two nearest samples as `hypsometric_colour`
    /// does.
    #[inline(always)]
    pub(crate) fn colour_lanes<const N: usize>(&self, t: &[f32; N]) -> [[f32; N]; 3] {
        let mut base = [0usize; N];
        let mut fraction = [0.0f32; N];
        for l in 0..N {
            let t = if t[l].is_nan() { 0.0 } else { t[l].clamp(0.0, 1.0) };
            // The first stop at or above t, at least the second (as `stretch` finds it): one
            // more than the inner stops below t.
            let mut k = 1;
            for s in 1..STOPS - 1 {
                k += usize::from(self.stops[s] < t);
            }
            let w = ((t - self.stops[(k - 1) & 15]) * self.inverse_width[k & 15]).clamp(0.0, 1.0);
            let x = w * SAMPLES_PER_STRETCH as f32;
            let n = (x as usize).min(SAMPLES_PER_STRETCH - 1);
            fraction[l] = x - n as f32;
            base[l] = ((k - 1) * (SAMPLES_PER_STRETCH + 1) + n).min(ENTRIES - 2);
        }
        let mut colour = [[0.0f32; N]; 3];
        for (table, colour) in self.samples.iter().zip(&mut colour) {
            for l in 0..N {
                let (a, b) = (table[base[l]], table[base[l] + 1]);
                colour[l] = a + (b - a) * fraction[l];
            }
        }
        colour
    }
}
