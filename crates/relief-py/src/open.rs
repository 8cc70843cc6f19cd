//! `relief.open`: any input relief takes opened as a scene by the scene layer, with the
//! options of `relief render` given as keyword arguments.

use crate::errors::{invalid, scene as scene_error};
use crate::info::height_file_crs;
use crate::options;
use crate::scene::{Opened, PyScene};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_io::LengthUnit;
use relief_render::input::InputKind;
use relief_render::{RenderMode, Scene, SceneOptions, TracerChoice};
use relief_shade::mlhm::MlhmPreset;
use std::path::PathBuf;

/// The options `open` takes, as `relief render`'s (with underscores for dashes).
const KEYS: [&str; 30] = [
    "spacing",
    "north_up",
    "z_scale",
    "voids",
    "max_memory",
    "png_encoding",
    "array",
    "z_unit",
    "fbm_size",
    "seed",
    "surface",
    "tracer",
    "mode",
    "sigma",
    "preset",
    "ao",
    "tau",
    "voxel_height",
    "max_error_px",
    "cache_mb",
    "sun",
    "shadows",
    "exposure",
    "texture",
    "cache_dir",
    "no_cache",
    "colormap",
    "height_range",
    "sea_level",
    "shading_normals",
];

/// Opens an input as a scene, as ``relief render`` opens it: a height file (.tif, .tiff,
/// .hgt, .asc, .png, .npy, .npz), an MLHM scene (the reference simulator's .json with its
/// .dat, or a .mlhm), a material-stacks file (.stacks), a tile store (a folder made by
/// ``relief tile``), or, with ``path=None``, the default fBm terrain.
///
/// The keyword options are ``relief render``'s, with the same defaults and ranges:
///
/// - reading and placing: ``spacing`` (a number or ``(dx, dy)``; default the file's
///   georeference, else 1), ``north_up``, ``z_scale``, ``voids`` (``"fill"`` or
///   ``"hole"``), ``max_memory`` (bytes), ``png_encoding``, ``array`` (of an .npz),
///   ``z_unit`` (``"m"``, ``"ft"``, ``"us-ft"``); the fBm terrain's ``fbm_size`` and
///   ``seed``;
/// - drawing: ``surface`` (``"triangles"`` or ``"boxes"``), ``tracer`` (``"mipmap"``,
///   ``"naive"``, ``"safety"`` or a safety variant such as ``"cyl_all+cone_all"``,
///   ``"hybrid"``, ``"clipmap"``, ``"hierarchy"`` for MLHM scenes), ``mode`` (``"boxes"``,
///   ``"smooth"`` or ``"mesh"``), ``sigma`` (metres), ``preset`` (``"low"``, ``"mid"``,
///   ``"high"``, ``"max"``), ``ao`` (an MLHM preset's ambient occlusion, default True),
///   ``tau`` and ``voxel_height`` (meshes), ``max_error_px`` and ``cache_mb`` (tile stores),
///   ``cache_dir`` and ``no_cache`` (the safety shapes' cache);
/// - light: ``sun`` (``(azimuth, elevation)`` in degrees), ``shadows`` (default True),
///   ``exposure``, ``texture`` (a PNG draped over the terrain);
/// - colours of a height field or tile store: ``colormap`` (``"terrain"``, the default,
///   ``"bathymetry"``, ``"greys"``, ``"viridis"``, ``"cividis"``, ``"magma"``),
///   ``height_range`` (``(min, max)`` in metres before ``z_scale``; default the terrain's
///   own) and ``sea_level`` (``bathymetry``'s, metres, default 0); ``shading_normals``
///   (``"smooth"``, the default for the triangles surface, or ``"faceted"``; boxes are
///   always faceted and refuse ``"smooth"``).
///
/// Returns a ``relief.Scene``. Raises ``relief.ReliefError`` (a ``ValueError``) for an
/// option relief cannot use or that does not apply, ``OSError`` (``FileNotFoundError``, ...)
/// for an input that cannot be read. The GIL is released while the input is read.
#[pyfunction]
#[pyo3(signature = (path=None, **options))]
pub fn open(
    py: Python<'_>,
    path: Option<PathBuf>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyScene> {
    let empty = PyDict::new(py);
    let given = options.unwrap_or(&empty);
    let scene_options = scene_options(given)?;
    if path.is_some() {
        for key in ["fbm_size", "seed"] {
            if given.contains(key)? {
                return Err(invalid(format!(
                    "{key} applies to the default fBm terrain (path=None), not to an input file"
                )));
            }
        }
    }
    let max_memory = scene_options.terrain.read.max_memory;
    let opened = py.detach(|| {
        let scene = Scene::open(path.as_deref(), &scene_options)?;
        let crs = match (&path, InputKind::of(path.as_deref())) {
            (Some(path), InputKind::HeightFile) => {
                height_file_crs(path, &scene_options.terrain.read.read_options())
            }
            _ => None,
        };
        Ok::<_, relief_render::RenderError>(Opened {
            scene,
            path,
            max_memory,
            crs,
            simulation: None,
        })
    });
    Ok(PyScene::new(opened.map_err(scene_error)?))
}

/// The scene options `given` names (the defaults for the rest), each checked.
fn scene_options(given: &Bound<'_, PyDict>) -> PyResult<SceneOptions> {
    for key in given.keys() {
        let key: String = key.extract()?;
        if !KEYS.contains(&key.as_str()) {
            return Err(invalid(format!(
                "open: unknown option '{key}' (expected {})",
                KEYS.join(", ")
            )));
        }
    }
    let item = |key: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
        Ok(given.get_item(key)?.filter(|v| !v.is_none()))
    };
    let wrong = |key: &str, what: &str| invalid(format!("open: {key} must be {what}"));
    let number = |key: &str| -> PyResult<Option<f64>> {
        item(key)?.map(|v| v.extract::<f64>().map_err(|_| wrong(key, "a number"))).transpose()
    };
    let positive = |key: &str| -> PyResult<Option<f64>> {
        match number(key)? {
            Some(v) if !(v.is_finite() && v > 0.0) => Err(wrong(key, "a positive number")),
            v => Ok(v),
        }
    };
    let whole = |key: &str| -> PyResult<Option<u64>> {
        item(key)?
            .map(|v| v.extract::<u64>().map_err(|_| wrong(key, "a whole number >= 0")))
            .transpose()
    };
    let flag = |key: &str| -> PyResult<Option<bool>> {
        item(key)?.map(|v| v.extract::<bool>().map_err(|_| wrong(key, "True or False"))).transpose()
    };
    let text = |key: &str| -> PyResult<Option<String>> {
        item(key)?.map(|v| v.extract::<String>().map_err(|_| wrong(key, "a string"))).transpose()
    };
    let path = |key: &str| -> PyResult<Option<PathBuf>> {
        item(key)?.map(|v| v.extract::<PathBuf>().map_err(|_| wrong(key, "a path"))).transpose()
    };

    let mut o = SceneOptions::default();
    if let Some(spacing) = item("spacing")? {
        if spacing.cast::<PyDict>().is_ok() {
            return Err(wrong("spacing", "a number or (dx, dy)"));
        }
        let geometry = options::geometry(Some(&spacing), None, 1.0)?;
        o.terrain.spacing = Some((geometry.dx, geometry.dy));
    }
    o.terrain.north_up = flag("north_up")?.unwrap_or(false);
    if let Some(z) = number("z_scale")? {
        o.terrain.z_scale = options::geometry(None, None, z)?.z_scale;
    }
    o.terrain.fbm_size = whole("fbm_size")?.map(|n| n as usize);
    o.terrain.seed = whole("seed")?;
    let read = &mut o.terrain.read;
    read.voids = text("voids")?.map(|v| options::voids(&v)).transpose()?;
    read.max_memory = whole("max_memory")?;
    if read.max_memory == Some(0) {
        return Err(invalid("max_memory must be at least 1 byte"));
    }
    if let Some(name) = text("png_encoding")? {
        read.png_encoding = options::png_encoding(&name)?;
    }
    read.array = text("array")?;
    read.z_unit = text("z_unit")?.map(|u| u.parse::<LengthUnit>().map_err(invalid)).transpose()?;

    o.surface = text("surface")?.map(|s| options::surface(&s)).transpose()?;
    o.tracer = text("tracer")?.map(|t| t.parse::<TracerChoice>().map_err(invalid)).transpose()?;
    o.mode = text("mode")?.map(|m| mode(&m)).transpose()?;
    o.sigma = positive("sigma")?;
    o.mlhm.preset =
        text("preset")?.map(|p| p.parse::<MlhmPreset>().map_err(invalid)).transpose()?;
    o.mlhm.no_ao = !flag("ao")?.unwrap_or(true);
    o.mesh.tau_px = positive("tau")?;
    o.mesh.voxel_height = positive("voxel_height")?;
    if let Some(px) = positive("max_error_px")? {
        o.store.max_error_px = px;
    }
    if let Some(mb) = whole("cache_mb")? {
        o.store.cache_bytes = mb
            .checked_mul(1 << 20)
            .filter(|&b| b > 0)
            .ok_or_else(|| wrong("cache_mb", "a whole number of megabytes, at least 1"))?;
    }
    if let Some(sun) = item("sun")? {
        let pair: (f64, f64) = sun.extract().map_err(|_| wrong("sun", "(azimuth, elevation)"))?;
        o.light.sun = options::sun(pair)?;
    }
    o.light.no_shadows = !flag("shadows")?.unwrap_or(true);
    if let Some(exposure) = number("exposure")? {
        o.light.exposure = options::exposure(exposure)?;
    }
    o.light.texture = path("texture")?;
    let height_range = item("height_range")?
        .map(|v| v.extract::<(f64, f64)>().map_err(|_| wrong("height_range", "(min, max)")))
        .transpose()?;
    o.light.colours =
        options::colours(text("colormap")?.as_deref(), height_range, number("sea_level")?)?;
    o.light.shading_normals =
        text("shading_normals")?.map(|n| options::shading_normals(&n)).transpose()?;
    o.safety.cache_dir = path("cache_dir")?;
    o.safety.no_cache = flag("no_cache")?.unwrap_or(false);
    Ok(o)
}

/// How the columns (or stacks) are drawn, by name: `boxes`, `smooth` or `mesh`.
fn mode(name: &str) -> PyResult<RenderMode> {
    match name {
        "boxes" => Ok(RenderMode::Boxes),
        "smooth" => Ok(RenderMode::Smooth),
        "mesh" => Ok(RenderMode::Mesh),
        _ => Err(invalid(format!("unknown mode '{name}' (expected boxes, smooth or mesh)"))),
    }
}
