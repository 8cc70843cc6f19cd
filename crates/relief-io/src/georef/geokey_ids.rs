//! The GeoKeys (GeoTIFF tag 34735) relief reads and writes, by id, and the values of theirs
//! that it names (GeoTIFF 1.1, section 7).

/// GTModelTypeGeoKey: 1 projected, 2 geographic (degrees), 3 geocentric.
pub(crate) const GT_MODEL_TYPE: u16 = 1024;
/// GTModelTypeGeoKey's value for a geographic model (longitude and latitude).
pub(crate) const MODEL_GEOGRAPHIC: u16 = 2;
/// GTRasterTypeGeoKey: 1 PixelIsArea, 2 PixelIsPoint.
pub(crate) const GT_RASTER_TYPE: u16 = 1025;
/// GTRasterTypeGeoKey's value for PixelIsArea.
pub(crate) const PIXEL_IS_AREA: u16 = 1;
/// GTRasterTypeGeoKey's value for PixelIsPoint.
pub(crate) const PIXEL_IS_POINT: u16 = 2;
/// GeographicTypeGeoKey: the geographic CRS (EPSG code).
pub(crate) const GEOGRAPHIC_TYPE: u16 = 2048;
/// GeogAngularUnitsGeoKey: the unit of longitudes and latitudes (EPSG unit code).
pub(crate) const GEOG_ANGULAR_UNITS: u16 = 2054;
/// ProjectedCSTypeGeoKey: the projected CRS (EPSG code).
pub(crate) const PROJECTED_CS_TYPE: u16 = 3072;
/// ProjLinearUnitsGeoKey: the unit of projected coordinates (EPSG unit code).
pub(crate) const PROJ_LINEAR_UNITS: u16 = 3076;
/// VerticalUnitsGeoKey: the unit of the heights (EPSG unit code).
pub(crate) const VERTICAL_UNITS: u16 = 4099;
/// The GeoKey value meaning "user-defined".
pub(crate) const USER_DEFINED: u16 = 32767;
