//! The hypsometric colour ramp: terrain colour by elevation, greyer on steep slopes.

use relief_core::DVec3;

use crate::tonemap::srgb_to_linear;
use crate::ShadeError;

/// Stops of the ramp: (elevation fraction, 8-bit sRGB colour), fractions increasing.
const STOPS: [(f64, [u8; 3]); 9] = [
    (0.00, [38, 94, 38]),    // deep green lowlands
    (0.20, [78, 132, 52]),   // green
    (0.38, [160, 170, 84]),  // yellow-green
    (0.55, [146, 108, 62]),  // brown
    (0.72, [128, 110, 96]),  // brown-grey
    (0.84, [136, 134, 132]), // grey rock
    (0.89, [150, 150, 150]), // light rock
    (0.92, [236, 238, 242]), // snow on the top tenth
    (1.00, [250, 250, 255]), // white summits
];

/// Colour of steep rock faces, 8-bit sRGB.
const ROCK: [u8; 3] = [104, 100, 96];

/// Samples of the ramp's linear colour per stretch between two stops, both stops included.
pub(crate) const SAMPLES_PER_STRETCH: usize = 512;

/// Linear-RGB colour of the hypsometric ramp at elevation fraction `t` (clamped to `[0, 1]`,
/// NaN taken as 0): deep green lowlands, yellow-green, brown, grey rock, white snow on the top
/// ~10%. Stops are interpolated in sRGB, which looks even, then converted to linear.
///
/// The conversion to linear (a power per channel) is tabulated once: 512 samples between each
/// two stops, interpolated linearly, within 1e-6 of the curve (see the tests).
pub fn hypsometric_colour(t: f64) -> DVec3 {
    let (k, w) = stretch(t);
    let x = w * SAMPLES_PER_STRETCH as f64;
    let n = (x as usize).min(SAMPLES_PER_STRETCH - 1);
    let samples = &ramp_table()[k - 1];
    samples[n].lerp(samples[n + 1], x - n as f64)
}

/// The ramp's linear colour tabulated: for each stretch between two stops (`k - 1` to `k`, at
/// index `k - 1`), [`SAMPLES_PER_STRETCH`] + 1 samples from one stop to the next, built once.
pub(crate) fn ramp_table() -> &'static [[DVec3; SAMPLES_PER_STRETCH + 1]] {
    static TABLE: std::sync::LazyLock<Vec<[DVec3; SAMPLES_PER_STRETCH + 1]>> =
        std::sync::LazyLock::new(|| {
            (1..STOPS.len())
                .map(|k| {
                    std::array::from_fn(|n| {
                        hypsometric_colour_by_formula(k, n as f64 / SAMPLES_PER_STRETCH as f64)
                    })
                })
                .collect()
        });
    &TABLE
}

/// The elevation fractions of the ramp's stops, increasing from 0 to 1.
pub(crate) fn stop_fractions() -> [f64; STOPS.len()] {
    STOPS.map(|(t, _)| t)
}

/// The linear colour steep slopes turn to.
pub(crate) fn rock_linear() -> DVec3 {
    static ROCK_LINEAR: std::sync::LazyLock<DVec3> =
        std::sync::LazyLock::new(|| linear(srgb8(ROCK)));
    *ROCK_LINEAR
}

/// The stretch of the ramp that elevation fraction `t` falls in (`k`: between stops `k - 1`
/// and `k`), and where in it (0 to 1).
fn stretch(t: f64) -> (usize, f64) {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let k = STOPS.iter().position(|&(s, _)| s >= t).unwrap_or(STOPS.len() - 1).max(1);
    let (t0, t1) = (STOPS[k - 1].0, STOPS[k].0);
    (k, ((t - t0) / (t1 - t0)).clamp(0.0, 1.0))
}

/// The ramp's colour at `w` (0 to 1) of the stretch between stops `k - 1` and `k`, computed.
fn hypsometric_colour_by_formula(k: usize, w: f64) -> DVec3 {
    linear(srgb8(STOPS[k - 1].1).lerp(srgb8(STOPS[k].1), w))
}

/// A colour ramp over the elevation range `[min_z, max_z]` of a terrain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HypsometricRamp {
    /// World elevation at the bottom of the ramp.
    pub min_z: f64,
    /// World elevation at the top of the ramp (at least `min_z`).
    pub max_z: f64,
    /// Whether steep slopes turn to darker grey rock (snow and grass do not hold there).
    pub steep_rock: bool,
}

