//! Where on the earth a raster lies, in latitude and longitude: its centre read directly in a
//! geographic CRS, or taken back from WGS 84 UTM coordinates by the inverse transverse
//! Mercator projection (Krüger's series to fourth order in the third flattening, as Karney
//! 2011 gives them: sub-millimetre within a UTM zone).

use crate::Georeference;
use thiserror::Error;

/// A place on the earth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeographicPosition {
    /// Latitude in degrees, north positive, in [-90, 90].
    pub latitude_deg: f64,
    /// Longitude in degrees, east positive, in [-180, 180).
    pub longitude_deg: f64,
}

/// Why a raster's latitude and longitude cannot be known from its georeference.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PositionError {
    /// The CRS is neither geographic nor WGS 84 UTM (or names no EPSG code).
    #[error("the raster's CRS ({crs}) is neither geographic nor WGS 84 UTM (EPSG 326xx, 327xx), so its latitude and longitude are unknown")]
    UnsupportedCrs {
        /// The CRS as far as it is known.
        crs: String,
    },
    /// The raster's centre is not a place on the earth in its CRS.
    #[error("the raster's centre ({x}, {y}) is not a place on the earth in {crs}")]
    OutOfRange {
        /// The CRS.
        crs: String,
        /// The centre's first coordinate.
        x: f64,
        /// The centre's second coordinate.
        y: f64,
    },
}

/// The WGS 84 ellipsoid's semi-major axis in metres.
const WGS84_SEMI_MAJOR_M: f64 = 6_378_137.0;
/// The WGS 84 ellipsoid's flattening.
const WGS84_FLATTENING: f64 = 1.0 / 298.257_223_563;
/// UTM's scale on the central meridian.
const UTM_SCALE: f64 = 0.9996;
/// UTM's false easting in metres.
const UTM_FALSE_EASTING_M: f64 = 500_000.0;
/// UTM's false northing in the southern hemisphere, in metres.
const UTM_FALSE_NORTHING_SOUTH_M: f64 = 10_000_000.0;

impl Georeference {
    /// The latitude and longitude of the centre of a raster of `width x height` pixels so
    /// placed: its coordinates themselves in a geographic CRS (any datum: the few hundred
    /// metres between datums matter little for where the sun stands), or inverse-projected from
    /// WGS 84 UTM (EPSG 32601-32660 north, 32701-32760 south).
    ///
    /// ```
    /// use relief_io::Georeference;
    /// let tile = Georeference::srtm_tile(46, 7, 3601);
    /// let centre = tile.centre_position(3601, 3601).unwrap();
    /// assert!((centre.latitude_deg - 46.5).abs() < 1e-9 && (centre.longitude_deg - 7.5).abs() < 1e-9);
    /// ```
    pub fn centre_position(
        &self,
        width: usize,
        height: usize,
    ) -> Result<GeographicPosition, PositionError> {
        self.centre_and_true_north(width, height).map(|(position, _)| position)
    }

    /// The direction of true north at the centre of a raster of `width x height` pixels so
    /// placed, in degrees clockwise from the grid's north (+y): 0 in a geographic CRS, minus
    /// the meridians' convergence in WGS 84 UTM (up to a few degrees off the central
    /// meridian). A compass azimuth `a` points along the grid azimuth `a + true_north`.
    ///
    /// ```
    /// use relief_io::Georeference;
    /// assert_eq!(Georeference::srtm_tile(46, 7, 3601).true_north_deg(3601, 3601).unwrap(), 0.0);
    /// ```
    pub fn true_north_deg(&self, width: usize, height: usize) -> Result<f64, PositionError> {
        self.centre_and_true_north(width, height).map(|(_, north)| north)
    }

