//! The georeference dict `read` returns beside the heights: where the grid sits in relief's
//! world and what the file said about itself. Built in one place, so that a fuller
//! georeference (a coordinate reference system) adds its keys here.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::GridGeometry;
use relief_io::RasterInfo;

/// The georeference of a `height`-row raster placed by `geometry`, described by `info`:
///
/// - `spacing`: `(dx, dy)`, the texel size in world units (metres when georeferenced);
/// - `origin`: `(x, y)`, the world position of the grid's south-west corner;
/// - `geotransform`: GDAL's six numbers `(west, dx, 0, north, 0, -dy)` of the north-up array,
///   in the same world units;
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
    dict.set_item("spacing", (dx, dy))?;
    dict.set_item("origin", (origin.x, origin.y))?;
    dict.set_item("geotransform", (origin.x, dx, 0.0, north, 0.0, -dy))?;
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
