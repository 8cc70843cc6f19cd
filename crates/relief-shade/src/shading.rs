//! The terrain's reflectance: a Lambertian diffuse term plus an optional GGX specular lobe
//! (one lobe for every renderer, with the masking term of the height-field shading or that of
//! the MLHM reference renderer), and the light they reflect from the sun and from the sky.

use std::f64::consts::{FRAC_1_PI, PI};

use relief_core::DVec3;

use crate::ShadeError;

/// Reflectance at normal incidence of common dielectrics (rock, soil, vegetation, water).
pub const DIELECTRIC_F0: f64 = 0.04;

/// A GGX (Trowbridge-Reitz) microfacet specular lobe with Schlick's Fresnel approximation.
///
/// Two masking-shadowing terms: the height-correlated Smith term ([`GgxSpecular::brdf`], the
/// deferred shading of height fields) and the separable Smith-Schlick term with
/// `k = (roughness + 1)² / 8` of the MLHM reference renderer (Nilles & Müller 2025, section
/// 4.6; [`GgxSpecular::brdf_smith_schlick`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GgxSpecular {
    /// Perceptual roughness in `[0, 1]`; the GGX `alpha` is its square.
    pub roughness: f64,
    /// Reflectance at normal incidence, in `[0, 1]`.
    pub f0: f64,
}

impl Default for GgxSpecular {
    /// A rough dielectric, as terrain is: roughness 0.7, F0 0.04.
    fn default() -> Self {
        GgxSpecular { roughness: 0.7, f0: DIELECTRIC_F0 }
    }
}

/// Smallest GGX alpha used, so that a roughness of 0 stays finite.
const MIN_ALPHA: f64 = 1e-3;

/// Smallest cosine of the view angle used, so that grazing views stay finite.
const MIN_COS_VIEW: f64 = 1e-4;

impl GgxSpecular {
    /// Checks that roughness and F0 are within `[0, 1]`.
    pub fn validate(&self) -> Result<(), ShadeError> {
        for (name, v) in [("GGX roughness", self.roughness), ("GGX F0", self.f0)] {
            if !(0.0..=1.0).contains(&v) {
                return Err(ShadeError::parameter(name, format!("{v} is not between 0 and 1")));
            }
        }
        Ok(())
    }

    /// The BRDF value `D G F / (4 (n.l) (n.v))` for unit `normal`, unit direction `to_eye`
    /// and unit direction `to_light`; 0 when the light is behind the surface.
    pub fn brdf(&self, normal: DVec3, to_eye: DVec3, to_light: DVec3) -> f64 {
        let n_l = normal.dot(to_light);
        if n_l <= 0.0 {
            return 0.0;
        }
        let n_v_signed = normal.dot(to_eye);
        let n_v = n_v_signed.max(MIN_COS_VIEW);
        // The half vector h = (v + l) / |v + l| is never formed: |v + l|^2 = 2 + 2 v.l, so
        // (n.h)^2 = (n.v + n.l)^2 / |v + l|^2 and v.h = |v + l| / 2. Eye and light opposite
        // (|v + l| = 0) leave no half vector: n.h = v.h = 0, as a zero half vector gives.
        let v_l = to_eye.dot(to_light);
        let sum_squared = 2.0 + 2.0 * v_l;
        let (n_h2, v_h) = if sum_squared > 0.0 {
            let n_h = (n_v_signed + n_l).max(0.0);
            (n_h * n_h / sum_squared, (0.5 * sum_squared.sqrt()).clamp(0.0, 1.0))
        } else {
            (0.0, 0.0)
        };
        let alpha = (self.roughness * self.roughness).max(MIN_ALPHA);
        let a2 = alpha * alpha;
        let d_denom = n_h2 * (a2 - 1.0) + 1.0;
        // D = a2 / (π d_denom^2) and V = 1 / (2 (n.l Λv + n.v Λl)), in one division.
        let smith =
            n_l * (n_v * n_v * (1.0 - a2) + a2).sqrt() + n_v * (n_l * n_l * (1.0 - a2) + a2).sqrt();
        let fresnel = schlick(v_h, self.f0);
        a2 * fresnel / (2.0 * PI * d_denom * d_denom * smith)
    }

