//! The ray directions of a shade map: the sky's hemisphere and a soft sun's disc.

use relief_core::DVec3;

/// The golden angle in radians, `π (3 - √5)`: successive points turned by it never line up.
const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653;

/// The sky's directions for the sky-view factor: `n` directions over the hemisphere above the
/// horizontal plane, uniform in solid angle, on `azimuths` compass directions with `bands`
/// elevations each (`azimuths * bands = n`).
///
/// The `n` directions rise to `sin(elevation) = (k + 0.5) / n` for `k = 0..n`, the midpoints of
/// `n` equal steps (so under a horizon at elevation `γ` all round, the fraction of them that
/// escape is within `1 / n` of the sky-view factor `1 - sin γ`). Elevation band `b` of azimuth
/// `a` takes `k = b * azimuths + rank(a)`, where `rank` orders the azimuths by the fractional
/// part of `a` golden ratios, so that neighbouring azimuths sample their bands at well-spread
/// heights. The azimuths are evenly spaced, turned by a fixed irrational angle so that none
/// runs along the grid's rows or columns. Every sample of a map uses the same set, so its rays
/// trace as coherent batches and a map has no noise.
///
/// Grouped by azimuth, a sample's rays can be traced by bisection: from a point on a height
/// field, a ray that meets the terrain hides every lower ray of its azimuth too (the lower ray
/// passes under the hit point, inside the solid), so the escaping rays of an azimuth are its
/// highest ones, and finding where they start decides all of them.
#[derive(Debug, Clone, PartialEq)]
pub struct SkyDirections {
    azimuths: usize,
    bands: usize,
    /// Azimuth-major: the `bands` directions of azimuth 0, lowest first, then azimuth 1, ...
    directions: Vec<DVec3>,
}

/// The turn of the first azimuth from north, in radians: not a rational multiple of π.
const AZIMUTH_TURN: f64 = 0.1;

impl SkyDirections {
    /// The set of `n` directions (at least 1), with `bands` the largest divisor of `n` at most
    /// `sqrt(n / 2)`: 64 directions are 16 azimuths of 4 elevations, 256 are 32 of 8.
    pub fn new(n: u32) -> SkyDirections {
        let n = n.max(1) as usize;
        let bands = (1..=n).filter(|b| n.is_multiple_of(*b) && 2 * b * b <= n).max().unwrap_or(1);
        let azimuths = n / bands;
        let golden = (5f64.sqrt() - 1.0) / 2.0;
        let mut order: Vec<usize> = (0..azimuths).collect();
        order.sort_by(|&a, &b| (a as f64 * golden).fract().total_cmp(&(b as f64 * golden).fract()));
        let mut rank = vec![0; azimuths];
        for (r, &a) in order.iter().enumerate() {
            rank[a] = r;
        }
        let mut directions = Vec::with_capacity(n);
        for (a, &rank) in rank.iter().enumerate() {
            let azimuth = AZIMUTH_TURN + (a as f64 + 0.5) * std::f64::consts::TAU / azimuths as f64;
            for band in 0..bands {
                let z = ((band * azimuths + rank) as f64 + 0.5) / n as f64;
                let horizontal = (1.0 - z * z).sqrt();
                directions.push(DVec3::new(
                    azimuth.sin() * horizontal,
                    azimuth.cos() * horizontal,
                    z,
                ));
            }
        }
        SkyDirections { azimuths, bands, directions }
    }

    /// How many compass directions the set has.
    pub fn azimuths(&self) -> usize {
        self.azimuths
    }

    /// How many elevations each azimuth has.
    pub fn bands(&self) -> usize {
        self.bands
    }

    /// The direction of elevation `band` (0 the lowest) of `azimuth`.
    pub fn direction(&self, azimuth: usize, band: usize) -> DVec3 {
        self.directions[azimuth * self.bands + band]
    }

    /// Every direction, azimuth by azimuth, lowest first.
    pub fn all(&self) -> &[DVec3] {
        &self.directions
    }
}

/// The `n` directions of [`SkyDirections::new`], azimuth by azimuth, lowest first.
pub fn sky_directions(n: u32) -> Vec<DVec3> {
    SkyDirections::new(n).directions
}

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
    fn sky_directions_are_unit_and_above_the_horizon() {
        let dirs = sky_directions(64);
        assert_eq!(dirs.len(), 64);
        for d in &dirs {
            assert!((d.length() - 1.0).abs() < 1e-12);
            assert!(d.z > 0.0 && d.z < 1.0);
        }
    }

    #[test]
    fn sky_directions_are_uniform_in_solid_angle() {
        // The mean of z over the hemisphere, uniform in solid angle, is 1/2, and the set's z
        // values are the midpoints of n equal steps of [0, 1].
        let dirs = sky_directions(400);
        let mean_z = dirs.iter().map(|d| d.z).sum::<f64>() / 400.0;
        assert!((mean_z - 0.5).abs() < 1e-9, "{mean_z}");
        let mut steps: Vec<f64> = dirs.iter().map(|d| d.z * 400.0 - 0.5).collect();
        steps.sort_by(f64::total_cmp);
        for (k, step) in steps.iter().enumerate() {
            assert!((step - k as f64).abs() < 1e-9, "{k}: {step}");
        }
        // Balanced round the compass: the mean horizontal vector is near 0.
        let mean_x = dirs.iter().map(|d| d.x).sum::<f64>() / 400.0;
        let mean_y = dirs.iter().map(|d| d.y).sum::<f64>() / 400.0;
        assert!(mean_x.abs() < 0.01 && mean_y.abs() < 0.01, "{mean_x} {mean_y}");
    }

    #[test]
    fn sky_directions_are_azimuths_of_rising_bands() {
        for (n, azimuths, bands) in
            [(1, 1, 1), (7, 7, 1), (12, 6, 2), (16, 8, 2), (64, 16, 4), (256, 32, 8)]
        {
            let sky = SkyDirections::new(n);
            assert_eq!((sky.azimuths(), sky.bands()), (azimuths, bands), "{n}");
            assert_eq!(sky.all().len(), n as usize);
            for a in 0..azimuths {
                let first = sky.direction(a, 0);
                let compass = first.x.atan2(first.y);
                for b in 0..bands {
                    let d = sky.direction(a, b);
                    // The same compass direction, rising band by band.
                    assert!((d.x.atan2(d.y) - compass).abs() < 1e-12);
                    assert!(b == 0 || d.z > sky.direction(a, b - 1).z);
                }
                // None along the grid's rows or columns.
                let quarter = std::f64::consts::FRAC_PI_2;
                let off_axis = (compass / quarter - (compass / quarter).round()).abs();
                assert!(off_axis > 1e-3, "{n} directions: azimuth {a} runs along an axis");
            }
        }
    }

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
