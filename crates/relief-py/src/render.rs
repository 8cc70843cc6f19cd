//! `relief.render`: a heights array opened as a height-field scene of the scene layer and
//! drawn as `relief render` draws it, returned as an RGB image and its depth.

use crate::arrays::heights as heights_array;
use crate::camera::{CameraSpec, ARRAY_KEYS};
use crate::errors::{argument, invalid};
use crate::options;
use crate::picture::{arrays, check_image, Rendered};
use crate::terrain::height_field;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::Surface;
use relief_render::scenes::height_field::{
    legend_colours, shading, shading_normals as shading_normals_of,
};
use relief_render::{
    memory, HeightFieldScene, HybridSettings, ImageHolding, KeptHits, LightSettings,
    SafetySettings, Scene, Silent, TracerChoice,
};

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
/// ``voids``: ``"fill"`` or ``"hole"``. ``colormap``: ``"terrain"`` (the default look),
/// ``"bathymetry"`` (blues below ``sea_level``, default 0 m, land colours above),
/// ``"greys"``, ``"viridis"``, ``"cividis"`` or ``"magma"``, over ``height_range`` ``(min,
/// max)`` in metres before ``z_scale`` (default: the terrain's own). ``legend``,
/// ``scale_bar`` and ``north_arrow`` draw that furniture over the picture as ``relief
/// render --legend --scale-bar --north-arrow`` does (a scale bar needs an orthographic camera,
/// which ``relief.open(...).render`` takes). ``shading_normals``: ``"smooth"`` (the
/// default for ``"triangles"``: normals interpolated from the heights' gradients, no facets
/// show) or ``"faceted"`` (each triangle's exact normal); ``"boxes"`` are always faceted and
/// refuse ``"smooth"``; the depth is exact either way. ``aa``: anti-aliasing, ``"adaptive"`` (one
/// ray a pixel, then 4 in the pixels on edges), ``"off"``, or N for N x N rays in every
/// pixel (1 to 8); the depth stays that of each pixel's centre ray.
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
    voids="fill", colormap=None, height_range=None, sea_level=None, legend=false,
    scale_bar=false, north_arrow=false, aa=None, shading_normals=None
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
    colormap: Option<&str>,
    height_range: Option<(f64, f64)>,
    sea_level: Option<f64>,
    legend: bool,
    scale_bar: bool,
    north_arrow: bool,
    aa: Option<&Bound<'py, PyAny>>,
    shading_normals: Option<&str>,
) -> PyResult<Rendered<'py>> {
    let (width, height) = options::image_size(size)?;
    let aa = aa.map(options::antialiasing).transpose()?.unwrap_or_default();
    let holding = ImageHolding::Strips { depth: true, normals: false };
    check_image(width, height, holding, aa, None, None)?;
    let geometry = options::geometry(spacing, origin, z_scale)?;
    let (surface, kind) = (options::surface(surface)?, options::tracer(tracer)?);
    let light = LightSettings {
        sun: options::sun(sun)?,
        no_shadows: !shadows,
        exposure: options::exposure(exposure)?,
        texture: None,
        colours: options::colours(colormap, height_range, sea_level)?,
        shading_normals: shading_normals.map(options::shading_normals).transpose()?,
    };
    let furniture = options::furniture(legend, scale_bar, north_arrow);
    let voids = options::voids(voids)?;
    let spec = CameraSpec::from_dict(camera, ARRAY_KEYS)?;
    let grid = heights_array(heights)?;

    let field = py.detach(|| height_field(&grid, geometry, voids)).map_err(invalid)?;
    drop(grid);
    let bounds = field.world_bounds(Surface::Boxes);
    // The colours' metres are the file's heights before the exaggeration `z_scale`.
    let mut params = shading(&light, &bounds, z_scale).map_err(argument)?;
    params.normals =
        shading_normals_of(light.shading_normals, surface, &field).map_err(argument)?;
    let colours = legend_colours(&light, &bounds, z_scale).map_err(argument)?;
    let scene = Scene::HeightField(HeightFieldScene {
        field,
        surface,
        choice: TracerChoice::Plain(kind),
        safety: SafetySettings::default(),
        hybrid: HybridSettings::default(),
        max_memory: memory::budget(None).bytes,
        params,
        normal_style: light.shading_normals,
        colours,
        warnings: Vec::new(),
    });
    let camera = spec.camera(py, &scene.bounds(), width, height)?;
    let keep = KeptHits { depth: true, normals: false };
    furniture.check(&camera, colours.as_ref()).map_err(argument)?;
    let mut picture = py.detach(|| scene.render(&camera, keep, aa, &Silent)).map_err(argument)?;
    furniture.draw(&mut picture, &camera, colours.as_ref()).map_err(argument)?;
    arrays(py, picture)
}
