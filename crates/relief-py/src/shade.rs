//! `relief.shade`: the shade layers of a heights array (cast shadows, horizons and the layers
//! built on them, hillshades, combined), on the array's own grid.

use crate::arrays::{bands_f32, heights as heights_array, image_f32};
use crate::errors::{argument, invalid};
use crate::options;
use crate::terrain::{flip_rows, height_field};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::{HeightField, Surface};
use relief_shade::horizon::HorizonParams;
use relief_shade::shade_map::{
    shade_map, InsolationSun, ShadeLayer, ShadeMap, ShadeMapParams, SkyModel, SunPosition,
};
use relief_shade::solar;
use relief_trace::{build_tracer, TracerKind};
use std::sync::Arc;

/// The shade layers of a height field, each a float32 array shaped like ``heights``.
///
/// ``heights``, ``spacing``, ``origin``, ``z_scale``, ``surface`` and ``voids`` place and read
/// the terrain as ``render`` does (row 0 the north edge; NaN a void). ``layers``: any of
/// ``"shadow"`` (the fraction of the suns each sample sees, cast shadows exact), ``"sky"`` (the
/// sky-view factor from exact horizons), ``"hillshade"`` (Lambert's cosine with Horn's
/// gradient, as ``gdaldem hillshade``), ``"combined"`` (the map layer), ``"horizon"`` (the
/// horizon's elevation angle in degrees in each of ``azimuths`` directions from north: a
/// ``(azimuths, rows, columns)`` array), ``"sky-aniso"`` (RVT's anisotropic sky-view factor),
/// ``"openness-pos"`` and ``"openness-neg"`` (degrees), ``"sky-illumination"`` (an
/// ``sky_model`` sky, ``"overcast"`` or ``"uniform"``, with the suns' shadows),
/// ``"hillshade-multi"`` (``gdaldem -multidirectional``), ``"insolation"`` (Wh/m²) and
/// ``"sun-hours"`` (see ``insolation``). ``suns``: a sequence of ``(azimuth, elevation)`` in
/// degrees, azimuth clockwise from north, elevation above 0; ``sun_radius``: each sun's
/// angular radius in degrees, sampled by ``sun_rays`` rays. The horizons: ``azimuths``
/// directions, seen ``observer_height`` metres above each sample, to ``radius`` metres (None:
/// the edge of the data), with ``earth_curvature`` the refraction coefficient of the earth's
/// curvature (None: a flat earth). The sun from place and time (NREL's solar position
/// algorithm), as ``relief shade``'s ``--date``: ``date`` ``"YYYY-MM-DD"`` with ``time``
/// ``"HH:MM"`` places one sun (instead of ``suns``); ``date`` alone, or a range
/// ``"FROM..TO"``, is the period of ``"insolation"`` and ``"sun-hours"``, every ``step``
/// (``"15m"``); clocks ``timezone`` from UTC (``"+02:00"``, ``"Z"``), seen from ``latitude`` and
/// ``longitude`` in degrees (an array has no georeference: both are needed with ``date``).
/// ``threads``: how many threads shade (None: all the processor's, shared by the calls of
/// the process; ``relief.dask`` gives each task one); the result is the same for any.
///
/// Returns a dict from layer name to its array, in the order of ``layers``, NaN at a void of
/// ``heights``, exactly as ``relief shade`` computes it.
///
/// Raises ``relief.ReliefError`` (a ``ValueError``) for arrays or options relief cannot use.
#[pyfunction]
#[pyo3(signature = (
    heights, spacing=None, *, origin=None, z_scale=1.0, layers=vec!["combined".to_string()],
    suns=vec![(315.0, 45.0)], sun_radius=0.0, sun_rays=16, azimuths=32, observer_height=0.01,
    radius=None, earth_curvature=None, sky_model="overcast", date=None, time=None,
    timezone="Z", step="15m", latitude=None, longitude=None, surface="triangles", voids="fill", threads=None
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
    voids: &str,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let geometry = options::geometry(spacing, origin, z_scale)?;
    let surface = options::surface(surface)?;
    let voids = options::voids(voids)?;
    let horizon = HorizonParams { azimuths, observer_height, radius, refraction: earth_curvature };
    let when = SunTime { date, time, timezone, step, latitude, longitude };
    let params = map_params(layers, suns, sun_radius, sun_rays, horizon, sky_model, &when)?;
    params.check_surface(surface).map_err(argument)?;
    let grid = heights_array(heights)?;

    let map = py.detach(|| {
        crate::options::on_threads(threads, || {
            let void: Vec<bool> =
                flip_rows(&grid.samples, grid.width).iter().map(|v| v.is_nan()).collect();
            let field = height_field(&grid, geometry, voids)?;
            let mask = void.contains(&true).then_some(void.as_slice());
            shade_field(&field, surface, mask, &params)
        })
    })?;
    layer_arrays(py, map.map_err(invalid)?)
}

