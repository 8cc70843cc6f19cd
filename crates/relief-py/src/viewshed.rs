//! `relief.viewshed`: which samples of a heights array an observer sees, or how many of
//! several observers see each one, on the array's own grid.

use crate::arrays::{heights as heights_array, image_f32};
use crate::errors::{argument, invalid};
use crate::options;
use crate::terrain::{flip_rows, height_field};
use numpy::PyArray2;
use pyo3::prelude::*;
use relief_shade::viewshed::DEFAULT_OBSERVER_HEIGHT;
use relief_shade::viewshed::{viewshed as viewshed_of, Observer, ViewshedParams};
use relief_trace::{build_tracer, TracerKind};

/// The viewshed of ``observers`` over ``heights``: a float32 array shaped like it.
///
/// ``heights``, ``spacing``, ``origin``, ``z_scale``, ``surface`` and ``voids`` place and read
/// the terrain as ``shade`` does (row 0 the north edge; NaN a void). ``observers``: a sequence
/// of ``(x, y)`` or ``(x, y, height)`` in the terrain's world coordinates (``origin`` the
/// south-west corner; with neither ``spacing`` nor ``origin`` the first sample of the last
/// row is at ``(0.5, 0.5)``), ``height`` the eye above the ground in metres (1.7 unless
/// given). ``target_height``: the target above the ground at each sample; ``radius``: the
/// horizontal distance beyond which an observer sees nothing (``None``: no limit).
///
/// Returns, per sample, the number of observers that see it (0 or 1 for one), NaN at a void,
/// exactly as ``relief viewshed`` computes it.
///
/// Raises ``relief.ReliefError`` (a ``ValueError``) for arrays or options relief cannot use:
/// no observer, one outside the terrain or on a void, a negative or NaN height.
#[pyfunction]
#[pyo3(signature = (
    heights, spacing=None, *, origin=None, z_scale=1.0, observers=Vec::new(),
    target_height=0.0, radius=None, surface="triangles", voids="fill"
))]
#[allow(clippy::too_many_arguments)]
pub fn viewshed<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    spacing: Option<&Bound<'py, PyAny>>,
    origin: Option<(f64, f64)>,
    z_scale: f64,
    observers: Vec<Vec<f64>>,
    target_height: f64,
    radius: Option<f64>,
    surface: &str,
    voids: &str,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let geometry = options::geometry(spacing, origin, z_scale)?;
    let surface = options::surface(surface)?;
    let voids = options::voids(voids)?;
    let observers = observers
        .iter()
        .map(|o| match o.as_slice() {
            &[x, y] => Ok(Observer::new(x, y, DEFAULT_OBSERVER_HEIGHT)),
            &[x, y, height] => Ok(Observer::new(x, y, height)),
            other => Err(invalid(format!(
                "an observer is (x, y) or (x, y, height), not {} numbers",
                other.len()
            ))),
        })
        .collect::<PyResult<Vec<_>>>()?;
    let params = ViewshedParams { observers, target_height, radius };
    params.validate().map_err(argument)?;
    let grid = heights_array(heights)?;

    let result = py.detach(|| {
        let void: Vec<bool> =
            flip_rows(&grid.samples, grid.width).iter().map(|v| v.is_nan()).collect();
        let field = height_field(&grid, geometry, voids)?;
        let mask = void.contains(&true).then_some(void.as_slice());
        let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
        viewshed_of(&field, &*tracer, mask, &params, &|_| {}).map_err(|e| e.to_string())
    });
    let result = result.map_err(invalid)?;
    // relief's rows run south to north; the caller's array runs north to south.
    let north_up = flip_rows(&result.counts, result.width);
    image_f32(py, result.height, result.width, north_up)
}
