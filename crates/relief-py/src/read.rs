//! `relief.read`: a height file as a north-up array and its georeference.

use crate::arrays::image_f32;
use crate::errors::{file, invalid};
use crate::georeference::georeference;
use crate::options;
use crate::terrain::flip_rows;
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_io::{LengthUnit, ReadOptions};
use std::path::PathBuf;

/// Reads a height file, in the format its extension names (.tif/.tiff GeoTIFF, .hgt, .asc,
/// .png, .npy, .npz), as relief's command line reads it.
///
/// Returns ``(heights, georeference)``: ``heights`` a float32 array of shape (rows, columns)
/// whose row 0 is the north edge (as rasterio returns a north-up raster), NaN for a void
/// (the file's nodata), in the file's own height unit; ``georeference`` a dict with
/// ``spacing`` (dx, dy) and ``origin`` (the world x, y of the south-west corner) in relief's
/// world (metres), ``geotransform`` (GDAL's six numbers of the north-up array in the file's
/// own CRS and units, as GDAL reads it), ``transform`` (the same as rasterio's Affine),
/// ``world_geotransform`` (GDAL's six numbers in relief's world), ``crs`` (``"EPSG:4326"``,
/// ...), ``epsg``, ``crs_wkt`` (ESRI WKT), ``height_unit``, ``height_unit_reason``,
/// ``z_scale`` (metres per height unit), ``nodata``, ``format``, ``sample_type``,
/// ``georeferenced`` and ``from_degrees``. ``relief.render(*relief.read(path))`` draws what
/// ``relief render PATH`` draws (the dict's ``z_scale`` turns feet into metres).
///
/// A ``.npy`` or ``.npz`` grid has no georeference and relief takes its row 0 as the south
/// edge, so its north-up heights are ``numpy.flipud(numpy.load(path))``.
///
/// ``array`` names the array of an .npz archive (default: the first); ``png_encoding`` says
/// how a PNG encodes heights: ``grey``, ``terrain-rgb`` or ``terrarium``; ``max_memory`` is
/// the most bytes the raster may take (default: half the machine's memory); ``z_unit``
/// (``"m"``, ``"ft"``, ``"us-ft"``) the unit of the file's heights when the file says
/// otherwise or nothing (as ``relief --z-unit``).
///
/// Raises ``FileNotFoundError`` (or another ``OSError``) when the file cannot be read, with
/// relief's message.
#[pyfunction]
#[pyo3(signature = (path, *, array=None, png_encoding="grey", max_memory=None, z_unit=None))]
pub fn read<'py>(
    py: Python<'py>,
    path: PathBuf,
    array: Option<String>,
    png_encoding: &str,
    max_memory: Option<u64>,
    z_unit: Option<&str>,
) -> PyResult<(Bound<'py, PyArray2<f32>>, Bound<'py, PyDict>)> {
    let z_unit = z_unit.map(|u| u.parse::<LengthUnit>().map_err(invalid)).transpose()?;
    let png_encoding = options::png_encoding(png_encoding)?;
    if max_memory == Some(0) {
        return Err(invalid("max_memory must be at least 1 byte"));
    }
    let defaults = ReadOptions::default();
    let max_memory = max_memory.unwrap_or(defaults.max_memory);
    let options = ReadOptions { max_memory, array, png_encoding, z_unit };
    let raster = py.detach(|| relief_io::read_raster(&path, &options)).map_err(file)?;
    let samples = flip_rows(&raster.samples, raster.width);
    let dict = georeference(py, &raster.info, &raster.geometry, raster.height)?;
    Ok((image_f32(py, raster.height, raster.width, samples)?, dict))
}
