//! The coordinate reference system a [`Georeference`] names, in the words other formats and
//! tools use: its EPSG code, whether it is geographic, the unit of its coordinates and of its
//! heights, and its ESRI WKT (what a `.prj` beside an `.asc` or a `.png` holds).

use crate::georef::geokey_ids::{
    GEOGRAPHIC_TYPE, GT_MODEL_TYPE, GT_RASTER_TYPE, MODEL_GEOGRAPHIC, PIXEL_IS_AREA,
    PROJECTED_CS_TYPE, PROJ_LINEAR_UNITS, USER_DEFINED, VERTICAL_UNITS,
};
use crate::georef::projected_unit::projected_unit;
use crate::{GeoTiffTags, Georeference, HeightUnit, LengthUnit};

/// ESRI's WKT of the WGS 84 geographic CRS (EPSG:4326).
const GCS_WGS84: &str = "GEOGCS[\"GCS_WGS_1984\",DATUM[\"D_WGS_1984\",SPHEROID[\"WGS_1984\",\
    6378137.0,298.257223563]],PRIMEM[\"Greenwich\",0.0],UNIT[\"Degree\",0.0174532925199433]]";
/// ESRI's WKT of the NAD83 geographic CRS (EPSG:4269).
const GCS_NAD83: &str = "GEOGCS[\"GCS_North_American_1983\",DATUM[\"D_North_American_1983\",\
    SPHEROID[\"GRS_1980\",6378137.0,298.257222101]],PRIMEM[\"Greenwich\",0.0],\
    UNIT[\"Degree\",0.0174532925199433]]";

impl Georeference {
    /// The value of the short-valued GeoKey `id`, if the directory holds it.
    pub fn geo_key(&self, id: u16) -> Option<u16> {
        let directory = self.geotiff.geo_key_directory.as_deref()?;
        let count = directory.get(3).map_or(0, |&c| usize::from(c));
        directory
            .get(4..)?
            .chunks_exact(4)
            .take(count)
            .find(|key| key[0] == id && key[1] == 0 && key[2] == 1)
            .map(|key| key[3])
    }

    /// The text of the GeoKeys' citations (GeoAsciiParams), `|`-separated as stored, without
    /// the terminating NUL; empty when there is none.
    pub fn citation(&self) -> String {
        let bytes = self.geotiff.geo_ascii_params.as_deref().unwrap_or(&[]);
        String::from_utf8_lossy(bytes).trim_end_matches('\0').to_string()
    }

    /// Whether the coordinates are longitude and latitude (GTModelTypeGeoKey 2, or a
    /// geographic CRS key without a projected one).
    pub fn is_geographic(&self) -> bool {
        match self.geo_key(GT_MODEL_TYPE) {
            Some(model) => model == MODEL_GEOGRAPHIC,
            None => {
                self.geo_key(GEOGRAPHIC_TYPE).is_some() && self.geo_key(PROJECTED_CS_TYPE).is_none()
            }
        }
    }

    /// Whether the keys name a CRS at all (a model type or a CRS code): an ESRI grid without
    /// a `.prj` places its cells but names none.
    pub fn has_crs(&self) -> bool {
        [GT_MODEL_TYPE, GEOGRAPHIC_TYPE, PROJECTED_CS_TYPE]
            .iter()
            .any(|&k| self.geo_key(k).is_some())
    }

    /// The EPSG code of the CRS: the projected CRS's, else the geographic one's; `None` for a
    /// user-defined CRS or none.
    ///
    /// ```
    /// use relief_io::Georeference;
    /// assert_eq!(Georeference::srtm_tile(36, -85, 1201).epsg(), Some(4326));
    /// ```
    pub fn epsg(&self) -> Option<u16> {
        let code = if self.is_geographic() {
            self.geo_key(GEOGRAPHIC_TYPE)
        } else {
            self.geo_key(PROJECTED_CS_TYPE)
        };
        code.filter(|&c| c != USER_DEFINED && c != 0)
    }

