//! The water half of the `bathymetry` colour map: blues from the deepest water to the shore.

use relief_core::DVec3;

use super::linear_from_srgb;

/// Stops of the water ramp: (depth fraction, 0 the deepest and 1 the sea level; 8-bit sRGB),
/// fractions increasing. relief's own, in the manner of the ocean blues of GMT and ColorBrewer:
/// lightness rises steadily towards the shore, so that depth reads as darkness.
const STOPS: [(f64, [u8; 3]); 5] = [
    (0.00, [8, 29, 88]),     // abyssal navy
    (0.35, [24, 74, 148]),   // deep blue
    (0.65, [52, 124, 188]),  // mid blue
    (0.88, [118, 182, 220]), // shelf
    (1.00, [178, 224, 240]), // shallows
];

/// The water ramp's linear colour at fraction `w` (0 the deepest water, 1 the sea level),
/// clamped to `[0, 1]`; stops interpolated in sRGB.
pub(super) fn water_colour(w: f64) -> DVec3 {
    let w = w.clamp(0.0, 1.0);
    let k = STOPS.iter().position(|&(s, _)| s >= w).unwrap_or(STOPS.len() - 1).max(1);
    let ((w0, a), (w1, b)) = (STOPS[k - 1], STOPS[k]);
    let srgb = |c: [u8; 3]| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) / 255.0;
    let f = ((w - w0) / (w1 - w0)).clamp(0.0, 1.0);
    linear_from_srgb(srgb(a).lerp(srgb(b), f))
}

#[cfg(test)]
mod tests {
    use super::super::lightness;
    use super::*;

    #[test]
    fn water_is_blue_and_lighter_towards_the_shore() {
        let mut previous = -1.0;
        for k in 0..=100 {
            let c = water_colour(k as f64 / 100.0);
            assert!(c.z > c.x && c.z >= c.y, "blue at {k}: {c}");
            let l = lightness(c);
            assert!(l > previous, "lighter towards the shore at {k}");
            previous = l;
        }
        // At the stops exactly.
        for (w, c) in STOPS {
            let srgb = DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) / 255.0;
            assert!((water_colour(w) - linear_from_srgb(srgb)).abs().max_element() < 1e-12);
        }
    }
}
