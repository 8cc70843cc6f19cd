//! The unit of a projected CRS's coordinates, from what a GeoTIFF or a `.prj` says of it: its
//! unit key, its EPSG code or its name.

use crate::georef::epsg_feet::feet_unit_of_projected_code;
use crate::georef::geokey_ids::USER_DEFINED;
use crate::LengthUnit;

/// The unit of a projected CRS's coordinates from its keys and citation text, and why:
/// ProjLinearUnitsGeoKey, else the unit of the EPSG code (`pcs`), else a citation naming
/// `(ftUS)` or `(ft)` as EPSG's names do, else the metre. `Err(code)` for a unit key relief
/// does not know.
pub(crate) fn projected_unit(
    linear_key: Option<u16>,
    pcs: Option<u16>,
    citation: &str,
) -> Result<(LengthUnit, &'static str), u16> {
    match linear_key {
        Some(USER_DEFINED) | None => {}
        Some(code) => {
            return LengthUnit::from_epsg(code).map(|u| (u, "ProjLinearUnitsGeoKey")).ok_or(code)
        }
    }
    if let Some(unit) = pcs.and_then(feet_unit_of_projected_code) {
        return Ok((unit, "the unit of its EPSG code"));
    }
    if let Some(unit) = citation_unit(citation) {
        return Ok((unit, "its citation"));
    }
    Ok((LengthUnit::Metre, "the metre, as no key, code or citation names another"))
}

/// The foot a CRS's name names: `(ftUS)` or `Foot_US`, `(ft)` or `"Foot"`, as EPSG's and
/// ESRI's names do.
fn citation_unit(citation: &str) -> Option<LengthUnit> {
    if citation.contains("(ftUS)") || citation.contains("\"Foot_US\"") {
        Some(LengthUnit::UsSurveyFoot)
    } else if citation.contains("(ft)") || citation.contains("UNIT[\"Foot\"") {
        Some(LengthUnit::Foot)
    } else {
        None
    }
}
