//! `relief.render`: a heights array traced, shaded and tone-mapped as `relief render` does,
//! returned as an RGB image and its depth.

use crate::arrays::{heights as heights_array, image_f32, image_rgb8};
use crate::camera::CameraSpec;
use crate::errors::{argument, invalid};
use crate::options;
use crate::terrain::height_field;
use crate::tracer::tracer as build;
use numpy::{PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::Surface;
use relief_shade::{render_to_srgb8, sun_shadow_sweep, KeptHits, ShadingParams, Sun};
use relief_trace::Tracer;

/// What `render` returns: the RGB image and its depth.
type Rendered<'py> = (Bound<'py, PyArray3<u8>>, Bound<'py, PyArray2<f32>>);

/// Bytes an image takes per pixel while it is rendered (as the command line counts them): the
/// G-buffer (56), the linear radiance (12) and the 8-bit output (3).
const BYTES_PER_PIXEL: u64 = 71;

/// Renders a height field as ``relief render`` does, with the same defaults.
///
/// ``heights``: a 2-D array of any real dtype, row 0 the north edge (as ``read`` returns it),
/// NaN for voids. ``spacing``: the texel size, a number or ``(dx, dy)``, or the georeference
/// dict ``read`` returns (its spacing and origin), so that ``render(*read(path))`` works.
/// ``origin``: the world ``(x, y)`` of the grid's south-west corner (default 0, 0, or the
/// dict's). ``z_scale`` multiplies the heights. ``camera``: ``None`` for relief's framing (a
/// three-quarter view from the south-west), or a dict of ``eye`` and ``target`` (x, y, z),
/// ``up`` (default 0, 0, 1) and ``fov`` (vertical, degrees, default 45); a dict of ``fov``
/// alone frames automatically with that field of view. ``size``: ``(width, height)`` in
/// pixels. ``surface``: ``"triangles"`` or ``"boxes"``; ``tracer``: ``"mipmap"`` or
/// ``"naive"``. ``sun``: ``(azimuth, elevation)`` in degrees; ``shadows``; ``exposure``;
/// ``voids``: ``"fill"`` or ``"hole"``.
///
/// Returns ``(rgb, depth)``: ``rgb`` a uint8 array (height, width, 3), ``depth`` a float32
/// array (height, width), row 0 the image's top row, the distance from the eye to the first
/// hit along each pixel's unit ray, +inf for a miss.
///
/// Raises ``relief.ReliefError`` (a ``ValueError``) for an array or option relief cannot use,
/// with the command line's message.
#[pyfunction]
#[pyo3(signature = (
    heights, spacing=None, *, origin=None, z_scale=1.0, camera=None, size=(1280, 720),
    surface="triangles", tracer="mipmap", sun=(315.0, 35.0), shadows=true, exposure=1.0,
    voids="fill"
))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    spacing: Option<&Bound<'py, PyAny>>,
    origin: Option<(f64, f64)>,
    z_scale: f64,
    camera: Option<&Bound<'py, PyDict>>,
    size: (i64, i64),
    surface: &str,
    tracer: &str,
    sun: (f64, f64),
    shadows: bool,
    exposure: f64,
    voids: &str,
) -> PyResult<Rendered<'py>> {
    let (width, height) = options::image_size(size)?;
    check_image(width, height)?;
    let geometry = options::geometry(spacing, origin, z_scale)?;
    let (surface, kind) = (options::surface(surface)?, options::tracer(tracer)?);
    let ((azimuth_deg, elevation_deg), exposure) =
        (options::sun(sun)?, options::exposure(exposure)?);
    let voids = options::voids(voids)?;
    let spec = CameraSpec::from_dict(camera)?;
    let grid = heights_array(heights)?;

    let field = py.detach(|| height_field(&grid, geometry, voids)).map_err(invalid)?;
    drop(grid);
    let camera = spec.camera(py, &field.world_bounds(surface), width, height)?;
    let mut params =
        ShadingParams::for_terrain(&field.world_bounds(Surface::Boxes)).map_err(argument)?;
    params.sun = Sun { azimuth_deg, elevation_deg, ..params.sun };
    params.shadows = shadows;
    params.exposure = exposure;
    params.validate().map_err(argument)?;

    let traced = py.detach(|| {
        let tracer = build(&field, surface, kind);
        let bounds = field.world_bounds(surface);
        let keep = KeptHits { depth: true, normals: false };
        let pixels = camera.width() as usize * camera.height() as usize;
        let sweep = sun_shadow_sweep(tracer.as_ref(), &field, surface, &params, pixels);
        let shadow_tracer: &dyn Tracer = match &sweep {
            Some(sweep) => sweep,
            None => tracer.as_ref(),
        };
        let drawn = render_to_srgb8(
            tracer.as_ref(),
            shadow_tracer,
            &camera,
            &bounds,
            &params,
            keep,
            &|_| {},
        )?;
        let depth = drawn.depth.unwrap_or_default();
        Ok::<_, relief_shade::ShadeError>((drawn.rgb.into_flattened(), depth))
    });
    let (rgb, depth) = traced.map_err(argument)?;
    let (w, h) = (width as usize, height as usize);
    Ok((image_rgb8(py, h, w, rgb)?, image_f32(py, h, w, depth)?))
}

/// Refuses an image of `width x height` pixels that would not fit the default memory budget
/// (half the machine's memory), with the command line's message.
fn check_image(width: u32, height: u32) -> PyResult<()> {
    let budget = relief_io::default_memory_budget();
    let needed = width as u64 * height as u64 * BYTES_PER_PIXEL;
    if needed > budget.bytes {
        return Err(invalid(format!(
            "a {width}x{height} image needs {} MiB, over the {} MiB memory limit ({})",
            needed >> 20,
            budget.bytes >> 20,
            budget.source
        )));
    }
    Ok(())
}
