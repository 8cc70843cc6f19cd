//! `relief.shade`: the shade layers of a heights array (cast shadows, sky-view factor,
//! hillshade, combined), on the array's own grid.

use crate::arrays::{heights as heights_array, image_f32};
use crate::errors::{argument, invalid};
use crate::options;
use crate::terrain::{flip_rows, height_field};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::{HeightField, Surface};
use relief_shade::shade_map::{shade_map, ShadeLayer, ShadeMap, ShadeMapParams, SunPosition};
use relief_trace::{build_tracer, TracerKind};
use std::sync::Arc;

/// The shade layers of a height field, each a float32 array shaped like ``heights``.
///
/// ``heights``, ``spacing``, ``origin``, ``z_scale``, ``surface`` and ``voids`` place and read
/// the terrain as ``render`` does (row 0 the north edge; NaN a void). ``layers``: any of
/// ``"shadow"`` (the fraction of the suns each sample sees, cast shadows exact), ``"sky"`` (the
/// sky-view factor from ``sky_rays`` directions), ``"hillshade"`` (Lambert's cosine with Horn's
/// gradient, as ``gdaldem hillshade``) and ``"combined"`` (the map layer). ``suns``: a sequence
/// of ``(azimuth, elevation)`` in degrees, azimuth clockwise from north, elevation above 0;
/// ``sun_radius``: each sun's angular radius in degrees, sampled by ``sun_rays`` rays.
///
/// Returns a dict from layer name to its array, in the order of ``layers``: 0 dark (or closed
/// to the sky) to 1 lit (or open), NaN at a void of ``heights``, exactly as ``relief shade``
/// computes it.
///
/// Raises ``relief.ReliefError`` (a ``ValueError``) for arrays or options relief cannot use.
#[pyfunction]
#[pyo3(signature = (
    heights, spacing=None, *, origin=None, z_scale=1.0, layers=vec!["combined".to_string()],
    suns=vec![(315.0, 45.0)], sun_radius=0.0, sun_rays=16, sky_rays=64,
    surface="triangles", voids="fill"
))]
#[allow(clippy::too_many_arguments)]
pub fn shade<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    spacing: Option<&Bound<'py, PyAny>>,
    origin: Option<(f64, f64)>,
    z_scale: f64,
    layers: Vec<String>,
    suns: Vec<(f64, f64)>,
    sun_radius: f64,
    sun_rays: u32,
    sky_rays: u32,
    surface: &str,
    voids: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let geometry = options::geometry(spacing, origin, z_scale)?;
    let surface = options::surface(surface)?;
    let voids = options::voids(voids)?;
    let params = map_params(layers, suns, sun_radius, sun_rays, sky_rays)?;
    let grid = heights_array(heights)?;

    let map = py.detach(|| {
        let void: Vec<bool> =
            flip_rows(&grid.samples, grid.width).iter().map(|v| v.is_nan()).collect();
        let field = height_field(&grid, geometry, voids)?;
        let mask = void.contains(&true).then_some(void.as_slice());
        shade_field(&field, surface, mask, &params)
    });
    layer_arrays(py, map.map_err(invalid)?)
}

/// The shade map's parameters: the `layers` by name, the `suns` as (azimuth, elevation) in
/// degrees, each of `sun_radius` degrees sampled by `sun_rays` rays, the sky by `sky_rays`;
/// checked as `relief shade` checks them.
pub fn map_params(
    layers: Vec<String>,
    suns: Vec<(f64, f64)>,
    sun_radius: f64,
    sun_rays: u32,
    sky_rays: u32,
) -> PyResult<ShadeMapParams> {
    let layers = layers
        .iter()
        .map(|name| name.parse::<ShadeLayer>().map_err(invalid))
        .collect::<PyResult<Vec<_>>>()?;
    let suns = suns
        .into_iter()
        .map(|(azimuth_deg, elevation_deg)| SunPosition { azimuth_deg, elevation_deg })
        .collect();
    let params = ShadeMapParams { layers, suns, sun_radius_deg: sun_radius, sun_rays, sky_rays };
    params.validate().map_err(argument)?;
    Ok(params)
}

/// The shade map of `surface` of `field` (NaN where `mask` marks a void), traced by the
/// mipmap tracer as `relief shade` traces it.
pub fn shade_field(
    field: &Arc<HeightField>,
    surface: Surface,
    mask: Option<&[bool]>,
    params: &ShadeMapParams,
) -> Result<ShadeMap, String> {
    let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
    shade_map(field, &*tracer, mask, params, &|_| {}).map_err(|e| e.to_string())
}

/// The layers of `map` as a dict from layer name to a north-up float32 array.
pub fn layer_arrays(py: Python<'_>, map: ShadeMap) -> PyResult<Bound<'_, PyDict>> {
    let result = PyDict::new(py);
    for (layer, values) in map.layers {
        // relief's rows run south to north; the caller's array runs north to south.
        let north_up = flip_rows(&values, map.width);
        result.set_item(layer.name(), image_f32(py, map.height, map.width, north_up)?)?;
    }
    Ok(result)
}