    /// [`centre_position`](Self::centre_position) and [`true_north_deg`](Self::true_north_deg).
    fn centre_and_true_north(
        &self,
        width: usize,
        height: usize,
    ) -> Result<(GeographicPosition, f64), PositionError> {
        let [x0, a, b, y0, d, e] = self.geotransform;
        let (u, v) = (width as f64 / 2.0, height as f64 / 2.0);
        let (x, y) = (x0 + u * a + v * b, y0 + u * d + v * e);
        let crs = self.epsg().map_or_else(|| "no EPSG code".to_string(), |c| format!("EPSG:{c}"));
        let out_of_range = || PositionError::OutOfRange { crs: crs.clone(), x, y };
        let (position, convergence) = if self.is_geographic() {
            (GeographicPosition { latitude_deg: y, longitude_deg: wrap_longitude(x) }, 0.0)
        } else {
            let (zone, north) = match self.epsg() {
                Some(code @ 32601..=32660) => (code - 32600, true),
                Some(code @ 32701..=32760) => (code - 32700, false),
                _ => return Err(PositionError::UnsupportedCrs { crs }),
            };
            utm_inverse(zone as u8, north, x, y).ok_or_else(out_of_range)?
        };
        let fine = position.latitude_deg.is_finite()
            && position.longitude_deg.is_finite()
            && (-90.0..=90.0).contains(&position.latitude_deg);
        if fine {
            Ok((position, -convergence))
        } else {
            Err(out_of_range())
        }
    }
}

/// The latitude and longitude of WGS 84 UTM coordinates (`easting`, `northing` in metres) of
/// `zone` (1 to 60) in the northern (`north`) or southern hemisphere; `None` for a zone out
/// of range or coordinates that are not finite or lie beyond the projection's reach.
///
/// ```
/// use relief_io::utm_to_geographic;
/// // The centre of zone 32's false origin: 9 E on the equator.
/// let p = utm_to_geographic(32, true, 500_000.0, 0.0).unwrap();
/// assert!(p.latitude_deg.abs() < 1e-12 && (p.longitude_deg - 9.0).abs() < 1e-12);
/// ```
pub fn utm_to_geographic(
    zone: u8,
    north: bool,
    easting: f64,
    northing: f64,
) -> Option<GeographicPosition> {
    utm_inverse(zone, north, easting, northing).map(|(position, _)| position)
}

/// The latitude and longitude of WGS 84 UTM coordinates, and the meridians' convergence
/// there in degrees (the angle from grid north to true north, counterclockwise positive:
/// positive east of the central meridian in the northern hemisphere).
fn utm_inverse(
    zone: u8,
    north: bool,
    easting: f64,
    northing: f64,
) -> Option<(GeographicPosition, f64)> {
    if !(1..=60).contains(&zone) || !easting.is_finite() || !northing.is_finite() {
        return None;
    }
    let false_northing = if north { 0.0 } else { UTM_FALSE_NORTHING_SOUTH_M };
    let central_meridian = f64::from(zone) * 6.0 - 183.0;
    let n = WGS84_FLATTENING / (2.0 - WGS84_FLATTENING);
    let (n2, n3, n4) = (n * n, n * n * n, n * n * n * n);
    // The rectifying radius: the meridian's length is 2 pi of it.
    let rectifying = WGS84_SEMI_MAJOR_M / (1.0 + n) * (1.0 + n2 / 4.0 + n4 / 64.0);
    let xi = (northing - false_northing) / (UTM_SCALE * rectifying);
    let eta = (easting - UTM_FALSE_EASTING_M) / (UTM_SCALE * rectifying);
    // Beyond about 90 degrees of arc from the central meridian the series means nothing.
    if xi.abs() > std::f64::consts::PI || eta.abs() > 2.5 {
        return None;
    }
    // Transverse Mercator to the conformal sphere (Krüger's beta series).
    let beta = [
        n / 2.0 - 2.0 * n2 / 3.0 + 37.0 * n3 / 96.0 - n4 / 360.0,
        n2 / 48.0 + n3 / 15.0 - 437.0 * n4 / 1440.0,
        17.0 * n3 / 480.0 - 37.0 * n4 / 840.0,
        4397.0 * n4 / 161_280.0,
    ];
    let (mut xi_sphere, mut eta_sphere) = (xi, eta);
    // The derivatives of the series, for the convergence.
    let (mut p, mut q) = (1.0, 0.0);
    for (j, b) in beta.iter().enumerate() {
        let k = 2.0 * (j + 1) as f64;
        xi_sphere -= b * (k * xi).sin() * (k * eta).cosh();
        eta_sphere -= b * (k * xi).cos() * (k * eta).sinh();
        p -= k * b * (k * xi).cos() * (k * eta).cosh();
        q += k * b * (k * xi).sin() * (k * eta).sinh();
    }
    let spherical = xi_sphere.tan() * eta_sphere.tanh();
    let convergence = (q + p * spherical).atan2(p - q * spherical).to_degrees();
    let conformal_latitude = (xi_sphere.sin() / eta_sphere.cosh()).asin();
    let longitude = central_meridian + eta_sphere.sinh().atan2(xi_sphere.cos()).to_degrees();
    // Conformal latitude to geodetic latitude (the delta series).
    let delta = [
        2.0 * n - 2.0 * n2 / 3.0 - 2.0 * n3 + 116.0 * n4 / 45.0,
        7.0 * n2 / 3.0 - 8.0 * n3 / 5.0 - 227.0 * n4 / 45.0,
        56.0 * n3 / 15.0 - 136.0 * n4 / 35.0,
        4279.0 * n4 / 630.0,
    ];
    let latitude = conformal_latitude
        + delta
            .iter()
            .enumerate()
            .map(|(j, d)| d * (2.0 * (j + 1) as f64 * conformal_latitude).sin())
            .sum::<f64>();
    let position = GeographicPosition {
        latitude_deg: latitude.to_degrees(),
        longitude_deg: wrap_longitude(longitude),
    };
    Some((position, convergence))
}

