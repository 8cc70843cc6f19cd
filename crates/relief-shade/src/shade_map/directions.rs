//! The ray directions of a shade map over a soft sun's disc.

use relief_core::DVec3;

/// The golden angle in radians, `π (3 - √5)`: successive points turned by it never line up.
const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653;

/// `n` directions spread evenly over the disc of angular radius `radius_deg` round the unit
/// direction `centre`: a Vogel spiral (point `k` at `radius * sqrt((k + 0.5) / n)` from the
/// centre, turned by `k` golden angles), so each stands for an equal part of the disc. With
/// `n = 1` or a radius of 0 it is the centre alone.
pub fn disc_directions(centre: DVec3, radius_deg: f64, n: u32) -> Vec<DVec3> {
    if n <= 1 || radius_deg == 0.0 {
        return vec![centre];
    }
    let (u, v) = perpendicular_basis(centre);
    let tan_radius = radius_deg.to_radians().tan();
    (0..n)
        .map(|k| {
            let r = tan_radius * ((k as f64 + 0.5) / n as f64).sqrt();
            let angle = k as f64 * GOLDEN_ANGLE;
            (centre + (u * angle.cos() + v * angle.sin()) * r).normalize()
        })
        .collect()
}

/// Two unit vectors perpendicular to the unit `w` and to each other.
fn perpendicular_basis(w: DVec3) -> (DVec3, DVec3) {
    let helper = if w.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = w.cross(helper).normalize();
    (u, w.cross(u))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disc_directions_stay_within_the_radius() {
        let centre = DVec3::new(0.3, -0.5, 0.8).normalize();
        let dirs = disc_directions(centre, 2.0, 32);
        assert_eq!(dirs.len(), 32);
        let cos_radius = 2.0f64.to_radians().cos();
        let mut widest: f64 = 1.0;
        for d in &dirs {
            assert!((d.length() - 1.0).abs() < 1e-12);
            assert!(d.dot(centre) >= cos_radius - 1e-12);
            widest = widest.min(d.dot(centre));
        }
        // The outermost point lies near the rim, not bunched at the centre.
        assert!(widest < 1.9f64.to_radians().cos(), "{widest}");
        assert_eq!(disc_directions(centre, 0.0, 32), vec![centre]);
        assert_eq!(disc_directions(centre, 2.0, 1), vec![centre]);
    }
}
