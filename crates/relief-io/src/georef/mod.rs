//! Georeferencing, whatever the format: where a raster lies and in which coordinate reference
//! system ([`Georeference`](crate::Georeference) and the GeoTIFF tags it keeps), the CRS in the
//! words of other tools (EPSG codes, ESRI WKT, units), the unit of the heights, the GeoKeys that
//! place a GeoTIFF, the files beside a raster that place it (world file, `.prj`), degrees to
//! metres on the WGS84 ellipsoid, and the latitude and longitude of a raster's centre.

pub(crate) mod crs;
pub(crate) mod epsg_feet;
pub(crate) mod geodesy;
pub(crate) mod geographic_position;
pub(crate) mod geokey_ids;
pub(crate) mod geokeys;
pub(crate) mod georeference;
pub(crate) mod height_unit;
pub(crate) mod projected_unit;
pub(crate) mod sidecars;
