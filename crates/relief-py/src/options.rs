//! The options of the Python functions, each held to the range the relief command line holds
//! it to, with the command line's messages: placement (spacing, origin, z scale), surface,
//! tracer, voids, image size, sun and exposure, colour maps and map furniture.

use crate::errors::invalid;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::{DVec2, GridGeometry, Surface};
use relief_io::{PngEncoding, VoidPolicy};
use relief_render::{Antialiasing, ColourSettings, MapFurniture, TracerChoice};
use relief_shade::{ColourMap, NormalStyle};
use relief_trace::TracerKind;
use std::ops::RangeInclusive;

/// Texel spacing and height scale relief places grids with (as `relief --spacing`,
/// `--z-scale`).
pub const SCALE_RANGE: RangeInclusive<f64> = 1e-6..=1e7;

/// Largest distance from the origin, in metres, a coordinate may have on an axis (as the
/// command line's `--eye`, `--target`).
pub const MAX_COORDINATE: f64 = 1e9;

/// Vertical field of view in degrees (as `--fov`).
pub const FOV_RANGE: RangeInclusive<f64> = 0.01..=179.0;

/// Exposure before tone mapping (as `--exposure`).
pub const EXPOSURE_RANGE: RangeInclusive<f64> = 1e-4..=1e4;

/// Largest image side in pixels (as `--size`).
pub const MAX_IMAGE_SIDE: i64 = 32768;

