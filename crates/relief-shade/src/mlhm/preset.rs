//! The quality presets of Nilles & Müller (2025), section 5: which secondary rays, shadows,
//! ambient occlusion and water absorption a rendering uses.

use std::fmt;
use std::str::FromStr;

/// How light is absorbed in water (Beer's law), section 4.6.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WaterAbsorption {
    /// Twice the distance the view ray travelled through water, as if all light came from the
    /// camera: `d = 2 t_water`.
    Cheap,
    /// The view ray's distance through water plus the distance from the lit point up to the
    /// water surface, at most twice the former: `d = min(t_water + t_up, 2 t_water)`.
    Expensive,
}

/// Everything a preset decides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlhmQuality {
    /// Water reflects and refracts by secondary rays (one reflection and one refraction per
    /// water surface seen); without them water is shaded as an opaque surface.
    pub water_rays: bool,
    /// How water absorbs light along refracted rays and rays under water.
    pub absorption: WaterAbsorption,
    /// Shadow rays towards the sun from surfaces seen directly.
    pub shadows: bool,
    /// Half-size of the cube of the geometric ambient occlusion in metres, or `None` for no AO.
    pub ao_radius: Option<f64>,
    /// Shadows and AO also on the surfaces seen through reflections and refractions.
    pub secondary_lighting: bool,
    /// Normals of the smooth surface by central instead of forward differences (smooth mode).
    pub central_differences: bool,
}

/// The presets low, mid, high and max of section 5.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MlhmPreset {
    /// Closest to the previous work: no secondary rays, no AO.
    Low,
    /// Cheap water absorption, single reflections and refractions, shadows and AO with a
    /// radius of 1 m.
    #[default]
    Mid,
    /// As mid with expensive water absorption, and shadows and AO for secondary rays too.
    High,
    /// As high with an AO radius of 2 m and central differences for normals.
    Max,
}

impl MlhmPreset {
    /// Every preset, cheapest first.
    pub const ALL: [MlhmPreset; 4] =
        [MlhmPreset::Low, MlhmPreset::Mid, MlhmPreset::High, MlhmPreset::Max];

    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            MlhmPreset::Low => "low",
            MlhmPreset::Mid => "mid",
            MlhmPreset::High => "high",
            MlhmPreset::Max => "max",
        }
    }

    /// What the preset turns on.
    pub fn quality(self) -> MlhmQuality {
        let low = MlhmQuality {
            water_rays: false,
            absorption: WaterAbsorption::Cheap,
            shadows: false,
            ao_radius: None,
            secondary_lighting: false,
            central_differences: false,
        };
        let mid = MlhmQuality { water_rays: true, shadows: true, ao_radius: Some(1.0), ..low };
        let high =
            MlhmQuality { absorption: WaterAbsorption::Expensive, secondary_lighting: true, ..mid };
        match self {
            MlhmPreset::Low => low,
            MlhmPreset::Mid => mid,
            MlhmPreset::High => high,
            MlhmPreset::Max => {
                MlhmQuality { ao_radius: Some(2.0), central_differences: true, ..high }
            }
        }
    }
}

impl fmt::Display for MlhmPreset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for MlhmPreset {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MlhmPreset::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| format!("unknown preset '{s}' (expected low, mid, high or max)"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_follow_section_5() {
        let [low, mid, high, max] = MlhmPreset::ALL.map(MlhmPreset::quality);
        assert!(!low.water_rays && !low.shadows && low.ao_radius.is_none());
        assert!(mid.water_rays && mid.shadows && mid.ao_radius == Some(1.0));
        assert_eq!((mid.absorption, mid.secondary_lighting), (WaterAbsorption::Cheap, false));
        assert_eq!((high.absorption, high.secondary_lighting), (WaterAbsorption::Expensive, true));
        assert_eq!(high.ao_radius, Some(1.0));
        assert_eq!((max.ao_radius, max.central_differences), (Some(2.0), true));
        assert_eq!(MlhmQuality { ao_radius: Some(1.0), central_differences: false, ..max }, high);
        for p in MlhmPreset::ALL {
            assert_eq!(p.name().parse::<MlhmPreset>(), Ok(p));
        }
        assert!("ultra".parse::<MlhmPreset>().is_err());
    }
}