/// `degrees` of longitude wrapped to [-180, 180).
fn wrap_longitude(degrees: f64) -> f64 {
    (degrees + 180.0).rem_euclid(360.0) - 180.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::georef::geokey_ids::{
        GT_MODEL_TYPE, GT_RASTER_TYPE, PIXEL_IS_AREA, PROJECTED_CS_TYPE,
    };
    use crate::GeoTiffTags;

    /// UTM points and their latitude and longitude as PROJ gives them (EPSG code, easting,
    /// northing, latitude, longitude), over both hemispheres, zone edges and high latitudes.
    #[rustfmt::skip]
    const PROJ_POINTS: [(u16, f64, f64, f64, f64); 10] = [
        (32632, 500000.00, 5200000.00, 46.9535292023, 9.0000000000),
        (32632, 400000.00, 100.00, 0.0009046193, 8.1013623397),
        (32618, 583960.00, 4507523.00, 40.7143492125, -74.0059695268),
        (32733, 334786.00, 6252080.00, -33.8586639165, 13.2140228609),
        (32601, 166021.00, 0.01, 0.0000000903, 179.9999960236),
        (32660, 833978.00, 9329005.00, 83.3059127428, -156.4171668414),
        (32706, 720000.00, 9000000.00, -9.0410993107, -144.9985980806),
        (32756, 334000.00, 6252000.00, -33.8592617045, 151.2055146869),
        (32633, 420000.00, 8800000.00, 79.2454023252, 11.1570066075),
        (32723, 600000.00, 2000000.00, -72.0775365270, -42.0875076782),
    ];

    /// A north-up PixelIsArea raster in projected CRS `epsg` whose north-west corner is at
    /// (`west`, `north`), pixels `size` metres.
    fn projected(epsg: u16, west: f64, north: f64, size: f64) -> Georeference {
        let tags = GeoTiffTags {
            model_pixel_scale: Some(vec![size, size, 0.0]),
            model_tiepoint: Some(vec![0.0, 0.0, 0.0, west, north, 0.0]),
            #[rustfmt::skip]
            geo_key_directory: Some(vec![
                1, 1, 0, 3,
                GT_MODEL_TYPE, 0, 1, 1,
                GT_RASTER_TYPE, 0, 1, PIXEL_IS_AREA,
                PROJECTED_CS_TYPE, 0, 1, epsg,
            ]),
            ..GeoTiffTags::default()
        };
        Georeference::from_geotiff_tags(tags).unwrap()
    }

    #[test]
    fn utm_points_agree_with_proj() {
        for (epsg, easting, northing, latitude, longitude) in PROJ_POINTS {
            let (zone, north) =
                if epsg < 32700 { (epsg - 32600, true) } else { (epsg - 32700, false) };
            let p = utm_to_geographic(zone as u8, north, easting, northing).unwrap();
            // 1e-9 degrees is 0.1 mm; PROJ's figures are given to 1e-10.
            assert!((p.latitude_deg - latitude).abs() < 1e-9, "{epsg} {p:?} {latitude}");
            let dlon = wrap_longitude(p.longitude_deg - longitude);
            assert!(dlon.abs() < 1e-9, "{epsg} {p:?} {longitude}");
        }
    }

    #[test]
    fn the_centre_of_a_utm_raster() {
        // 1000 x 600 pixels of 10 m whose centre is (500000, 5200000) in zone 32 N.
        let raster = projected(32632, 495_000.0, 5_203_000.0, 10.0);
        let centre = raster.centre_position(1000, 600).unwrap();
        assert!((centre.latitude_deg - 46.9535292023).abs() < 1e-9, "{centre:?}");
        assert!((centre.longitude_deg - 9.0).abs() < 1e-9, "{centre:?}");
        let south = projected(32733, 334_776.0, 6_252_090.0, 2.0);
        let centre = south.centre_position(10, 10).unwrap();
        assert!((centre.latitude_deg - -33.8586639165).abs() < 1e-9, "{centre:?}");
    }

    #[test]
    fn true_north_off_the_central_meridian() {
        // (EPSG code, easting, northing, grid azimuth of true north) as PROJ gives them: the
        // direction between points 1e-5 degrees of latitude apart.
        #[rustfmt::skip]
        let proj = [
            (32632, 690237.1407995026, 5202641.6391071845, -1.82744111525047),
            (32632, 286935.5585948423, 5203413.721526127, 2.046889492792174),
            (32733, 334416.3939896558, 6251925.3603523895, -0.997553193353661),
            (32618, 584469.7157825801, 4507045.932973549, -0.6522692115149795),
            (32660, 595404.9704624237, 7767829.407630524, -2.3494063221876353),
        ];
        for (epsg, easting, northing, true_north) in proj {
            // A 2 x 2 raster of 1 m pixels centred on the point.
            let raster = projected(epsg, easting - 1.0, northing + 1.0, 1.0);
            let got = raster.true_north_deg(2, 2).unwrap();
            assert!((got - true_north).abs() < 1e-6, "{epsg}: {got} vs {true_north}");
        }
        let on_the_meridian = projected(32632, 499_999.0, 5_200_001.0, 1.0);
        assert!(on_the_meridian.true_north_deg(2, 2).unwrap().abs() < 1e-12);
    }

    #[test]
    fn geographic_rasters_are_read_directly() {
        let tile = Georeference::srtm_tile(-34, 151, 1201);
        let centre = tile.centre_position(1201, 1201).unwrap();
        assert!(
            (centre.latitude_deg - -33.5).abs() < 1e-9
                && (centre.longitude_deg - 151.5).abs() < 1e-9
        );
        // Longitudes past 180 wrap.
        let east = Georeference::srtm_tile(10, 185, 1201);
        assert!((east.centre_position(1201, 1201).unwrap().longitude_deg - -174.5).abs() < 1e-9);
        let beyond_the_pole = Georeference::srtm_tile(95, 0, 1201);
        let error = beyond_the_pole.centre_position(1201, 1201).unwrap_err();
        assert!(matches!(error, PositionError::OutOfRange { .. }), "{error}");
    }

    #[test]
    fn other_crs_are_refused() {
        // Swiss LV95 (EPSG 2056) and a grid without a CRS.
        let swiss = projected(2056, 2_600_000.0, 1_200_000.0, 2.0);
        let error = swiss.centre_position(100, 100).unwrap_err().to_string();
        assert!(
            error.contains("EPSG:2056") && error.contains("neither geographic nor WGS 84 UTM"),
            "{error}"
        );
        let bare = Georeference::north_up_grid(0.0, 100.0, 1.0, 1.0);
        let error = bare.centre_position(100, 100).unwrap_err().to_string();
        assert!(error.contains("no EPSG code"), "{error}");
        // A UTM easting beyond the projection's reach.
        let far = projected(32632, 1e9, 5e6, 1.0);
        assert!(matches!(far.centre_position(2, 2), Err(PositionError::OutOfRange { .. })));
        assert_eq!(utm_to_geographic(0, true, 500_000.0, 0.0), None);
        assert_eq!(utm_to_geographic(61, true, 500_000.0, 0.0), None);
        assert_eq!(utm_to_geographic(32, true, f64::NAN, 0.0), None);
    }
}