/// A number for a message: plain decimals for everyday magnitudes, scientific notation for
/// the rest (as the command line prints them).
pub fn readable(v: f64) -> String {
    if v == 0.0 || (1e-4..1e9).contains(&v.abs()) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A range's ends as a reader wants them: `0.01..179`, `1e-6..10000000`.
fn range_text(range: &RangeInclusive<f64>) -> String {
    format!("{}..{}", readable(*range.start()), readable(*range.end()))
}

/// The grid geometry of `spacing` (a number, `(dx, dy)`, or the georeference dict `read`
/// returns, whose spacing, origin and `z_scale` (the metres in one unit of the file's
/// heights) are taken), `origin` (the south-west corner `(x, y)`, overriding the dict's) and
/// `z_scale` (multiplying the dict's).
pub fn geometry(
    spacing: Option<&Bound<'_, PyAny>>,
    origin: Option<(f64, f64)>,
    z_scale: f64,
) -> PyResult<GridGeometry> {
    let (mut dx, mut dy, mut corner) = (1.0, 1.0, DVec2::ZERO);
    let mut file_z = 1.0;
    if let Some(spacing) = spacing {
        if let Ok(georeference) = spacing.cast::<PyDict>() {
            let item = |key: &str| -> PyResult<(f64, f64)> {
                georeference
                    .get_item(key)?
                    .ok_or_else(|| invalid(format!("the georeference dict has no '{key}'")))?
                    .extract()
                    .map_err(|_| {
                        invalid(format!("georeference['{key}'] must be a pair of numbers"))
                    })
            };
            (dx, dy) = item("spacing")?;
            corner = DVec2::from(item("origin")?);
            // Heights in feet: the dict's z scale turns them into metres.
            if let Some(unit) = georeference.get_item("z_scale")? {
                file_z = unit
                    .extract()
                    .map_err(|_| invalid("georeference['z_scale'] must be a number"))?;
            }
        } else if let Ok(d) = spacing.extract::<f64>() {
            (dx, dy) = (d, d);
        } else {
            (dx, dy) = spacing.extract().map_err(|_| {
                invalid("spacing must be a number, a pair (dx, dy) or the georeference dict read() returns")
            })?;
        }
    }
    for d in [dx, dy] {
        if !SCALE_RANGE.contains(&d) {
            return Err(invalid(format!(
                "spacing {} must be positive, within {} world units",
                readable(d),
                range_text(&SCALE_RANGE)
            )));
        }
    }
    if let Some(origin) = origin {
        corner = DVec2::from(origin);
    }
    if !corner.is_finite() || corner.abs().max_element() > MAX_COORDINATE {
        return Err(invalid(format!(
            "origin ({}, {}) is farther than {} m from the world's origin on an axis",
            corner.x,
            corner.y,
            readable(MAX_COORDINATE)
        )));
    }
    if !SCALE_RANGE.contains(&z_scale) {
        return Err(invalid(format!(
            "z scale {} is outside {}",
            readable(z_scale),
            range_text(&SCALE_RANGE)
        )));
    }
    let z_scale = z_scale * file_z;
    if !SCALE_RANGE.contains(&z_scale) {
        return Err(invalid(format!(
            "z scale {} (z_scale times the georeference's) is outside {}",
            readable(z_scale),
            range_text(&SCALE_RANGE)
        )));
    }
    Ok(GridGeometry { dx, dy, z_scale, origin: corner })
}

/// The surface named `name`: `triangles` or `boxes`.
pub fn surface(name: &str) -> PyResult<Surface> {
    name.parse().map_err(invalid)
}

/// The tracer named `name` for the array functions (`render`, `intersect`): `mipmap` or
/// `naive`, parsed as the scene layer names tracers; the safety tracer (precomputed shapes
/// with their cache), the hybrid and clipmap renderers are `relief.open`'s.
pub fn tracer(name: &str) -> PyResult<TracerKind> {
    match name.parse::<TracerChoice>().map_err(invalid)? {
        TracerChoice::Plain(kind) => Ok(kind),
        _ => Err(invalid(format!(
            "the {name} tracer is not offered by the Python module's array functions \
             (expected naive or mipmap; relief.open takes every tracer relief render does)"
        ))),
    }
}

/// The anti-aliasing `aa` asks for: ``"adaptive"`` (the default), ``"off"``, or the side `N`
/// of a pixel's grid of samples, 1 to 8 (as `relief render --aa`).
pub fn antialiasing(aa: &Bound<'_, PyAny>) -> PyResult<Antialiasing> {
    let text = match aa.extract::<i64>() {
        Ok(n) => n.to_string(),
        Err(_) => aa.extract::<String>().map_err(|_| {
            invalid("aa must be \"adaptive\", \"off\" or a grid side N from 1 to 8")
        })?,
    };
    text.parse().map_err(invalid)
}

/// The void policy named `name`: `fill` (nearest valid sample, then smoothed, as the command
/// line does by default) or `hole` (empty texels the rays pass through).
pub fn voids(name: &str) -> PyResult<VoidPolicy> {
    match name {
        "fill" => Ok(VoidPolicy::Fill),
        "hole" => Ok(VoidPolicy::Hole),
        _ => Err(invalid(format!("unknown voids '{name}' (expected fill or hole)"))),
    }
}

/// The image size `(width, height)`, each side 1 to 32768 pixels.
pub fn image_size((width, height): (i64, i64)) -> PyResult<(u32, u32)> {
    for side in [width, height] {
        if !(1..=MAX_IMAGE_SIDE).contains(&side) {
            return Err(invalid(format!(
                "size: {side} in ({width}, {height}) is not an image dimension between 1 and \
                 {MAX_IMAGE_SIDE}"
            )));
        }
    }
    Ok((width as u32, height as u32))
}

/// The sun `(azimuth, elevation)` in degrees: azimuth clockwise from north, -360 to 360;
/// elevation -90 to 90.
pub fn sun((azimuth, elevation): (f64, f64)) -> PyResult<(f64, f64)> {
    if !(-360.0..=360.0).contains(&azimuth) {
        return Err(invalid(format!(
            "sun azimuth {} is outside -360..360 degrees",
            readable(azimuth)
        )));
    }
    if !(-90.0..=90.0).contains(&elevation) {
        return Err(invalid(format!(
            "sun elevation {} is outside -90..90 degrees",
            readable(elevation)
        )));
    }
    Ok((azimuth, elevation))
}

/// The exposure, within [`EXPOSURE_RANGE`].
pub fn exposure(exposure: f64) -> PyResult<f64> {
    if !EXPOSURE_RANGE.contains(&exposure) {
        return Err(invalid(format!(
            "exposure {} is outside {}",
            readable(exposure),
            range_text(&EXPOSURE_RANGE)
        )));
    }
    Ok(exposure)
}

/// The vertical field of view in degrees, within [`FOV_RANGE`].
pub fn fov(fov: f64) -> PyResult<f64> {
    if !FOV_RANGE.contains(&fov) {
        return Err(invalid(format!(
            "field of view {} is outside {} degrees",
            readable(fov),
            range_text(&FOV_RANGE)
        )));
    }
    Ok(fov)
}

/// How a PNG encodes heights, by name: `grey`, `terrain-rgb` or `terrarium`.
pub fn png_encoding(name: &str) -> PyResult<PngEncoding> {
    match name {
        "grey" => Ok(PngEncoding::Grey),
        "terrain-rgb" => Ok(PngEncoding::TerrainRgb),
        "terrarium" => Ok(PngEncoding::Terrarium),
        other => Err(invalid(format!(
            "unknown png_encoding '{other}' (expected grey, terrain-rgb or terrarium)"
        ))),
    }
}

/// Heights a colour map's range and sea level may take, metres (as `--height-range`,
/// `--sea-level`).
pub const HEIGHT_RANGE: RangeInclusive<f64> = -1e6..=1e6;

/// The colour options (as `--colormap`, `--height-range` and `--sea-level`), checked: a known
/// map, a finite range within [`HEIGHT_RANGE`] with the lower first, a sea level only for
/// `bathymetry`.
pub fn colours(
    colormap: Option<&str>,
    height_range: Option<(f64, f64)>,
    sea_level: Option<f64>,
) -> PyResult<ColourSettings> {
    let map = colormap
        .map(|name| {
            ColourMap::from_name(name).map_err(|_| {
                invalid(format!(
                    "unknown colour map '{name}' (known: {})",
                    ColourMap::known_names()
                ))
            })
        })
        .transpose()?;
    let heights = height_range.iter().flat_map(|&(lo, hi)| [lo, hi]).chain(sea_level);
    for z in heights {
        if !HEIGHT_RANGE.contains(&z) {
            return Err(invalid(format!(
                "height {} is outside {}..{} m",
                readable(z),
                readable(*HEIGHT_RANGE.start()),
                readable(*HEIGHT_RANGE.end())
            )));
        }
    }
    let settings = ColourSettings { map, height_range, sea_level };
    settings.validate().map_err(|e| invalid(e.to_string()))?;
    Ok(settings)
}

/// The map furniture the switches ask for (as `--legend`, `--scale-bar`, `--north-arrow`).
pub fn furniture(legend: bool, scale_bar: bool, north_arrow: bool) -> MapFurniture {
    MapFurniture { legend, scale_bar, north_arrow }
}

/// The shading normals by name (as `--shading-normals`): `smooth` or `faceted`.
pub fn shading_normals(name: &str) -> PyResult<NormalStyle> {
    name.parse::<NormalStyle>().map_err(invalid)
}

/// Runs `work` on a pool of `threads` threads (as `RAYON_NUM_THREADS` sets the command line's),
/// or on the process's shared pool where `threads` is `None`. Errors: no thread, or a pool
/// the system will not start.
pub fn on_threads<T: Send>(threads: Option<usize>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    let Some(threads) = threads else {
        return Ok(work());
    };
    if threads == 0 {
        return Err(invalid("threads must be at least 1"));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| invalid(format!("cannot start {threads} threads: {e}")))?;
    Ok(pool.install(work))
}
