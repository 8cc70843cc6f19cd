//! `relief.shade_window` and `relief.source_info`: the shade layers of one window of a raster of
//! any size, a tile store or a file, exactly as `relief shade` computes them for the whole: the
//! chunk task of `relief.dask.shade`.

use crate::errors::{argument, invalid};
use crate::georeference::georeference;
use crate::shade::{layer_arrays, map_params, SunTime};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_io::{ReadOptions, VoidPolicy};
use relief_render::block_shade::{chunk_halo, shade_block, ShadeSource, DEFAULT_TILE_CACHE};
use relief_shade::horizon::HorizonParams;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

/// A source opened, by its path and the time its index or file changed.
type Opened = (PathBuf, Option<SystemTime>, Arc<ShadeSource>);

/// Sources opened by this process: a worker opens a store once (reading its bounds), whatever
/// the number of its chunks.
static OPENED: Mutex<Vec<Opened>> = Mutex::new(Vec::new());

/// Sources kept open at most.
const KEPT_SOURCES: usize = 4;

/// The source at `path`: a tile store (a folder), or a raster file read whole, its voids
/// filled for tracing (and NaN in every layer), as `relief shade` reads it.
fn open_source(path: &Path, max_memory: Option<u64>) -> Result<Arc<ShadeSource>, String> {
    let stamp_file = if path.is_dir() { path.join("index.json") } else { path.to_path_buf() };
    let stamp = std::fs::metadata(&stamp_file).and_then(|m| m.modified()).ok();
    let mut opened = OPENED.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, _, source)) = opened.iter().find(|(p, s, _)| p == path && *s == stamp) {
        return Ok(source.clone());
    }
    let source = if path.is_dir() {
        ShadeSource::open_store(path, DEFAULT_TILE_CACHE).map_err(|e| e.to_string())?
    } else {
        let defaults = ReadOptions::default();
        let options =
            ReadOptions { max_memory: max_memory.unwrap_or(defaults.max_memory), ..defaults };
        let raster = relief_io::read_raster(path, &options).map_err(|e| e.to_string())?;
        let void: Vec<bool> = raster.samples.iter().map(|v| v.is_nan()).collect();
        let info = raster.info.clone();
        let field = raster.into_height_field(path, VoidPolicy::Fill).map_err(|e| e.to_string())?;
        let void = void.contains(&true).then_some(void);
        ShadeSource::in_memory(path, field, info, void)
    };
    let source = Arc::new(source);
    if opened.len() == KEPT_SOURCES {
        opened.remove(0);
    }
    opened.push((path.to_path_buf(), stamp, source.clone()));
    Ok(source)
}

/// What ``relief.dask`` needs to know of a source before shading it: a dict with ``width``
/// and ``height`` (samples), ``tile`` (a store's tile side, ``None`` for a file), and the
/// georeference keys of ``relief.read`` (``transform``, ``geotransform``, ``crs``,
/// ``crs_wkt``, ``epsg``, ``nodata``, ``spacing``, ``origin``, ...).
///
/// ``source`` is a tile store (a folder written by ``relief tile``) or a height file.
/// Raises ``relief.ReliefError`` when it cannot be opened (an incomplete or corrupt store is
/// refused with the tile named).
#[pyfunction]
#[pyo3(signature = (source, *, max_memory=None))]
pub fn source_info<'py>(
    py: Python<'py>,
    source: PathBuf,
    max_memory: Option<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    let opened = py.detach(|| open_source(&source, max_memory)).map_err(invalid)?;
    let dict = georeference(py, opened.info(), &opened.geometry(), opened.height())?;
    dict.set_item("width", opened.width())?;
    dict.set_item("height", opened.height())?;
    dict.set_item("tile", opened.tile())?;
    Ok(dict)
}

/// The shade layers of one window of a raster of any size: ``source`` a tile store (a folder
/// written by ``relief tile``) or a height file, ``window`` ``(col_off, row_off, width,
/// height)`` in the north-up raster's pixels (rasterio's ``Window``: row 0 the north edge).
///
/// The keywords are ``relief.shade``'s (``layers``, ``suns``, ``sun_radius``, ``sun_rays``,
/// ``azimuths``, ``observer_height``, ``radius``, ``earth_curvature``, ``sky_model``,
/// ``date``, ``time``, ``timezone``, ``step``, ``latitude``, ``longitude``, ``surface``,
/// ``threads``); the
/// spacing, origin and heights come from the source. The window is shaded over itself and
/// the halo its layers need, and its horizons are followed past it through the whole raster,
/// so the result is, bit for bit, what ``relief shade SOURCE`` writes for those pixels,
/// whatever the windows. Returns a dict like ``relief.shade``'s (north-up float32 arrays of
/// the window's shape; ``"horizon"`` one band per direction).
///
/// Raises ``relief.ReliefError`` for a source that cannot be read, a window outside it, or
/// options relief cannot use.
#[pyfunction]
#[pyo3(signature = (
    source, window, *, layers=vec!["combined".to_string()], suns=vec![(315.0, 45.0)],
    sun_radius=0.0, sun_rays=16, azimuths=32, observer_height=0.01, radius=None,
    earth_curvature=None, sky_model="overcast", date=None, time=None, timezone="Z",
    step="15m", latitude=None, longitude=None, surface="triangles", max_memory=None, threads=None
))]
#[allow(clippy::too_many_arguments)]
pub fn shade_window<'py>(
    py: Python<'py>,
    source: PathBuf,
    window: (usize, usize, usize, usize),
    layers: Vec<String>,
    suns: Vec<(f64, f64)>,
    sun_radius: f64,
    sun_rays: u32,
    azimuths: u32,
    observer_height: f64,
    radius: Option<f64>,
    earth_curvature: Option<f64>,
    sky_model: &str,
    date: Option<&str>,
    time: Option<&str>,
    timezone: &str,
    step: &str,
    latitude: Option<f64>,
    longitude: Option<f64>,
    surface: &str,
    max_memory: Option<u64>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let surface = crate::options::surface(surface)?;
    let horizon = HorizonParams { azimuths, observer_height, radius, refraction: earth_curvature };
    let when = SunTime { date, time, timezone, step, latitude, longitude };
    let params = map_params(layers, suns, sun_radius, sun_rays, horizon, sky_model, &when)?;
    params.check_surface(surface).map_err(argument)?;
    let map = py.detach(|| {
        crate::options::on_threads(threads, || {
            let source = open_source(&source, max_memory)?;
            let (col_off, row_off, width, height) = window;
            let (raster_width, raster_height) = (source.width(), source.height());
            if width == 0
                || height == 0
                || col_off + width > raster_width
                || row_off + height > raster_height
            {
                return Err(format!(
                    "window (col_off {col_off}, row_off {row_off}, width {width}, height {height}) \
                     is not within the {raster_width} x {raster_height} raster"
                ));
            }
            let rows = raster_height - row_off - height..raster_height - row_off;
            let halo = chunk_halo(&params, source.span(), &source.geometry())
                .map_err(|e| e.to_string())?;
            shade_block(&source, &params, surface, halo, col_off..col_off + width, rows, &|_| {})
                .map_err(|e| e.to_string())
        })
    })?;
    layer_arrays(py, map.map_err(invalid)?)
}
