//! The georeference dict `read` returns beside the heights: where the grid sits in relief's
//! world, where it sits in the file's own CRS (as GDAL and rasterio place it), and what the
//! file said about itself, its heights' unit included.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::GridGeometry;
use relief_io::RasterInfo;

/// The georeference of a `height`-row raster placed by `geometry`, described by `info`:
///
/// - `spacing`: `(dx, dy)`, the texel size in world units (metres when georeferenced);
/// - `origin`: `(x, y)`, the world position of the grid's south-west corner;
/// - `geotransform`: GDAL's six numbers of the north-up array in the file's own units and
///   CRS (degrees for a geographic CRS, feet for a CRS in feet), as GDAL reads the file;
///   without a georeference, those of relief's world;
/// - `transform`: the same as rasterio's `Affine` six numbers `(a, b, c, d, e, f)`;
/// - `world_geotransform`: GDAL's six numbers `(west, dx, 0, north, 0, -dy)` of the north-up
///   array in relief's world (metres);
/// - `crs`: `"EPSG:<code>"` when the file names an EPSG-coded CRS, else its name or `None`;
///   `epsg`: the code or `None`; `crs_wkt`: the CRS's ESRI WKT where relief can write it,
///   else `None`;
/// - `height_unit`: the unit of the heights (`metre`, `foot`, `US survey foot`),
///   `height_unit_reason` why relief took it, and `z_scale` the metres in one unit (what
///   `render` and `shade` multiply the heights by when given this dict);
/// - `nodata`: the value the file declares for voids, or `None`;
/// - `format`, `sample_type`: the file's format and stored sample type (`int16`, ...);
/// - `georeferenced`: whether spacing and origin came from the file (else 1 and 0);
/// - `from_degrees`: `None`, or `{dlon, dlat, latitude}` when the file's georeference was in
///   degrees and relief converted it to metres at that latitude.
pub fn georeference<'py>(
    py: Python<'py>,
    info: &RasterInfo,
    geometry: &GridGeometry,
    height: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let (dx, dy, origin) = (geometry.dx, geometry.dy, geometry.origin);
    let north = origin.y + height as f64 * dy;
    let world = [origin.x, dx, 0.0, north, 0.0, -dy];
    let file = info.georeference.as_ref();
    let [x0, a, b, y0, d, e] = file.map_or(world, |g| g.north_up_geotransform(height));
    dict.set_item("spacing", (dx, dy))?;
    dict.set_item("origin", (origin.x, origin.y))?;
    dict.set_item("geotransform", (x0, a, b, y0, d, e))?;
    dict.set_item("transform", (a, b, x0, d, e, y0))?;
    dict.set_item("world_geotransform", (world[0], dx, 0.0, north, 0.0, -dy))?;
    let named = file.filter(|g| g.has_crs());
    dict.set_item("crs", named.map(|g| g.crs_name()))?;
    dict.set_item("epsg", named.and_then(|g| g.epsg()))?;
    dict.set_item("crs_wkt", named.and_then(|g| g.esri_wkt().ok()))?;
    dict.set_item("height_unit", info.height_unit.unit.name())?;
    dict.set_item("height_unit_reason", &info.height_unit.reason)?;
    dict.set_item("z_scale", geometry.z_scale)?;
    dict.set_item("nodata", info.nodata)?;
    dict.set_item("format", info.format.name())?;
    dict.set_item("sample_type", &info.sample_type)?;
    dict.set_item("georeferenced", info.georeferenced)?;
    let degrees = match &info.from_degrees {
        Some(d) => {
            let degrees = PyDict::new(py);
            degrees.set_item("dlon", d.dlon)?;
            degrees.set_item("dlat", d.dlat)?;
            degrees.set_item("latitude", d.latitude)?;
            Some(degrees)
        }
        None => None,
    };
    dict.set_item("from_degrees", degrees)?;
    Ok(dict)
}
