//! The unit a raster's heights are stored in (metre, foot, US survey foot), and why relief
//! took it: a file's vertical unit key, its CRS's linear unit, the reader's option, or an
//! assumption. Readers give their raster's geometry the z scale that turns the stored heights
//! into metres.

use std::fmt;

/// A unit of length a raster's coordinates or heights can be in.
///
/// ```
/// use relief_io::LengthUnit;
/// assert_eq!(LengthUnit::UsSurveyFoot.metres(), 1200.0 / 3937.0);
/// assert_eq!(LengthUnit::from_epsg(9002), Some(LengthUnit::Foot));
/// assert_eq!("us-ft".parse::<LengthUnit>(), Ok(LengthUnit::UsSurveyFoot));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LengthUnit {
    /// The metre (EPSG:9001).
    #[default]
    Metre,
    /// The international foot, 0.3048 m (EPSG:9002).
    Foot,
    /// The US survey foot, 1200/3937 m (EPSG:9003).
    UsSurveyFoot,
}

impl LengthUnit {
    /// Every unit, metre first.
    pub const ALL: [LengthUnit; 3] =
        [LengthUnit::Metre, LengthUnit::Foot, LengthUnit::UsSurveyFoot];

    /// Metres in one unit.
    pub fn metres(self) -> f64 {
        match self {
            LengthUnit::Metre => 1.0,
            LengthUnit::Foot => 0.3048,
            LengthUnit::UsSurveyFoot => 1200.0 / 3937.0,
        }
    }

    /// The unit's name, as EPSG spells it.
    pub fn name(self) -> &'static str {
        match self {
            LengthUnit::Metre => "metre",
            LengthUnit::Foot => "foot",
            LengthUnit::UsSurveyFoot => "US survey foot",
        }
    }

    /// The short name the command line takes: `m`, `ft`, `us-ft`.
    pub fn short_name(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Foot => "ft",
            LengthUnit::UsSurveyFoot => "us-ft",
        }
    }

    /// The unit's EPSG code (9001, 9002, 9003), as GeoTIFF's unit keys store it.
    pub fn epsg(self) -> u16 {
        match self {
            LengthUnit::Metre => 9001,
            LengthUnit::Foot => 9002,
            LengthUnit::UsSurveyFoot => 9003,
        }
    }

    /// The unit of EPSG code `code`, if it is one of these.
    pub fn from_epsg(code: u16) -> Option<LengthUnit> {
        LengthUnit::ALL.into_iter().find(|u| u.epsg() == code)
    }

    /// The unit's ESRI WKT clause, as a `.prj` names it: `UNIT["Meter",1.0]`, ...
    pub fn esri_wkt(self) -> &'static str {
        match self {
            LengthUnit::Metre => "UNIT[\"Meter\",1.0]",
            LengthUnit::Foot => "UNIT[\"Foot\",0.3048]",
            LengthUnit::UsSurveyFoot => "UNIT[\"Foot_US\",0.3048006096012192]",
        }
    }

    /// The unit a WKT `UNIT["name", metres]` clause names, by its factor (to 1e-9).
    pub fn from_metres(metres: f64) -> Option<LengthUnit> {
        LengthUnit::ALL.into_iter().find(|u| (u.metres() - metres).abs() < 1e-9)
    }
}

impl fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl std::str::FromStr for LengthUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "m" | "metre" | "meter" => Ok(LengthUnit::Metre),
            "ft" | "foot" | "feet" => Ok(LengthUnit::Foot),
            "us-ft" | "ftUS" | "us-foot" => Ok(LengthUnit::UsSurveyFoot),
            other => Err(format!("unknown unit '{other}' (expected m, ft or us-ft)")),
        }
    }
}

/// The unit of a raster's stored heights and where relief took it from.
///
/// ```
/// use relief_io::{HeightUnit, LengthUnit};
/// let assumed = HeightUnit::default();
/// assert_eq!(assumed.unit, LengthUnit::Metre);
/// assert!(assumed.to_string().starts_with("metre (assumed"));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct HeightUnit {
    /// The unit.
    pub unit: LengthUnit,
    /// Why: `"VerticalUnitsGeoKey"`, `"the CRS's linear unit (ProjLinearUnitsGeoKey)"`,
    /// `"assumed: ..."`, ...
    pub reason: String,
}

impl HeightUnit {
    /// `unit`, because of `reason`.
    pub fn new(unit: LengthUnit, reason: impl Into<String>) -> HeightUnit {
        HeightUnit { unit, reason: reason.into() }
    }

    /// Metres, assumed because `why`.
    pub fn assumed_metres(why: &str) -> HeightUnit {
        HeightUnit::new(LengthUnit::Metre, format!("assumed: {why}"))
    }

    /// Whether the unit was taken without the file or the caller naming it.
    pub fn is_assumed(&self) -> bool {
        self.reason.starts_with("assumed")
    }
}

impl Default for HeightUnit {
    /// Metres, assumed: the file names no unit.
    fn default() -> Self {
        HeightUnit::assumed_metres("the file names no vertical unit")
    }
}

impl fmt::Display for HeightUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.unit, self.reason)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_codes_and_factors_agree() {
        for unit in LengthUnit::ALL {
            assert_eq!(LengthUnit::from_epsg(unit.epsg()), Some(unit));
            assert_eq!(unit.short_name().parse::<LengthUnit>(), Ok(unit));
            assert_eq!(LengthUnit::from_metres(unit.metres()), Some(unit));
            let factor: f64 =
                unit.esri_wkt().rsplit(',').next().unwrap().trim_end_matches(']').parse().unwrap();
            assert!((factor - unit.metres()).abs() < 1e-15, "{unit}");
        }
        assert!("yard".parse::<LengthUnit>().is_err());
        assert_eq!(LengthUnit::from_epsg(9036), None);
    }
}