    /// A short name of the CRS for messages: `EPSG:4326`, else its citation, else
    /// `a user-defined CRS` or `no CRS`.
    pub fn crs_name(&self) -> String {
        if let Some(code) = self.epsg() {
            return format!("EPSG:{code}");
        }
        let citation = self.citation();
        let first = citation.split('|').next().unwrap_or("").trim();
        if !first.is_empty() && !first.starts_with("ESRI PE String") {
            return first.to_string();
        }
        if self.has_crs() {
            "a user-defined CRS".into()
        } else {
            "no CRS".into()
        }
    }

    /// The unit of a projected CRS's coordinates and why (see [`Georeference::height_unit`]);
    /// `None` for a geographic CRS, no CRS, or a unit key relief does not know.
    pub fn linear_unit(&self) -> Option<(LengthUnit, &'static str)> {
        if self.is_geographic() || !self.has_crs() {
            return None;
        }
        let (key, pcs) = (self.geo_key(PROJ_LINEAR_UNITS), self.geo_key(PROJECTED_CS_TYPE));
        projected_unit(key, pcs, &self.citation()).ok()
    }

    /// The unit of the heights as the georeference says: VerticalUnitsGeoKey when present,
    /// else the projected CRS's linear unit (ProjLinearUnitsGeoKey, the EPSG code's unit, or
    /// the CRS name's), else metres, assumed.
    ///
    /// ```
    /// use relief_io::{Georeference, LengthUnit};
    /// let tile = Georeference::srtm_tile(36, -85, 1201);
    /// assert_eq!(tile.height_unit().unit, LengthUnit::Metre);
    /// assert!(tile.height_unit().is_assumed());
    /// ```
    pub fn height_unit(&self) -> HeightUnit {
        if let Some(code) = self.geo_key(VERTICAL_UNITS).filter(|&c| c != USER_DEFINED) {
            return match LengthUnit::from_epsg(code) {
                Some(unit) => HeightUnit::new(unit, "VerticalUnitsGeoKey"),
                None => HeightUnit::assumed_metres(&format!(
                    "VerticalUnitsGeoKey names EPSG:{code}, a unit relief does not know"
                )),
            };
        }
        if self.is_geographic() {
            return HeightUnit::assumed_metres("the CRS is geographic and names no vertical unit");
        }
        match self.linear_unit() {
            Some((unit, why)) if self.has_crs() => HeightUnit::new(
                unit,
                format!("the unit of the projected CRS {}, from {why}", self.crs_name()),
            ),
            _ => HeightUnit::default(),
        }
    }

    /// The CRS as ESRI WKT, the text of a `.prj`: the ESRI PE string a GeoTIFF's citation
    /// holds, else the WKT of the EPSG codes relief knows (4326, 4269, 3857, the WGS 84 and
    /// NAD83 UTM zones, 2274). `Err` says why the CRS cannot be written.
    ///
    /// ```
    /// use relief_io::Georeference;
    /// let wkt = Georeference::srtm_tile(36, -85, 1201).esri_wkt().unwrap();
    /// assert!(wkt.starts_with("GEOGCS[\"GCS_WGS_1984\""));
    /// ```
    pub fn esri_wkt(&self) -> Result<String, String> {
        let citation = self.citation();
        if let Some(at) = citation.find("ESRI PE String = ") {
            let text = &citation[at + "ESRI PE String = ".len()..];
            return Ok(text.split('|').next().unwrap_or("").trim().to_string());
        }
        let Some(code) = self.epsg() else {
            return Err(if self.has_crs() {
                format!("{} is user-defined: relief cannot write it as WKT", self.crs_name())
            } else {
                "the input names no CRS".into()
            });
        };
        epsg_esri_wkt(code).ok_or_else(|| {
            format!(
                "relief knows no WKT of EPSG:{code} (it writes EPSG:4326, 4269, 3857, 2274 and \
                 the WGS 84 and NAD83 UTM zones)"
            )
        })
    }
}

