//! What to precompute: the variants of Baboud et al.'s safety shapes (sections 6 and 7).

use std::fmt;
use std::str::FromStr;

/// Which rays a shape must be safe for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RaySet {
    /// Every ray that starts above the surface (section 6.1): any camera.
    All,
    /// Exterior rays only (section 6.2): rays that come from outside the terrain's bounding box
    /// (cameras outside it, shadow rays traced from the light). Larger shapes, exact
    /// visibility in dual space at precomputation.
    Exterior,
}

/// The slanted (cone) part of the cylinder-cone shape (section 6.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ConeMode {
    /// Cylinders (safety distances) only.
    None,
    /// The conservative approximation: every vertex past the radius counts, found with
    /// N-buffers (the paper's `cone_all`).
    NBuffer,
    /// Exact: only the limiting triangles of the cylinder's ray set count (`cone_ext` for
    /// exterior rays, `cone_exact` for all rays).
    Exact,
}

/// Whether each ray class keeps its own shape or all share the smallest (section 8, Fig. 28).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShapeLayout {
    /// One shape per texel and ray class.
    Directional,
    /// One shape per texel, safe for all four classes.
    Isotropic,
}

/// The options a set of safety shapes is built with; part of its cache key.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafetyOptions {
    /// The rays the cylinders (and an exact cone) must be safe for.
    pub rays: RaySet,
    /// The cone part.
    pub cone: ConeMode,
    /// The viewing-angle bound (section 6.2.5), in degrees: only rays whose slope angle is at
    /// most this (e.g. -45: looking down at least 45 degrees) are admitted.
    pub phi_max_deg: Option<f64>,
    /// Directional or isotropic shapes.
    pub layout: ShapeLayout,
    /// Clamp distances to at least one (section 7): faster, approximate at sharp silhouettes.
    pub strictly_positive: bool,
    /// The farthest step, in texels, a shape may allow; the precomputation looks this far.
    pub reach: u16,
}

impl Default for SafetyOptions {
    fn default() -> Self {
        SafetyOptions {
            rays: RaySet::All,
            cone: ConeMode::NBuffer,
            phi_max_deg: None,
            layout: ShapeLayout::Directional,
            strictly_positive: false,
            reach: 128,
        }
    }
}

impl SafetyOptions {
    /// Whether rendering with these shapes is exact for every admitted ray.
    pub fn is_exact(&self) -> bool {
        !self.strictly_positive
    }

    /// The variant's name in the paper's notation, e.g. `cyl_ext+cone_all`.
    pub fn variant(&self) -> String {
        let cyl = match self.rays {
            RaySet::All => "cyl_all",
            RaySet::Exterior => "cyl_ext",
        };
        let cone = match (self.cone, self.rays) {
            (ConeMode::None, _) => "",
            (ConeMode::NBuffer, _) => "+cone_all",
            (ConeMode::Exact, RaySet::Exterior) => "+cone_ext",
            (ConeMode::Exact, RaySet::All) => "+cone_exact",
        };
        format!("{cyl}{cone}")
    }

    /// Checks the options make sense.
    pub fn validate(&self) -> Result<(), String> {
        if let Some(phi) = self.phi_max_deg {
            if !(phi.is_finite() && phi > -90.0 && phi < 90.0) {
                return Err(format!("phi max {phi} must be strictly between -90 and 90 degrees"));
            }
        }
        if self.reach == 0 {
            return Err("the reach of safety shapes must be at least 1".into());
        }
        Ok(())
    }

    /// The tangent of `phi_max` (the largest admitted slope `dz / horizontal length`).
    pub fn max_slope(&self) -> Option<f64> {
        self.phi_max_deg.map(|phi| phi.to_radians().tan())
    }
}

impl fmt::Display for SafetyOptions {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.variant())?;
        if let Some(phi) = self.phi_max_deg {
            write!(f, " phi_max={phi}")?;
        }
        if self.layout == ShapeLayout::Isotropic {
            f.write_str(" isotropic")?;
        }
        if self.strictly_positive {
            f.write_str(" positive")?;
        }
        write!(f, " reach={}", self.reach)
    }
}

/// Parses a variant name (`cyl_all`, `cyl_ext`, optionally followed by `+cone_all`,
/// `+cone_ext` or `+cone_exact`) into the ray set and cone mode.
impl FromStr for SafetyOptions {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let mut parts = s.split('+');
        let rays = match parts.next().unwrap_or("") {
            "cyl_all" => RaySet::All,
            "cyl_ext" => RaySet::Exterior,
            other => {
                return Err(format!(
                    "unknown safety shape '{other}' (expected cyl_all or cyl_ext, optionally \
                     followed by +cone_all, +cone_ext or +cone_exact)"
                ))
            }
        };
        let cone = match parts.next() {
            None => ConeMode::None,
            Some("cone_all") => ConeMode::NBuffer,
            Some("cone_ext") if rays == RaySet::Exterior => ConeMode::Exact,
            Some("cone_exact") if rays == RaySet::All => ConeMode::Exact,
            Some("cone_ext") => return Err("cone_ext needs cyl_ext (exterior rays)".into()),
            Some("cone_exact") => return Err("cone_exact goes with cyl_all; use cone_ext".into()),
            Some(other) => {
                return Err(format!(
                    "unknown cone '{other}' (expected cone_all, cone_ext or cone_exact)"
                ))
            }
        };
        if let Some(extra) = parts.next() {
            return Err(format!("unexpected '+{extra}' in safety shape '{s}'"));
        }
        Ok(SafetyOptions { rays, cone, ..SafetyOptions::default() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variant_names_round_trip() {
        for name in [
            "cyl_all",
            "cyl_ext",
            "cyl_all+cone_all",
            "cyl_ext+cone_all",
            "cyl_ext+cone_ext",
            "cyl_all+cone_exact",
        ] {
            let options: SafetyOptions = name.parse().unwrap();
            assert_eq!(options.variant(), name);
        }
        assert!("cyl_all+cone_ext".parse::<SafetyOptions>().is_err());
        assert!("cone_all".parse::<SafetyOptions>().is_err());
        assert!("cyl_all+cone_all+x".parse::<SafetyOptions>().is_err());
    }
}
