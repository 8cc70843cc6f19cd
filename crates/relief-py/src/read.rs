//! `relief.read`: a height file as a north-up array and its georeference.

use crate::arrays::image_f32;
use crate::errors::{file, invalid};
use crate::georeference::georeference;
use crate::terrain::flip_rows;
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_io::{PngEncoding, ReadOptions};
use std::path::PathBuf;

/// Reads a height file, in the format its extension names (.tif/.tiff GeoTIFF, .hgt, .asc,
/// .png, .npy, .npz), as relief's command line reads it.
///
/// Returns ``(heights, georeference)``: ``heights`` a float32 array of shape (rows, columns)
/// whose row 0 is the north edge (as rasterio returns a north-up raster), NaN for a void
/// (the file's nodata); ``georeference`` a dict with ``spacing`` (dx, dy), ``origin`` (the
/// world x, y of the south-west corner), ``geotransform`` (GDAL's six numbers of the north-up
/// array), ``nodata``, ``format``, ``sample_type``, ``georeferenced`` and ``from_degrees``.
/// ``relief.render(*relief.read(path))`` draws what ``relief render PATH`` draws.
///
/// A ``.npy`` or ``.npz`` grid has no georeference and relief takes its row 0 as the south
/// edge, so its north-up heights are ``numpy.flipud(numpy.load(path))``.
///
/// ``array`` names the array of an .npz archive (default: the first); ``png_encoding`` says
/// how a PNG encodes heights: ``grey``, ``terrain-rgb`` or ``terrarium``; ``max_memory`` is
/// the most bytes the raster may take (default: half the machine's memory).
///
/// Raises ``FileNotFoundError`` (or another ``OSError``) when the file cannot be read, with
/// relief's message.
#[pyfunction]
#[pyo3(signature = (path, *, array=None, png_encoding="grey", max_memory=None))]
pub fn read<'py>(
    py: Python<'py>,
    path: PathBuf,
    array: Option<String>,
    png_encoding: &str,
    max_memory: Option<u64>,
) -> PyResult<(Bound<'py, PyArray2<f32>>, Bound<'py, PyDict>)> {
    let png_encoding = match png_encoding {
        "grey" => PngEncoding::Grey,
        "terrain-rgb" => PngEncoding::TerrainRgb,
        "terrarium" => PngEncoding::Terrarium,
        other => {
            return Err(invalid(format!(
                "unknown png_encoding '{other}' (expected grey, terrain-rgb or terrarium)"
            )))
        }
    };
    if max_memory == Some(0) {
        return Err(invalid("max_memory must be at least 1 byte"));
    }
    let defaults = ReadOptions::default();
    let options =
        ReadOptions { max_memory: max_memory.unwrap_or(defaults.max_memory), array, png_encoding };
    let raster = py.detach(|| relief_io::read_raster(&path, &options)).map_err(file)?;
    let samples = flip_rows(&raster.samples, raster.width);
    let dict = georeference(py, &raster.info, &raster.geometry, raster.height)?;
    Ok((image_f32(py, raster.height, raster.width, samples)?, dict))
}