impl HypsometricRamp {
    /// The ramp over `[min_z, max_z]` with steep rock on, checked.
    pub fn new(min_z: f64, max_z: f64) -> Result<Self, ShadeError> {
        let ramp = HypsometricRamp { min_z, max_z, steep_rock: true };
        ramp.validate()?;
        Ok(ramp)
    }

    /// Checks that both bounds are finite and `min_z <= max_z` (equal bounds colour everything
    /// as lowland).
    pub fn validate(&self) -> Result<(), ShadeError> {
        if !(self.min_z.is_finite() && self.max_z.is_finite() && self.min_z <= self.max_z) {
            return Err(ShadeError::parameter(
                "hypsometric range",
                format!("[{}, {}] is not a finite, ordered range", self.min_z, self.max_z),
            ));
        }
        Ok(())
    }

    /// Linear albedo at world elevation `z` on a surface whose unit normal has vertical
    /// component `normal_z`.
    pub fn albedo(&self, z: f64, normal_z: f64) -> DVec3 {
        let extent = self.max_z - self.min_z;
        let t = if extent > 0.0 { (z - self.min_z) / extent } else { 0.0 };
        let colour = hypsometric_colour(t);
        if !self.steep_rock {
            return colour;
        }
        // 1 - n.z is 0.13 at a 30° slope, 0.29 at 45° and 0.5 at 60°: rock takes over between
        // about 35° and 60°.
        let steepness = 1.0 - normal_z.clamp(0.0, 1.0);
        colour.lerp(rock_linear(), smoothstep(0.18, 0.5, steepness))
    }
}

fn smoothstep(lo: f64, hi: f64, x: f64) -> f64 {
    let s = ((x - lo) / (hi - lo)).clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

fn srgb8(c: [u8; 3]) -> DVec3 {
    DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) / 255.0
}

fn linear(srgb: DVec3) -> DVec3 {
    let f = |v: f64| srgb_to_linear(v as f32) as f64;
    DVec3::new(f(srgb.x), f(srgb.y), f(srgb.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_runs_from_green_to_snow() {
        let low = hypsometric_colour(0.0);
        assert!(low.y > low.x && low.y > low.z, "lowlands are green: {low}");
        let mid = hypsometric_colour(0.6);
        assert!(mid.x > mid.y && mid.y > mid.z, "middle is brown: {mid}");
        let top = hypsometric_colour(0.95);
        assert!(top.min_element() > 0.8, "the top tenth is snow: {top}");
        assert!(hypsometric_colour(0.85).max_element() < 0.35, "below the snow is rock");
        assert_eq!(hypsometric_colour(-3.0), low);
        assert_eq!(hypsometric_colour(f64::NAN), low);
        assert_eq!(hypsometric_colour(7.0), hypsometric_colour(1.0));
        // Continuous: no jumps larger than the stops' own steps.
        for k in 0..1000 {
            let (a, b) = (
                hypsometric_colour(k as f64 / 1000.0),
                hypsometric_colour((k + 1) as f64 / 1000.0),
            );
            assert!((a - b).abs().max_element() < 0.05, "jump at {k}");
        }
    }

    #[test]
    fn the_table_follows_the_formula() {
        let mut worst = 0.0f64;
        for k in 0..=200_000 {
            let t = k as f64 / 200_000.0;
            let (stretch, w) = stretch(t);
            let error = hypsometric_colour(t) - hypsometric_colour_by_formula(stretch, w);
            worst = worst.max(error.abs().max_element());
        }
        assert!(worst < 1e-6, "the table is {worst} off");
        // At the stops exactly.
        for (k, &(t, _)) in STOPS.iter().enumerate().skip(1) {
            assert_eq!(hypsometric_colour(t), hypsometric_colour_by_formula(k, 1.0));
        }
    }

    #[test]
    fn steep_slopes_turn_to_rock() {
        let ramp = HypsometricRamp::new(100.0, 200.0).unwrap();
        let snow_flat = ramp.albedo(199.0, 1.0);
        let snow_cliff = ramp.albedo(199.0, 0.2);
        assert!(snow_cliff.max_element() < 0.5 * snow_flat.min_element());
        let smooth = HypsometricRamp { steep_rock: false, ..ramp };
        assert_eq!(smooth.albedo(199.0, 0.2), snow_flat);
        assert!(HypsometricRamp::new(2.0, 1.0).is_err());
        assert!(HypsometricRamp::new(f64::NAN, 1.0).is_err());
        assert_eq!(
            HypsometricRamp::new(5.0, 5.0).unwrap().albedo(5.0, 1.0),
            hypsometric_colour(0.0)
        );
    }
}