/// When and where the sun shines, as `relief.shade`'s keywords give it.
pub struct SunTime<'a> {
    /// `YYYY-MM-DD` or `FROM..TO`.
    pub date: Option<&'a str>,
    /// `HH:MM`, for one instant.
    pub time: Option<&'a str>,
    /// The clocks' offset from UTC.
    pub timezone: &'a str,
    /// The time step over a period.
    pub step: &'a str,
    /// Degrees north.
    pub latitude: Option<f64>,
    /// Degrees east.
    pub longitude: Option<f64>,
}

impl SunTime<'_> {
    /// The sun of one instant (`Some`, with a time) or the suns of the period (without), by
    /// NREL's solar position algorithm; neither without a date.
    fn suns(&self) -> Result<(Option<SunPosition>, Vec<InsolationSun>), String> {
        let Some(date) = self.date else {
            if self.time.is_some() || self.latitude.is_some() || self.longitude.is_some() {
                return Err("time, latitude and longitude need a date".to_string());
            }
            return Ok((None, Vec::new()));
        };
        let (Some(latitude), Some(longitude)) = (self.latitude, self.longitude) else {
            return Err(
                "a date needs latitude and longitude (an array has no georeference)".to_string()
            );
        };
        let e = |e: relief_shade::ShadeError| e.to_string();
        let days = solar::parse_date_range(date).map_err(e)?;
        let offset = solar::parse_timezone(self.timezone).map_err(e)?;
        let observer = solar::Observer::at(latitude, longitude);
        match self.time {
            Some(time) => {
                if days.first != days.last {
                    return Err(format!("time {time} asks for one instant, not the range {date}"));
                }
                let instant = solar::UtcInstant::from_civil(
                    days.first,
                    solar::parse_time(time).map_err(e)?,
                    offset,
                );
                let sun = solar::solar_position(instant, &observer).map_err(e)?;
                if sun.apparent_elevation_deg <= 0.0 {
                    return Err(format!(
                        "the sun is below the horizon at {} (elevation {:.2} degrees)",
                        instant.local_text(offset),
                        sun.apparent_elevation_deg
                    ));
                }
                let position = SunPosition {
                    azimuth_deg: sun.azimuth_deg,
                    elevation_deg: sun.apparent_elevation_deg,
                };
                Ok((Some(position), Vec::new()))
            }
            None => {
                let step = solar::parse_step(self.step).map_err(e)?;
                let suns = solar::sun_samples_over(days, offset, step, &observer).map_err(e)?;
                Ok((None, suns))
            }
        }
    }
}

/// The shade map's parameters: the `layers` by name, the `suns` as (azimuth, elevation) in
/// degrees, each of `sun_radius` degrees sampled by `sun_rays` rays, the `horizon`'s, the
/// `sky_model` by name and the sun of `when` (replacing `suns` for one instant, or the
/// insolation suns of a period); checked as `relief shade` checks them.
pub fn map_params(
    layers: Vec<String>,
    suns: Vec<(f64, f64)>,
    sun_radius: f64,
    sun_rays: u32,
    horizon: HorizonParams,
    sky_model: &str,
    when: &SunTime<'_>,
) -> PyResult<ShadeMapParams> {
    let layers = layers
        .iter()
        .map(|name| name.parse::<ShadeLayer>().map_err(invalid))
        .collect::<PyResult<Vec<_>>>()?;
    let (instant, insolation) = when.suns().map_err(invalid)?;
    let suns = match instant {
        Some(sun) => vec![sun],
        None => suns
            .into_iter()
            .map(|(azimuth_deg, elevation_deg)| SunPosition { azimuth_deg, elevation_deg })
            .collect(),
    };
    let params = ShadeMapParams {
        layers,
        suns,
        sun_radius_deg: sun_radius,
        sun_rays,
        horizon,
        sky_model: sky_model.parse::<SkyModel>().map_err(invalid)?,
        insolation,
        ..ShadeMapParams::default()
    };
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
    let (width, height) = (map.width, map.height);
    let mut horizon = Vec::new();
    for band in map.bands {
        // relief's rows run south to north; the caller's array runs north to south.
        let north_up = flip_rows(&band.values, width);
        if band.layer == ShadeLayer::Horizon {
            horizon.extend(north_up);
        } else {
            result.set_item(band.layer.name(), image_f32(py, height, width, north_up)?)?;
        }
    }
    if !horizon.is_empty() {
        let bands = horizon.len() / (width * height).max(1);
        result
            .set_item(ShadeLayer::Horizon.name(), bands_f32(py, bands, height, width, horizon)?)?;
    }
    Ok(result)
}