    /// The BRDF value `D G F / (4 (n.l) (n.v))` with the separable Smith-Schlick masking
    /// `G = G1(n.l) G1(n.v)`, `G1(c) = c / (c (1 - k) + k)`, `k = (roughness + 1)² / 8`, as
    /// the MLHM reference renderer has it, for unit `normal`, `to_eye` and `to_light`; 0 when
    /// either direction is below the surface.
    pub fn brdf_smith_schlick(&self, normal: DVec3, to_eye: DVec3, to_light: DVec3) -> f64 {
        let n_l = normal.dot(to_light);
        let n_v = normal.dot(to_eye);
        if n_l <= 0.0 || n_v <= 0.0 {
            return 0.0;
        }
        let (n_l, n_v) = (n_l.max(MIN_COS_VIEW), n_v.max(MIN_COS_VIEW));
        let half = (to_eye + to_light).normalize_or_zero();
        let n_h = normal.dot(half).max(0.0);
        let alpha = (self.roughness * self.roughness).max(MIN_ALPHA);
        let a2 = alpha * alpha;
        let denom = n_h * n_h * (a2 - 1.0) + 1.0;
        let distribution = a2 / (PI * denom * denom);
        let k = (self.roughness + 1.0).powi(2) / 8.0;
        let g1 = |c: f64| c / (c * (1.0 - k) + k);
        let fresnel = schlick(to_eye.dot(half).clamp(0.0, 1.0), self.f0);
        distribution * g1(n_l) * g1(n_v) * fresnel / (4.0 * n_l * n_v)
    }
}

