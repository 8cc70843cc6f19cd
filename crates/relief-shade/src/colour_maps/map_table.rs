//! A colour map tabulated at evenly spaced positions, in `f64` for the shading pass and in
//! `f32` lanes for the shading kernel, interpolated linearly the same way in both.

use relief_core::DVec3;

use super::ColourMap;

/// Intervals of a map's table: samples at `u = k / STEPS`, `k = 0..=STEPS`.
pub(crate) const STEPS: usize = 4096;

/// A colour map's linear colour at `STEPS + 1` evenly spaced positions.
pub(crate) struct MapTable {
    /// The samples in `f64`.
    linear: Box<[DVec3; STEPS + 1]>,
    /// The samples in `f32`, one table per channel (fixed size: lookups at clamped indices
    /// need no bounds checks).
    lanes: [Box<[f32; STEPS + 1]>; 3],
}

impl MapTable {
    /// The table of `map`, computed from its formula.
    pub(crate) fn build(map: ColourMap) -> MapTable {
        let linear: Box<[DVec3; STEPS + 1]> = (0..=STEPS)
            .map(|k| map.colour_by_formula(k as f64 / STEPS as f64))
            .collect::<Vec<_>>()
            .try_into()
            .expect("STEPS + 1 samples");
        let lanes = [0, 1, 2].map(|ch| {
            let mut channel = Box::new([0.0f32; STEPS + 1]);
            for (entry, colour) in channel.iter_mut().zip(linear.iter()) {
                *entry = colour[ch] as f32;
            }
            channel
        });
        MapTable { linear, lanes }
    }

    /// The colour at `u` (clamped to `[0, 1]`, NaN taken as 0), between the two nearest
    /// samples.
    pub(crate) fn colour(&self, u: f64) -> DVec3 {
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
        let x = u * STEPS as f64;
        let n = (x as usize).min(STEPS - 1);
        self.linear[n].lerp(self.linear[n + 1], x - n as f64)
    }

    /// The colours at positions `u` by channel, as [`MapTable::colour`] finds them, in `f32`.
    #[inline(always)]
    pub(crate) fn colour_lanes<const N: usize>(&self, u: &[f32; N]) -> [[f32; N]; 3] {
        let mut base = [0usize; N];
        let mut fraction = [0.0f32; N];
        for l in 0..N {
            let u = if u[l].is_nan() { 0.0 } else { u[l].clamp(0.0, 1.0) };
            let x = u * STEPS as f32;
            let n = (x as usize).min(STEPS - 1);
            base[l] = n;
            fraction[l] = x - n as f32;
        }
        let mut colour = [[0.0f32; N]; 3];
        for (table, colour) in self.lanes.iter().zip(&mut colour) {
            for l in 0..N {
                let (a, b) = (table[base[l]], table[base[l] + 1]);
                colour[l] = a + (b - a) * fraction[l];
            }
        }
        colour
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_follow_the_f64_table() {
        let table = MapTable::build(ColourMap::Magma);
        let u: [f32; 8] = [-1.0, 0.0, 0.1234, 0.5, 0.77777, 0.999, 1.0, f32::NAN];
        let lanes = table.colour_lanes(&u);
        for (l, &u) in u.iter().enumerate() {
            let want = table.colour(u as f64);
            for ch in 0..3 {
                assert!((lanes[ch][l] as f64 - want[ch]).abs() < 1e-6, "u {u}, channel {ch}");
            }
        }
    }
}