impl Georeference {
    /// This georeference with its VerticalUnitsGeoKey set to `unit` (added, or replacing the
    /// one there), for heights written in `unit`.
    ///
    /// ```
    /// use relief_io::{Georeference, LengthUnit};
    /// let tile = Georeference::srtm_tile(36, -85, 1201).with_vertical_unit(LengthUnit::Foot);
    /// assert_eq!(tile.geo_key(4099), Some(9002));
    /// assert_eq!(tile.height_unit().unit, LengthUnit::Foot);
    /// ```
    pub fn with_vertical_unit(&self, unit: LengthUnit) -> Georeference {
        let mut result = self.clone();
        let directory = result.geotiff.geo_key_directory.get_or_insert_with(|| vec![1, 1, 0, 0]);
        let count = directory.get(3).map_or(0, |&c| usize::from(c));
        let mut keys: Vec<[u16; 4]> = directory
            .get(4..)
            .unwrap_or(&[])
            .chunks_exact(4)
            .take(count)
            .map(|k| [k[0], k[1], k[2], k[3]])
            .filter(|k| k[0] != VERTICAL_UNITS)
            .collect();
        keys.push([VERTICAL_UNITS, 0, 1, unit.epsg()]);
        keys.sort_by_key(|k| k[0]);
        let header = [
            directory[0],
            directory.get(1).copied().unwrap_or(1),
            directory.get(2).copied().unwrap_or(0),
        ];
        let mut rebuilt = header.to_vec();
        rebuilt.push(keys.len() as u16);
        rebuilt.extend(keys.iter().flatten());
        *directory = rebuilt;
        result
    }

    /// The geotransform of the grid written north-up (first row the northernmost), for a
    /// `height`-row grid: the stored one, or a south-up file's turned over.
    pub fn north_up_geotransform(&self, height: usize) -> [f64; 6] {
        let [x0, a, b, y0, d, e] = self.geotransform;
        if e > 0.0 {
            [x0 + b * height as f64, a, -b, y0 + e * height as f64, d, -e]
        } else {
            [x0, a, b, y0, d, e]
        }
    }
}

/// What a `.prj`'s ESRI WKT says of its CRS, as far as placing a grid needs.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PrjCrs {
    /// The georeference of the grid in this CRS (its keys, the WKT in its citation).
    pub(crate) georeference: Georeference,
    /// Metres per unit of a projected CRS's coordinates; `None` for a geographic CRS.
    pub(crate) metres_per_unit: Option<f64>,
}

/// The CRS of the ESRI WKT `wkt` (a `.prj`) for a north-up grid whose north-west corner is
/// (`west`, `north`) and whose cells are `dx x dy` in the CRS's units. `Err` says why the
/// text is not a CRS relief reads: neither `GEOGCS[...]` nor `PROJCS[...]`, or a projected
/// CRS without a unit.
pub(crate) fn prj_crs(
    wkt: &str,
    (west, north, dx, dy): (f64, f64, f64, f64),
) -> Result<PrjCrs, String> {
    let wkt = wkt.trim().trim_start_matches('\u{feff}');
    let geographic = wkt.starts_with("GEOGCS[");
    if !geographic && !wkt.starts_with("PROJCS[") {
        let start: String = wkt.chars().take(24).collect();
        return Err(format!("it is not ESRI WKT (it starts '{start}', not GEOGCS[ or PROJCS[)"));
    }
    let name = first_quoted(wkt);
    let code = KNOWN_CODES
        .iter()
        .flat_map(|range| range.clone())
        .find(|&code| epsg_esri_wkt(code).is_some_and(|known| first_quoted(&known) == name));
    let metres_per_unit = if geographic {
        None
    } else {
        // The PROJCS's own UNIT is its last.
        let at = wkt.rfind("UNIT[").ok_or("the projected CRS names no UNIT")?;
        let factor = wkt[at..]
            .split(',')
            .nth(1)
            .map(|f| f.trim().trim_end_matches(']').trim())
            .and_then(|f| f.parse::<f64>().ok())
            .filter(|f| f.is_finite() && *f > 0.0)
            .ok_or("its UNIT has no positive factor")?;
        Some(factor)
    };
    let unit = metres_per_unit.and_then(LengthUnit::from_metres);
    #[rustfmt::skip]
    let mut keys = vec![
        GT_MODEL_TYPE, 0, 1, if geographic { MODEL_GEOGRAPHIC } else { 1 },
        GT_RASTER_TYPE, 0, 1, PIXEL_IS_AREA,
    ];
    let mut ascii = None;
    if code.is_none() {
        let text = format!("ESRI PE String = {wkt}|");
        keys.extend([1026, 34737, text.len() as u16, 0]);
        ascii = Some(text.into_bytes());
    }
    let crs_key = if geographic { GEOGRAPHIC_TYPE } else { PROJECTED_CS_TYPE };
    keys.extend([crs_key, 0, 1, code.unwrap_or(USER_DEFINED)]);
    if let Some(unit) = unit.filter(|_| !geographic) {
        keys.extend([PROJ_LINEAR_UNITS, 0, 1, unit.epsg()]);
    }
    let mut directory = vec![1, 1, 0, (keys.len() / 4) as u16];
    directory.extend(keys);
    let tags = GeoTiffTags {
        model_pixel_scale: Some(vec![dx, dy, 0.0]),
        model_tiepoint: Some(vec![0.0, 0.0, 0.0, west, north, 0.0]),
        geo_key_directory: Some(directory),
        geo_ascii_params: ascii,
        ..GeoTiffTags::default()
    };
    let georeference =
        Georeference { geotransform: [west, dx, 0.0, north, 0.0, -dy], geotiff: tags };
    Ok(PrjCrs { georeference, metres_per_unit })
}