/// Schlick's approximation of Fresnel reflectance, `F0 + (1 - F0) (1 - cos)^5`, with `cos`
/// clamped to `[0, 1]`.
pub fn schlick(cos: f64, f0: f64) -> f64 {
    f0 + (1.0 - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

/// Radiance reflected towards the eye from a distant light of irradiance `irradiance` in the
/// direction `to_light` (unit), seen through `visibility` in `[0, 1]`:
///
/// `(albedo / π + f_ggx) · E · max(n.l, 0) · visibility`, the GGX term only when `specular`
/// is given. `normal` and `to_eye` are unit vectors.
pub fn direct_lighting(
    albedo: DVec3,
    normal: DVec3,
    to_eye: DVec3,
    to_light: DVec3,
    irradiance: f64,
    visibility: f64,
    specular: Option<&GgxSpecular>,
) -> DVec3 {
    let n_l = normal.dot(to_light);
    if n_l <= 0.0 || visibility <= 0.0 {
        return DVec3::ZERO;
    }
    let specular = specular.map_or(0.0, |s| s.brdf(normal, to_eye, to_light));
    (albedo * FRAC_1_PI + DVec3::splat(specular)) * (irradiance * n_l * visibility)
}

/// Radiance a Lambertian surface reflects from a uniform sky of radiance `sky` over the upper
/// hemisphere: `albedo · sky · (1 + n.z) / 2` (the ground below the horizon reflects nothing).
pub fn ambient_lighting(albedo: DVec3, normal: DVec3, sky: DVec3) -> DVec3 {
    albedo * sky * (0.5 + 0.5 * normal.z.clamp(-1.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambertian_plane_reflects_rho_e_cos_over_pi() {
        let rho = DVec3::new(0.2, 0.5, 0.8);
        let n = DVec3::new(0.3, -0.4, 1.0).normalize();
        let e = 3.0;
        for theta_deg in [0.0, 10.0, 30.0, 45.0, 60.0, 85.0] {
            let theta: f64 = f64::to_radians(theta_deg);
            // A light direction at angle theta from the (tilted) normal.
            let tangent = n.any_orthonormal_vector();
            let l = n * theta.cos() + tangent * theta.sin();
            let got = direct_lighting(rho, n, n, l, e, 1.0, None);
            let want = rho * e * theta.cos() / PI;
            assert!(((got - want) / want).abs().max_element() < 1e-12, "θ={theta_deg}: {got}");
        }
        let behind = direct_lighting(rho, n, n, -n, e, 1.0, None);
        assert_eq!(behind, DVec3::ZERO);
        assert_eq!(direct_lighting(rho, n, n, n, e, 0.0, None), DVec3::ZERO);
    }

    #[test]
    fn ggx_matches_its_closed_form_at_normal_incidence_and_is_reciprocal() {
        let s = GgxSpecular::default();
        let a2 = s.roughness.powi(4);
        let at_normal = s.brdf(DVec3::Z, DVec3::Z, DVec3::Z);
        assert!((at_normal - s.f0 / (4.0 * PI * a2)).abs() < 1e-12 * at_normal);
        let (v, l) =
            (DVec3::new(0.5, 0.1, 0.8).normalize(), DVec3::new(-0.2, 0.7, 0.4).normalize());
        assert!((s.brdf(DVec3::Z, v, l) - s.brdf(DVec3::Z, l, v)).abs() < 1e-12);
        assert_eq!(s.brdf(DVec3::Z, v, -DVec3::Z), 0.0);
    }

    /// The textbook form, with the half vector formed and two divisions.
    fn brdf_with_half_vector(s: &GgxSpecular, n: DVec3, v: DVec3, l: DVec3) -> f64 {
        let n_l = n.dot(l);
        if n_l <= 0.0 {
            return 0.0;
        }
        let n_v = n.dot(v).max(MIN_COS_VIEW);
        let half = (v + l).normalize_or_zero();
        let (n_h, v_h) = (n.dot(half).max(0.0), v.dot(half).clamp(0.0, 1.0));
        let a2 = (s.roughness * s.roughness).max(MIN_ALPHA).powi(2);
        let d = n_h * n_h * (a2 - 1.0) + 1.0;
        let distribution = a2 / (PI * d * d);
        let visibility = 0.5
            / (n_l * (n_v * n_v * (1.0 - a2) + a2).sqrt()
                + n_v * (n_l * n_l * (1.0 - a2) + a2).sqrt());
        distribution * visibility * (s.f0 + (1.0 - s.f0) * (1.0 - v_h).powi(5))
    }

    #[test]
    fn ggx_without_the_half_vector_is_the_textbook_form() {
        let unit = |k: u32| {
            let a = k as f64 * 2.399_963;
            let z = 1.0 - 2.0 * ((k as f64 * 0.618_034) % 1.0);
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * a.cos(), r * a.sin(), z)
        };
        for roughness in [0.0, 0.2, 0.7, 1.0] {
            let s = GgxSpecular { roughness, f0: 0.04 };
            for k in 0..3000 {
                let (n, v, l) = (unit(k), unit(7 * k + 1), unit(13 * k + 5));
                let (got, want) = (s.brdf(n, v, l), brdf_with_half_vector(&s, n, v, l));
                // Near the peak of a mirror-like lobe the two roundings part by a few 1e-12.
                assert!((got - want).abs() <= 1e-9 * want.abs(), "{n} {v} {l}: {got} {want}");
            }
            // Eye and light opposite: no half vector, as a zero one gives.
            let (n, v) = (DVec3::new(0.3, 0.1, -0.9).normalize(), DVec3::new(0.6, -0.2, 0.7));
            let (v, l) = (v.normalize(), -v.normalize());
            let (got, want) = (s.brdf(n, v, l), brdf_with_half_vector(&s, n, v, l));
            assert!(want > 0.0 && (got - want).abs() <= 1e-12 * want, "{got} {want}");
        }
    }

    /// A BRDF of the lobe: normal, to the eye, to the light.
    type Brdf = fn(&GgxSpecular, DVec3, DVec3, DVec3) -> f64;

    /// Both masking terms of the lobe, by name.
    fn both_terms() -> [(&'static str, Brdf); 2] {
        [
            ("height-correlated", GgxSpecular::brdf),
            ("Smith-Schlick", GgxSpecular::brdf_smith_schlick),
        ]
    }

    #[test]
    fn both_masking_terms_are_reciprocal_and_dark_below_the_surface() {
        for (name, brdf) in both_terms() {
            for roughness in [0.05, 0.5, 0.7, 1.0] {
                let s = GgxSpecular { roughness, f0: 1.0 };
                let (v, l) =
                    (DVec3::new(0.5, 0.1, 0.8).normalize(), DVec3::new(-0.2, 0.7, 0.4).normalize());
                let (a, b) = (brdf(&s, DVec3::Z, v, l), brdf(&s, DVec3::Z, l, v));
                assert!((a - b).abs() <= 1e-12 * a.max(1.0), "{name} {roughness}: {a} {b}");
                assert_eq!(brdf(&s, DVec3::Z, v, -DVec3::Z), 0.0, "{name}");
            }
        }
        // The reference's masking is also dark seen from below.
        let s = GgxSpecular::default();
        assert_eq!(s.brdf_smith_schlick(DVec3::Z, -DVec3::Z, DVec3::Z), 0.0);
        assert!((schlick(1.0, 0.02) - 0.02).abs() < 1e-15 && schlick(-3.0, 0.02) == 1.0);
    }

    /// Directional albedo `∫ f cos dω` of `brdf` seen from `view_deg` off the normal, by
    /// midpoint quadrature.
    fn directional_albedo(brdf: Brdf, s: &GgxSpecular, view_deg: f64, steps: usize) -> f64 {
        let v = DVec3::new(view_deg.to_radians().sin(), 0.0, view_deg.to_radians().cos());
        let mut sum = 0.0;
        for a in 0..steps {
            let th = (a as f64 + 0.5) / steps as f64 * PI / 2.0;
            for b in 0..steps {
                let ph = (b as f64 + 0.5) / steps as f64 * 2.0 * PI;
                let l = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
                sum += brdf(s, DVec3::Z, v, l) * th.cos() * th.sin();
            }
        }
        sum * (PI / 2.0 / steps as f64) * (2.0 * PI / steps as f64)
    }

    #[test]
    fn ggx_reflects_less_than_it_receives() {
        for roughness in [0.3, 0.7, 1.0] {
            let s = GgxSpecular { roughness, f0: 1.0 };
            for view_deg in [0.0_f64, 45.0, 80.0] {
                let albedo = directional_albedo(GgxSpecular::brdf, &s, view_deg, 400);
                assert!(
                    albedo > 0.3 && albedo <= 1.01,
                    "roughness {roughness}, view {view_deg}: {albedo}"
                );
            }
        }
        // The reference renderer's rough terrain lobe, seen 30 degrees off the normal.
        let s = GgxSpecular { roughness: 1.0, f0: 1.0 };
        let albedo = directional_albedo(GgxSpecular::brdf_smith_schlick, &s, 30.0, 200);
        assert!(albedo > 0.2 && albedo <= 1.0, "{albedo}");
    }

    #[test]
    fn sky_light_fades_on_overhangs() {
        let rho = DVec3::splat(0.5);
        let sky = DVec3::new(0.1, 0.2, 0.3);
        assert_eq!(ambient_lighting(rho, DVec3::Z, sky), rho * sky);
        assert_eq!(ambient_lighting(rho, DVec3::X, sky), rho * sky * 0.5);
        assert_eq!(ambient_lighting(rho, -DVec3::Z, sky), DVec3::ZERO);
        assert!(GgxSpecular { roughness: 1.5, f0: 0.04 }.validate().is_err());
        assert!(GgxSpecular { roughness: f64::NAN, f0: 0.04 }.validate().is_err());
    }
}
