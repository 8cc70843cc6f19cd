//! `relief.sun_position`: the sun's azimuth and elevation seen from a place at a sequence of
//! instants, by NREL's solar position algorithm (relief_shade::solar).

use crate::arrays::vector_f64;
use crate::errors::{argument, invalid};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use rayon::prelude::*;
use relief_shade::solar::{parse_iso8601_instant, solar_position, Observer, UtcInstant};

/// What `times` may hold, for messages.
const TIMES_ARE: &str = "ISO-8601 strings with an offset (\"2026-06-21T09:30:00+02:00\"), \
                         timezone-aware datetimes or numpy datetime64 values (UTC)";

/// The sun seen from ``latitude``, ``longitude`` (degrees, north and east positive) at each
/// of ``times``: ISO-8601 strings with an offset (``"2026-06-21T09:30:00+02:00"``, ``Z`` for
/// UTC), timezone-aware ``datetime`` objects, or numpy ``datetime64`` values (taken as UTC).
/// ``elevation`` in metres above the ellipsoid, ``pressure`` in millibars and
/// ``temperature`` in degrees Celsius (for refraction), ``delta_t`` TT - UT1 in seconds, with
/// pvlib's defaults.
///
/// Returns a dict of float64 arrays, one value per time in order: ``azimuth`` (degrees
/// clockwise from north), ``elevation`` (the topocentric elevation without refraction) and
/// ``apparent_elevation`` (with it), by NREL's solar position algorithm (Reda & Andreas 2004).
///
/// Raises ``relief.ReliefError`` for a time that cannot be read or a parameter out of range.
#[pyfunction]
#[pyo3(signature = (
    latitude, longitude, times, *, elevation=0.0, pressure=1013.25, temperature=12.0,
    delta_t=67.0
))]
#[allow(clippy::too_many_arguments)]
pub fn sun_position<'py>(
    py: Python<'py>,
    latitude: f64,
    longitude: f64,
    times: &Bound<'py, PyAny>,
    elevation: f64,
    pressure: f64,
    temperature: f64,
    delta_t: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let observer = Observer {
        latitude_deg: latitude,
        longitude_deg: longitude,
        elevation_m: elevation,
        pressure_mbar: pressure,
        temperature_c: temperature,
        delta_t_s: delta_t,
    };
    observer.validate().map_err(argument)?;
    let instants = instants(py, times)?;
    let positions = py.detach(|| {
        instants
            .par_iter()
            .map(|&instant| solar_position(instant, &observer))
            .collect::<Result<Vec<_>, _>>()
    });
    let positions = positions.map_err(argument)?;
    let dict = PyDict::new(py);
    let column = |f: fn(&relief_shade::solar::SolarPosition) -> f64| {
        vector_f64(py, positions.iter().map(f).collect())
    };
    dict.set_item("azimuth", column(|p| p.azimuth_deg))?;
    dict.set_item("elevation", column(|p| p.elevation_deg))?;
    dict.set_item("apparent_elevation", column(|p| p.apparent_elevation_deg))?;
    Ok(dict)
}

/// The instants of `times`, flattened in order.
fn instants(py: Python<'_>, times: &Bound<'_, PyAny>) -> PyResult<Vec<UtcInstant>> {
    if times.is_instance_of::<PyString>() {
        return Err(invalid(format!("times must be a sequence of {TIMES_ARE}, not one string")));
    }
    let numpy = py.import("numpy")?;
    let array = numpy
        .call_method1("asarray", (times,))
        .map_err(|e| invalid(format!("times must be a sequence of {TIMES_ARE}: {e}")))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let flat = array.call_method0("ravel")?;
    if flat.len()? == 0 {
        return Ok(Vec::new());
    }
    if kind == "M" {
        // datetime64 of any unit, as microseconds since 1970 (NaT is the smallest int64).
        let micros = flat.call_method1("astype", ("datetime64[us]",))?;
        let micros: Vec<i64> =
            micros.call_method1("astype", ("int64",))?.call_method0("tolist")?.extract()?;
        return micros
            .iter()
            .enumerate()
            .map(|(i, &us)| {
                if us == i64::MIN {
                    Err(invalid(format!("times[{i}] is NaT, not a time")))
                } else {
                    Ok(UtcInstant::from_unix_seconds(us as f64 / 1e6))
                }
            })
            .collect();
    }
    if !matches!(kind.as_str(), "U" | "O") {
        return Err(invalid(format!(
            "times must be a sequence of {TIMES_ARE}, got an array of dtype {}",
            array.getattr("dtype")?.str()?
        )));
    }
    let items: Vec<Bound<'_, PyAny>> = flat.call_method0("tolist")?.extract()?;
    items.iter().enumerate().map(|(i, item)| instant_of(i, item)).collect()
}

/// Item `i` of `times`: an ISO-8601 string with an offset or a timezone-aware datetime.
fn instant_of(i: usize, item: &Bound<'_, PyAny>) -> PyResult<UtcInstant> {
    if let Ok(text) = item.extract::<String>() {
        return parse_iso8601_instant(&text).map_err(|e| invalid(format!("times[{i}]: {e}")));
    }
    if item.hasattr("utcoffset")? && item.hasattr("timestamp")? {
        if item.call_method0("utcoffset")?.is_none() {
            return Err(invalid(format!(
                "times[{i}] ({}) has no timezone: give it a tzinfo, or an offset in an ISO-8601 string",
                item.str()?
            )));
        }
        let seconds: f64 = item.call_method0("timestamp")?.extract()?;
        return Ok(UtcInstant::from_unix_seconds(seconds));
    }
    Err(invalid(format!("times[{i}] ({}) is not one of {TIMES_ARE}", item.repr()?)))
}