/// The EPSG codes whose ESRI WKT relief writes, and recognises in a `.prj` by name.
const KNOWN_CODES: [std::ops::RangeInclusive<u16>; 7] = [
    4326..=4326,
    4269..=4269,
    3857..=3857,
    2274..=2274,
    32601..=32660,
    32701..=32760,
    26901..=26923,
];

/// The first quoted name of a WKT: its CRS's name.
fn first_quoted(wkt: &str) -> &str {
    wkt.split('"').nth(1).unwrap_or("")
}

/// ESRI WKT of the EPSG codes relief knows.
fn epsg_esri_wkt(code: u16) -> Option<String> {
    let utm = |name: &str, gcs: &str, zone: u16, south: bool| {
        let meridian = f64::from(-183 + 6 * i32::from(zone));
        let north = if south { 10_000_000.0 } else { 0.0 };
        format!(
            "PROJCS[\"{name}_UTM_Zone_{zone}{}\",{gcs},PROJECTION[\"Transverse_Mercator\"],\
             PARAMETER[\"False_Easting\",500000.0],PARAMETER[\"False_Northing\",{north:.1}],\
             PARAMETER[\"Central_Meridian\",{meridian:.1}],PARAMETER[\"Scale_Factor\",0.9996],\
             PARAMETER[\"Latitude_Of_Origin\",0.0],UNIT[\"Meter\",1.0]]",
            if south { "S" } else { "N" }
        )
    };
    Some(match code {
        4326 => GCS_WGS84.to_string(),
        4269 => GCS_NAD83.to_string(),
        3857 => format!(
            "PROJCS[\"WGS_1984_Web_Mercator_Auxiliary_Sphere\",{GCS_WGS84},\
             PROJECTION[\"Mercator_Auxiliary_Sphere\"],PARAMETER[\"False_Easting\",0.0],\
             PARAMETER[\"False_Northing\",0.0],PARAMETER[\"Central_Meridian\",0.0],\
             PARAMETER[\"Standard_Parallel_1\",0.0],PARAMETER[\"Auxiliary_Sphere_Type\",0.0],\
             UNIT[\"Meter\",1.0]]"
        ),
        2274 => format!(
            "PROJCS[\"NAD_1983_StatePlane_Tennessee_FIPS_4100_Feet\",{GCS_NAD83},\
             PROJECTION[\"Lambert_Conformal_Conic\"],PARAMETER[\"False_Easting\",1968500.0],\
             PARAMETER[\"False_Northing\",0.0],PARAMETER[\"Central_Meridian\",-86.0],\
             PARAMETER[\"Standard_Parallel_1\",36.4166666666667],\
             PARAMETER[\"Standard_Parallel_2\",35.25],\
             PARAMETER[\"Latitude_Of_Origin\",34.3333333333333],\
             UNIT[\"Foot_US\",0.3048006096012192]]"
        ),
        32601..=32660 => utm("WGS_1984", GCS_WGS84, code - 32600, false),
        32701..=32760 => utm("WGS_1984", GCS_WGS84, code - 32700, true),
        26901..=26923 => utm("NAD_1983", GCS_NAD83, code - 26900, false),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with_keys(keys: &[u16], ascii: &str) -> Georeference {
        let mut directory = vec![1, 1, 0, (keys.len() / 3) as u16];
        for key in keys.chunks_exact(3) {
            let location = if key[1] == 1 { 34737 } else { 0 };
            directory.extend([
                key[0],
                location,
                if location == 0 { 1 } else { key[2] },
                if location == 0 { key[2] } else { 0 },
            ]);
        }
        let tags = GeoTiffTags {
            model_pixel_scale: Some(vec![1.0, 1.0, 0.0]),
            model_tiepoint: Some(vec![0.0; 6]),
            geo_key_directory: Some(directory),
            geo_ascii_params: (!ascii.is_empty()).then(|| ascii.as_bytes().to_vec()),
            ..GeoTiffTags::default()
        };
        Georeference::from_geotiff_tags(tags).unwrap()
    }

    #[test]
    fn units_from_keys_codes_and_citations() {
        // EPSG:2274 by code alone: US survey feet, from the code.
        let tennessee = with_keys(&[1024, 0, 1, 3072, 0, 2274], "");
        assert_eq!(tennessee.linear_unit().unwrap().0, LengthUnit::UsSurveyFoot);
        let heights = tennessee.height_unit();
        assert_eq!(heights.unit, LengthUnit::UsSurveyFoot);
        assert!(heights.reason.contains("EPSG:2274"), "{heights}");
        // A vertical unit key wins.
        let metres_up = with_keys(&[1024, 0, 1, 3072, 0, 2274, 4099, 0, 9001], "");
        assert_eq!(metres_up.height_unit().unit, LengthUnit::Metre);
        assert_eq!(metres_up.height_unit().reason, "VerticalUnitsGeoKey");
        // A user-defined CRS whose citation names its foot.
        let cited = with_keys(&[1024, 0, 1, 3072, 0, 32767, 1026, 1, 9], "x (ft)|");
        assert_eq!(cited.height_unit().unit, LengthUnit::Foot);
        // UTM: metres, from the (absent) unit key's default.
        let utm = with_keys(&[1024, 0, 1, 3072, 0, 32617], "");
        assert_eq!(utm.height_unit().unit, LengthUnit::Metre);
        assert!(!utm.height_unit().is_assumed());
        assert!(utm.esri_wkt().unwrap().contains("\"Central_Meridian\",-81.0"));
        // Geographic: assumed metres.
        let geographic = with_keys(&[1024, 0, 2, 2048, 0, 4326], "");
        assert!(geographic.height_unit().is_assumed());
        assert_eq!(geographic.epsg(), Some(4326));
        assert!(Georeference::north_up_grid(0.0, 0.0, 1.0, 1.0).esri_wkt().is_err());
        assert_eq!(projected_unit(Some(9036), None, ""), Err(9036));
    }

    #[test]
    fn prj_texts_name_their_codes_or_keep_their_wkt() {
        let place = (100.0, 900.0, 10.0, 10.0);
        let tennessee = epsg_esri_wkt(2274).unwrap();
        let crs = prj_crs(&tennessee, place).unwrap();
        assert_eq!(crs.georeference.epsg(), Some(2274));
        assert_eq!(crs.metres_per_unit, Some(LengthUnit::UsSurveyFoot.metres()));
        assert_eq!(crs.georeference.height_unit().unit, LengthUnit::UsSurveyFoot);
        let crs = prj_crs(GCS_WGS84, place).unwrap();
        assert_eq!((crs.georeference.epsg(), crs.metres_per_unit), (Some(4326), None));
        assert!(crs.georeference.is_geographic());
        // An unknown CRS keeps its WKT, which esri_wkt gives back.
        let other = tennessee.replace("Tennessee", "Elsewhere");
        let crs = prj_crs(&other, place).unwrap();
        assert_eq!(crs.georeference.epsg(), None);
        assert_eq!(crs.georeference.esri_wkt().unwrap(), other);
        assert_eq!(crs.georeference.height_unit().unit, LengthUnit::UsSurveyFoot);
        assert!(prj_crs("+proj=longlat", place).is_err());
    }
}
