//! The layers that follow from a sample's horizon angles: the sky-view factor (Zakšek et al.
//! 2011), its anisotropic form (the Relief Visualization Toolbox's), openness (Yokoyama et al.
//! 2002) and the diffuse light of a uniform or overcast sky on the tilted cell.

use relief_core::DVec3;
use std::f64::consts::{FRAC_PI_2, PI};

/// The anisotropic sky-view factor's weighting of directions, as the Relief Visualization
/// Toolbox (RVT) defines it: direction `φ` weighs `(1 - min_weight) cos((φ - main) / 2)^level
/// + min_weight`, so the sky towards `main` counts most.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Anisotropy {
    /// The direction that weighs most, degrees clockwise from north (RVT's default 315).
    pub main_direction_deg: f64,
    /// The power of the cosine (RVT's "low" level 4, "high" 8).
    pub polynomial: i32,
    /// The weight of the direction opposite the main one (RVT's "low" 0.4, "high" 0.1).
    pub min_weight: f64,
}

impl Default for Anisotropy {
    /// RVT's default: main direction 315 degrees, anisotropy level low.
    fn default() -> Self {
        Anisotropy { main_direction_deg: 315.0, polynomial: 4, min_weight: 0.4 }
    }
}

impl Anisotropy {
    /// The weight of the direction `azimuth_deg`.
    pub fn weight(&self, azimuth_deg: f64) -> f64 {
        let half = (azimuth_deg - self.main_direction_deg).to_radians() / 2.0;
        (1.0 - self.min_weight) * half.cos().powi(self.polynomial) + self.min_weight
    }
}

/// The sky's light over the hemisphere, for the sky-illumination layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SkyModel {
    /// Every direction of the sky equally bright.
    Uniform,
    /// The standard overcast sky (Moon and Spencer 1942, CIE): the luminance at elevation `h`
    /// is proportional to `(1 + 2 sin h) / 3`, three times brighter at the zenith than at the
    /// horizon.
    Overcast,
}

impl std::str::FromStr for SkyModel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "uniform" => Ok(SkyModel::Uniform),
            "overcast" => Ok(SkyModel::Overcast),
            _ => Err(format!("unknown sky model '{s}' (expected overcast or uniform)")),
        }
    }
}

/// The sky-view factor of a sample with horizon angles `angles` (radians) in evenly spaced
/// directions: `1 - mean(sin(max(h, 0)))`, the share of the sky's hemisphere it sees (1 on an
/// open plain, 0 at the bottom of a shaft).
pub fn sky_view_factor(angles: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for h in angles {
        sum += sin_of_elevation(h.max(0.0));
        n += 1;
    }
    1.0 - sum / n.max(1) as f64
}

/// The sine of an elevation angle `h` from 0 to pi/2 (radians), to four f64 epsilons: its
/// Taylor series to the 21st power, in Horner's form, inlined: the library's `sin`, a call that
/// first reduces any argument, took 7 % of a sky-view factor's time (docs/horizons.md).
#[inline]
fn sin_of_elevation(h: f64) -> f64 {
    // 1 / (2k + 1)! with alternating signs, from the 21st power down to the 3rd.
    const C: [f64; 10] = [
        1.0 / 51_090_942_171_709_440_000.0,
        -1.0 / 121_645_100_408_832_000.0,
        1.0 / 355_687_428_096_000.0,
        -1.0 / 1_307_674_368_000.0,
        1.0 / 6_227_020_800.0,
        -1.0 / 39_916_800.0,
        1.0 / 362_880.0,
        -1.0 / 5_040.0,
        1.0 / 120.0,
        -1.0 / 6.0,
    ];
    let x2 = h * h;
    let p = C.iter().fold(0.0, |p, &c| p * x2 + c);
    h + h * x2 * p
}

/// The anisotropic sky-view factor: `1 - sum(w sin(max(h, 0))) / sum(w)` over the directions
/// `azimuths_deg` with weights [`Anisotropy::weight`].
pub fn anisotropic_sky_view_factor(
    angles: impl Iterator<Item = f64>,
    azimuths_deg: &[f64],
    anisotropy: &Anisotropy,
) -> f64 {
    let (mut sum, mut weights) = (0.0, 0.0);
    for (h, &azimuth) in angles.zip(azimuths_deg) {
        let w = anisotropy.weight(azimuth);
        sum += w * sin_of_elevation(h.max(0.0));
        weights += w;
    }
    1.0 - sum / weights
}

/// Openness in degrees (Yokoyama et al. 2002): `90 - mean(h)` of the horizon angles in
/// degrees, not clamped (above 90 on a summit). Given the horizons of the terrain upside down,
/// it is the negative openness.
pub fn openness_deg(angles: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for h in angles {
        sum += h;
        n += 1;
    }
    90.0 - (sum / n.max(1) as f64).to_degrees()
}

