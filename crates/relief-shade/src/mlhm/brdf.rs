//! The reflectance of the MLHM reference renderer's materials (Nilles & Müller 2025, section
//! 4.6): their roughness and Fresnel reflectance for the one GGX lobe
//! ([`crate::GgxSpecular::brdf_smith_schlick`]), Schlick's Fresnel extended to total internal
//! reflection, and the ideal mirror and refraction directions of a water surface.

use crate::shading::schlick;
use relief_core::DVec3;

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
}
