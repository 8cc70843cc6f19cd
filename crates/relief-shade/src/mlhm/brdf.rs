//! The reflectance model of the MLHM reference renderer (Nilles & Müller 2025, section 4.6):
//! GGX normal distribution, Smith-Schlick geometry with `k = (roughness + 1)² / 8`, Schlick's
//! Fresnel extended to total internal reflection, and the ideal mirror and refraction
//! directions of a water surface.

use relief_core::DVec3;
use std::f64::consts::PI;

/// Index of refraction of water relative to air.
pub const WATER_IOR: f64 = 1.33;
/// Reflectance at normal incidence of terrain seen from air.
pub const TERRAIN_F0: f64 = 0.04;
/// Reflectance at normal incidence of terrain seen from under water.
pub const TERRAIN_UNDER_WATER_F0: f64 = 0.009;
/// Reflectance at normal incidence of the water surface.
pub const WATER_F0: f64 = 0.02;
/// Perceptual roughness of terrain.
pub const TERRAIN_ROUGHNESS: f64 = 1.0;
/// Perceptual roughness of water.
pub const WATER_ROUGHNESS: f64 = 0.05;

/// Smallest cosines used, so that grazing angles stay finite.
const MIN_COS: f64 = 1e-4;

/// A microfacet specular lobe: GGX distribution, Smith-Schlick visibility, Schlick Fresnel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MicrofacetLobe {
    /// Perceptual roughness in `[0, 1]`; the GGX `alpha` is its square.
    pub roughness: f64,
    /// Reflectance at normal incidence.
    pub f0: f64,
}

impl MicrofacetLobe {
    /// The specular BRDF `D G F / (4 (n.l) (n.v))` for unit `normal`, `to_eye` and `to_light`;
    /// 0 when either direction is below the surface.
    pub fn specular(&self, normal: DVec3, to_eye: DVec3, to_light: DVec3) -> f64 {
        let n_l = normal.dot(to_light);
        let n_v = normal.dot(to_eye);
        if n_l <= 0.0 || n_v <= 0.0 {
            return 0.0;
        }
        let (n_l, n_v) = (n_l.max(MIN_COS), n_v.max(MIN_COS));
        let half = (to_eye + to_light).normalize_or_zero();
        let n_h = normal.dot(half).max(0.0);
        let alpha = (self.roughness * self.roughness).max(1e-3);
        let a2 = alpha * alpha;
        let denom = n_h * n_h * (a2 - 1.0) + 1.0;
        let distribution = a2 / (PI * denom * denom);
        let k = (self.roughness + 1.0).powi(2) / 8.0;
        let g1 = |c: f64| c / (c * (1.0 - k) + k);
        let fresnel = schlick(to_eye.dot(half).clamp(0.0, 1.0), self.f0);
        distribution * g1(n_l) * g1(n_v) * fresnel / (4.0 * n_l * n_v)
    }
}

/// Schlick's approximation `F0 + (1 - F0) (1 - cos)^5`.
pub fn schlick(cos: f64, f0: f64) -> f64 {
    f0 + (1.0 - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

/// Fresnel reflectance at a surface between media of refractive index ratio
/// `eta = n_incident / n_transmitted`, for the cosine `cos_incident` of the angle of incidence:
/// Schlick's approximation, evaluated with the transmitted angle when light leaves the denser
/// medium (`eta > 1`), and 1 beyond the critical angle (total internal reflection).
pub fn fresnel(cos_incident: f64, eta: f64, f0: f64) -> f64 {
    let cos_i = cos_incident.clamp(0.0, 1.0);
    if eta <= 1.0 {
        return schlick(cos_i, f0);
    }
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    schlick((1.0 - sin2_t).sqrt(), f0)
}

/// The mirror direction of unit `dir` about unit `normal`.
pub fn reflect(dir: DVec3, normal: DVec3) -> DVec3 {
    dir - 2.0 * dir.dot(normal) * normal
}

/// The direction of unit `dir` refracted through a surface of unit `normal` facing against it,
/// with `eta = n_incident / n_transmitted` (Snell's law); `None` beyond the critical angle.
pub fn refract(dir: DVec3, normal: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = -dir.dot(normal);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    Some((eta * dir + (eta * cos_i - (1.0 - sin2_t).sqrt()) * normal).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_meets_f0_head_on_one_at_grazing_and_reflects_totally_past_the_critical_angle() {
        assert!((fresnel(1.0, 1.0 / WATER_IOR, WATER_F0) - WATER_F0).abs() < 1e-12);
        assert!((fresnel(0.0, 1.0 / WATER_IOR, WATER_F0) - 1.0).abs() < 1e-12);
        // From under water: the critical angle is asin(1 / 1.33) = 48.75 degrees.
        let critical = (1.0 / WATER_IOR).asin();
        let inside = (critical - 0.01).cos();
        let beyond = (critical + 0.01).cos();
        assert!(fresnel(inside, WATER_IOR, WATER_F0) < 1.0);
        assert_eq!(fresnel(beyond, WATER_IOR, WATER_F0), 1.0);
        assert!((fresnel(1.0, WATER_IOR, WATER_F0) - WATER_F0).abs() < 1e-12);
    }

    #[test]
    fn refraction_obeys_snell_and_reverses() {
        let n = DVec3::Z;
        let d = DVec3::new(0.6, 0.0, -0.8);
        let t = refract(d, n, 1.0 / WATER_IOR).unwrap();
        let sin_i = d.x;
        let sin_t = t.x;
        assert!((sin_i - WATER_IOR * sin_t).abs() < 1e-12);
        assert!(t.z < 0.0 && (t.length() - 1.0).abs() < 1e-12);
        // Back out of the water along the reversed ray gives the original direction.
        let back = refract(-t, -n, WATER_IOR).unwrap();
        assert!((back + d).length() < 1e-12);
        assert!(refract(DVec3::new(0.9, 0.0, 0.43589).normalize(), -n, WATER_IOR).is_none());
        assert_eq!(reflect(d, n), DVec3::new(0.6, 0.0, 0.8));
    }

    #[test]
    fn lobe_is_reciprocal_and_energy_bounded() {
        for roughness in [WATER_ROUGHNESS, 0.5, TERRAIN_ROUGHNESS] {
            let lobe = MicrofacetLobe { roughness, f0: 1.0 };
            let (v, l) =
                (DVec3::new(0.5, 0.1, 0.8).normalize(), DVec3::new(-0.2, 0.7, 0.4).normalize());
            let (a, b) = (lobe.specular(DVec3::Z, v, l), lobe.specular(DVec3::Z, l, v));
            assert!((a - b).abs() <= 1e-12 * a.max(1.0));
            assert_eq!(lobe.specular(DVec3::Z, v, -DVec3::Z), 0.0);
        }
        // Directional albedo of the rough lobe by midpoint quadrature stays below one.
        let lobe = MicrofacetLobe { roughness: TERRAIN_ROUGHNESS, f0: 1.0 };
        let v = DVec3::new(0.5, 0.0, 0.75_f64.sqrt());
        let (nt, np) = (200, 200);
        let mut sum = 0.0;
        for a in 0..nt {
            let th = (a as f64 + 0.5) / nt as f64 * PI / 2.0;
            for b in 0..np {
                let ph = (b as f64 + 0.5) / np as f64 * 2.0 * PI;
                let l = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
                sum += lobe.specular(DVec3::Z, v, l) * th.cos() * th.sin();
            }
        }
        let albedo = sum * (PI / 2.0 / nt as f64) * (2.0 * PI / np as f64);
        assert!(albedo > 0.2 && albedo <= 1.0, "{albedo}");
    }
}