/// The diffuse light of the sky `model` on a surface of unit upward `normal`, seen above the
/// horizon angles `angles` (radians) in the directions `azimuths_deg`, divided by what an open,
/// flat plane gets (so 1 there): per direction, the sector of the sky between the horizon (or
/// the horizontal, or the surface's own plane, whichever is highest) and the zenith, its
/// luminance weighted by the cosine of incidence, integrated over elevation in closed form.
pub fn sky_illumination(
    angles: impl Iterator<Item = f64>,
    azimuths_deg: &[f64],
    normal: DVec3,
    model: SkyModel,
) -> f64 {
    let sector = 2.0 * PI / azimuths_deg.len().max(1) as f64;
    let mut total = 0.0;
    for (h, &azimuth) in angles.zip(azimuths_deg) {
        let (sin_az, cos_az) = azimuth.to_radians().sin_cos();
        // n . direction(h) = a cos h + b sin h.
        let a = normal.x * sin_az + normal.y * cos_az;
        let b = normal.z;
        // Below the surface's own plane the cosine is negative: start above it.
        let own_plane = if a < 0.0 { (-a).atan2(b) } else { 0.0 };
        let low = h.max(0.0).max(own_plane).min(FRAC_PI_2);
        total += sector
            * match model {
                SkyModel::Uniform => {
                    uniform_integral(a, b, FRAC_PI_2) - uniform_integral(a, b, low)
                }
                SkyModel::Overcast => {
                    overcast_integral(a, b, FRAC_PI_2) - overcast_integral(a, b, low)
                }
            };
    }
    match model {
        // An open plane: 2π ∫ sin h cos h dh = π.
        SkyModel::Uniform => total / PI,
        // 2π ∫ (1 + 2 sin h) / 3 sin h cos h dh = 7π / 9.
        SkyModel::Overcast => total / (7.0 * PI / 9.0),
    }
}

/// An antiderivative in `h` of `(a cos h + b sin h) cos h`.
fn uniform_integral(a: f64, b: f64, h: f64) -> f64 {
    let (sin, cos) = h.sin_cos();
    a * (h / 2.0 + sin * cos / 2.0) + b * sin * sin / 2.0
}

/// An antiderivative in `h` of `(1 + 2 sin h) / 3 (a cos h + b sin h) cos h`.
fn overcast_integral(a: f64, b: f64, h: f64) -> f64 {
    let (sin, cos) = h.sin_cos();
    (uniform_integral(a, b, h) - 2.0 * a * cos.powi(3) / 3.0 + 2.0 * b * sin.powi(3) / 3.0) / 3.0
}

