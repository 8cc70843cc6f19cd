//! Image-based lighting from the procedural sky: the sky's radiance along a direction and the
//! irradiance it casts on a surface, precomputed once per rendering.

use crate::Sky;
use relief_core::DVec3;
use std::f64::consts::PI;

/// The sky of the MLHM reference renderer, `(0.3, 0.65, 0.98)` overhead, paler towards the
/// horizon.
pub fn reference_sky() -> Sky {
    Sky { zenith: [0.3, 0.65, 0.98], horizon: [0.5, 0.72, 0.95], ambient: [0.0; 3] }
}

/// Radiance of the ground below the horizon as a light: the terrain's own shade, dim.
pub const GROUND_RADIANCE: [f64; 3] = [0.08, 0.075, 0.07];

/// Entries of the irradiance table over `n.z` in `[-1, 1]`.
const TABLE_SIZE: usize = 65;

/// The sky as a light: its radiance and the irradiance it casts on a surface of any normal.
///
/// Light comes from the sky above the horizon and from the ground, [`GROUND_RADIANCE`], below
/// it. Both only depend on a direction's height (`z`), so the irradiance
/// `E(n) = ∫ L(ω) max(n.ω, 0) dω` only depends on `n.z`: it is integrated numerically once into
/// a table and interpolated linearly.
#[derive(Debug, Clone, PartialEq)]
pub struct SkyLight {
    sky: Sky,
    irradiance: Vec<DVec3>,
}

impl SkyLight {
    /// Precomputes the irradiance of `sky` (midpoint quadrature over the sphere), scaled by
    /// `strength`: how brightly the sky lights the terrain relative to how bright it looks.
    pub fn new(sky: Sky, strength: f64) -> Self {
        let (rings, sectors) = (96, 96);
        let mut samples = Vec::with_capacity(rings * sectors);
        for a in 0..rings {
            let theta = (a as f64 + 0.5) / rings as f64 * PI;
            let solid_angle = theta.sin() * (PI / rings as f64) * (2.0 * PI / sectors as f64);
            for b in 0..sectors {
                let phi = (b as f64 + 0.5) / sectors as f64 * 2.0 * PI;
                let dir = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                let radiance =
                    if dir.z > 0.0 { sky.radiance(dir) } else { DVec3::from(GROUND_RADIANCE) };
                samples.push((dir, radiance * solid_angle * strength));
            }
        }
        let irradiance = (0..TABLE_SIZE)
            .map(|k| {
                let nz = -1.0 + 2.0 * k as f64 / (TABLE_SIZE - 1) as f64;
                let normal = DVec3::new((1.0 - nz * nz).max(0.0).sqrt(), 0.0, nz);
                samples.iter().map(|&(dir, l)| l * normal.dot(dir).max(0.0)).sum()
            })
            .collect();
        SkyLight { sky, irradiance }
    }

    /// Radiance of the sky seen along unit `dir`.
    pub fn radiance(&self, dir: DVec3) -> DVec3 {
        self.sky.radiance(dir)
    }

    /// Irradiance from the sky on a surface of unit `normal` (nothing occluding it).
    pub fn irradiance(&self, normal: DVec3) -> DVec3 {
        let x = (normal.z.clamp(-1.0, 1.0) + 1.0) * 0.5 * (TABLE_SIZE - 1) as f64;
        let k = (x.floor() as usize).min(TABLE_SIZE - 2);
        self.irradiance[k].lerp(self.irradiance[k + 1], x - k as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uniform_sky_gives_pi_l_upwards_and_half_of_sky_and_ground_sideways() {
        let uniform = Sky { zenith: [1.0; 3], horizon: [1.0; 3], ambient: [0.0; 3] };
        let light = SkyLight::new(uniform, 1.0);
        let ground = DVec3::from(GROUND_RADIANCE);
        let close = |a: DVec3, b: DVec3| (a - b).abs().max_element() < 2e-3;
        assert!(close(light.irradiance(DVec3::Z), DVec3::splat(PI)));
        assert!(close(light.irradiance(DVec3::X), (DVec3::ONE + ground) * PI / 2.0));
        assert!(close(light.irradiance(-DVec3::Z), ground * PI));
        let sky = SkyLight::new(reference_sky(), 1.0);
        let dim = SkyLight::new(reference_sky(), 0.5);
        assert!((dim.irradiance(DVec3::Z) * 2.0 - sky.irradiance(DVec3::Z)).length() < 1e-12);
        assert_eq!(dim.radiance(DVec3::Z), sky.radiance(DVec3::Z));
        let (up, side) = (sky.irradiance(DVec3::Z), sky.irradiance(DVec3::X));
        assert!(up.z > up.x, "blue from above: {up}");
        assert!(side.x / side.z > up.x / up.z, "paler from the horizon: {side} vs {up}");
    }
}
