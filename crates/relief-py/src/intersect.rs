//! `relief.intersect`: the tracer's first hits of an array of rays, in relief's world.

use crate::arrays::{check_finite_rows, heights as heights_array, vector_f64, vectors};
use crate::errors::invalid;
use crate::options;
use crate::terrain::height_field;
use numpy::PyArray1;
use pyo3::prelude::*;
use rayon::prelude::*;
use relief_core::{DVec3, Ray};
use relief_render::{TracerChoice, TracerSpec};

/// Rays traced together as one batch (neighbouring rays gain from the mipmap tracer's
/// packets).
const BATCH: usize = 64;

/// The first hit of every ray with the surface of a height field.
///
/// ``heights``, ``spacing``, ``origin``, ``z_scale``, ``surface``, ``tracer`` and ``voids``
/// place and read the terrain as ``render`` does (row 0 of ``heights`` the north edge), in
/// relief's world: x east, y north, z up; the sample of array row r (from the north), column
/// c of an R-row grid sits at (x0 + (c + 0.5) dx, y0 + (R - 1 - r + 0.5) dy, h z_scale).
/// ``origins`` and ``directions``: arrays of shape (N, 3) of any real dtype; a direction need
/// not be unit, but must not be zero.
///
/// Returns ``t``, a float64 array of shape (N,): the ray parameter of the first hit, so that
/// the hit is at ``origins + t[:, None] * directions`` (the distance when the directions are
/// unit), 0 for a ray that starts inside the terrain's solid, +inf for a miss.
///
/// Raises ``relief.ReliefError`` (a ``ValueError``) for arrays or options relief cannot use.
#[pyfunction]
#[pyo3(signature = (
    heights, origins, directions, spacing=None, *, origin=None, z_scale=1.0,
    surface="triangles", tracer="mipmap", voids="fill"
))]
#[allow(clippy::too_many_arguments)]
pub fn intersect<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    spacing: Option<&Bound<'py, PyAny>>,
    origin: Option<(f64, f64)>,
    z_scale: f64,
    surface: &str,
    tracer: &str,
    voids: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let geometry = options::geometry(spacing, origin, z_scale)?;
    let (surface, kind) = (options::surface(surface)?, options::tracer(tracer)?);
    let voids = options::voids(voids)?;
    let grid = heights_array(heights)?;
    let starts = vectors(origins, "origins")?;
    let dirs = vectors(directions, "directions")?;
    if starts.len() != dirs.len() {
        return Err(invalid(format!(
            "origins and directions must have the same number of rays, got {} and {}",
            starts.len() / 3,
            dirs.len() / 3
        )));
    }
    let t = py.detach(|| {
        check_finite_rows(&starts, "origins")?;
        check_finite_rows(&dirs, "directions")?;
        if let Some(k) = dirs.chunks_exact(3).position(|d| d.iter().all(|&x| x == 0.0)) {
            return Err(format!("directions: row {k} is zero, not a direction"));
        }
        let field = height_field(&grid, geometry, voids)?;
        let spec = TracerSpec::new(TracerChoice::Plain(kind), surface);
        let tracer = spec.build(&field).map_err(|e| e.to_string())?;
        let mut t = vec![f64::INFINITY; starts.len() / 3];
        let (starts, dirs) = (starts.par_chunks(3 * BATCH), dirs.par_chunks(3 * BATCH));
        starts.zip(dirs).zip(t.par_chunks_mut(BATCH)).for_each(|((starts, dirs), t)| {
            let rays: Vec<Ray> = starts
                .chunks_exact(3)
                .zip(dirs.chunks_exact(3))
                .map(|(o, d)| Ray::new(DVec3::from_slice(o), DVec3::from_slice(d)))
                .collect();
            let mut hits = vec![None; rays.len()];
            let mut steps = vec![0; rays.len()];
            tracer.intersect_batch(&rays, &mut hits, &mut steps);
            for (t, hit) in t.iter_mut().zip(hits) {
                *t = hit.map_or(f64::INFINITY, |h| h.t);
            }
        });
        Ok(t)
    });
    Ok(vector_f64(py, t.map_err(invalid)?))
}