/// The hillshade of `gdaldem hillshade -multidirectional`: Lambert's cosine of the surface
/// under four suns 45 degrees up, from azimuths 225, 270, 315 and 360, each weighted by
/// `cos^2(aspect - azimuth)` with the aspect the compass direction the slope faces (the
/// weights sum to 2; what gdaldem computes, checked on planes of four aspects by
/// bench/gis/gdaldem_weights.py; after Mark 1992, USGS Open-File Report 92-422). A flat
/// sample gets `sin 45`.
pub fn multidirectional_hillshade(normal: DVec3) -> f64 {
    let sun = |azimuth: f64| crate::sun_direction(azimuth, 45.0);
    let horizontal = normal.x.hypot(normal.y);
    if horizontal == 0.0 {
        return sun(0.0).z * normal.z;
    }
    // The aspect: the compass direction the slope faces, clockwise from north.
    let aspect = normal.x.atan2(normal.y);
    let mut sum = 0.0;
    for azimuth in [225.0f64, 270.0, 315.0, 360.0] {
        let weight = (aspect - azimuth.to_radians()).cos().powi(2);
        sum += weight * normal.dot(sun(azimuth)).max(0.0);
    }
    sum / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn directions(n: usize) -> Vec<f64> {
        (0..n).map(|k| k as f64 * 360.0 / n as f64).collect()
    }

    #[test]
    fn the_elevation_sine_is_the_library_s() {
        for i in 0..=100_000 {
            let h = FRAC_PI_2 * i as f64 / 100_000.0;
            let (got, want) = (super::sin_of_elevation(h), h.sin());
            assert!((got - want).abs() <= 4.0 * f64::EPSILON * want, "sin({h}): {got}, not {want}");
        }
    }

    #[test]
    fn an_open_plane_sees_the_whole_sky() {
        let flat = [-0.001; 16];
        assert_eq!(sky_view_factor(flat.iter().copied()), 1.0);
        assert!((openness_deg(flat.iter().copied()) - 90.057).abs() < 1e-3);
        for model in [SkyModel::Uniform, SkyModel::Overcast] {
            let e = sky_illumination(flat.iter().copied(), &directions(16), DVec3::Z, model);
            assert!((e - 1.0).abs() < 1e-12, "{model:?}: {e}");
        }
        let aniso = anisotropic_sky_view_factor(
            flat.iter().copied(),
            &directions(16),
            &Anisotropy::default(),
        );
        assert_eq!(aniso, 1.0);
    }

    #[test]
    fn a_pit_sees_the_sky_above_its_rim() {
        // A horizon at γ all round: SVF 1 - sin γ; a uniform sky lights the floor by cos² γ;
        // an overcast sky by ((1 - sin² γ) / 2 + 2 (1 - sin³ γ) / 3) / (7 / 6).
        let gamma: f64 = 0.6;
        let pit = [gamma; 32];
        assert!((sky_view_factor(pit.iter().copied()) - (1.0 - gamma.sin())).abs() < 1e-12);
        assert!((openness_deg(pit.iter().copied()) - (90.0 - gamma.to_degrees())).abs() < 1e-9);
        let uniform =
            sky_illumination(pit.iter().copied(), &directions(32), DVec3::Z, SkyModel::Uniform);
        assert!((uniform - gamma.cos().powi(2)).abs() < 1e-12, "{uniform}");
        let overcast =
            sky_illumination(pit.iter().copied(), &directions(32), DVec3::Z, SkyModel::Overcast);
        let s = gamma.sin();
        let want = ((1.0 - s * s) / 2.0 + 2.0 * (1.0 - s.powi(3)) / 3.0) / (7.0 / 6.0);
        assert!((overcast - want).abs() < 1e-12, "{overcast} {want}");
    }

    #[test]
    fn an_infinite_slope_against_a_sum_over_the_sky() {
        // A plane tilted by β, facing east: its horizon towards φ is its own profile,
        // atan(-tan β sin φ), rising to β in the west. The light of either sky equals a plain
        // sum over a fine grid of the upper hemisphere of luminance times cosine of incidence.
        let beta: f64 = 0.5;
        let normal = DVec3::new(beta.sin(), 0.0, beta.cos());
        let horizon = |azimuth: f64| (-(beta.tan()) * azimuth.sin()).atan();
        let azimuths = directions(720);
        let angles: Vec<f64> = azimuths.iter().map(|&a| horizon(a.to_radians())).collect();
        for (model, luminance, open) in [
            (SkyModel::Uniform, (|_h: f64| 1.0) as fn(f64) -> f64, PI),
            (SkyModel::Overcast, |h: f64| (1.0 + 2.0 * h.sin()) / 3.0, 7.0 * PI / 9.0),
        ] {
            let got = sky_illumination(angles.iter().copied(), &azimuths, normal, model);
            let (steps_az, steps_h) = (720, 2000);
            let mut sum = 0.0;
            for i in 0..steps_az {
                let phi = (i as f64 + 0.5) * 2.0 * PI / steps_az as f64;
                for j in 0..steps_h {
                    let h = (j as f64 + 0.5) * FRAC_PI_2 / steps_h as f64;
                    if h < horizon(phi) {
                        continue;
                    }
                    let w = DVec3::new(h.cos() * phi.sin(), h.cos() * phi.cos(), h.sin());
                    sum += luminance(h) * normal.dot(w).max(0.0) * h.cos();
                }
            }
            let want = sum * (2.0 * PI / steps_az as f64) * (FRAC_PI_2 / steps_h as f64) / open;
            assert!((got - want).abs() < 2e-3, "{model:?}: {got} against {want}");
        }
        // Its openness is 90 degrees: the horizon rises as much one way as it falls the other.
        assert!((openness_deg(angles.iter().copied()) - 90.0).abs() < 1e-9);
    }

    #[test]
    fn anisotropy_weighs_the_main_direction() {
        let a = Anisotropy::default();
        assert!((a.weight(315.0) - 1.0).abs() < 1e-12);
        assert!((a.weight(135.0) - 0.4).abs() < 1e-12);
        // Sky closed towards the main direction only: less open than the isotropic factor.
        let azimuths = directions(8);
        let angles: Vec<f64> =
            azimuths.iter().map(|&az| if az == 315.0 { 1.0 } else { 0.0 }).collect();
        let iso = sky_view_factor(angles.iter().copied());
        let aniso = anisotropic_sky_view_factor(angles.iter().copied(), &azimuths, &a);
        assert!(aniso < iso, "{aniso} {iso}");
    }

    #[test]
    fn multidirectional_hillshade_of_flat_and_sloped_ground() {
        assert!((multidirectional_hillshade(DVec3::Z) - 45f64.to_radians().sin()).abs() < 1e-12);
        // A slope facing north-west is lit by the suns in the west and north.
        let north_west = DVec3::new(-0.3, 0.3, 1.0).normalize();
        let south_east = DVec3::new(0.3, -0.3, 1.0).normalize();
        assert!(multidirectional_hillshade(north_west) > multidirectional_hillshade(south_east));
    }
}
