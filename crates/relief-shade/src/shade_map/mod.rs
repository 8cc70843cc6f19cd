//! Shade maps: rasters aligned with a height field, sample for sample, that say how much of
//! the sun and of the sky each sample sees (exact cast shadows, the sky-view factor), its Lambert
//! hillshade, and a map layer combining them. Every ray starts on the surface at a sample
//! point ([`surface_ray`]) and is traced exactly by the tracer handed in.

mod directions;
mod hillshade;
mod layer;
mod params;
mod surface_ray;

pub use directions::{disc_directions, sky_directions, SkyDirections};
pub use hillshade::{horn_normal, lambert};
pub use layer::ShadeLayer;
pub use params::{ShadeMapParams, SunPosition, MAX_RAYS_PER_SAMPLE, MAX_SUN_RADIUS_DEG, SKY_SHARE};
pub use surface_ray::{surface_origin, surface_ray, SURFACE_LIFT};

use crate::ShadeError;
use rayon::prelude::*;
use relief_core::{DVec3, HeightField, Ray};
use relief_trace::Tracer;
use std::sync::atomic::{AtomicU64, Ordering};

/// The layers of a shade map, each `width * height` values in the height field's sample order
/// (row-major, row 0 south), from 0 to 1, NaN on a void.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadeMap {
    /// Samples per row (the height field's width).
    pub width: usize,
    /// Rows (the height field's height).
    pub height: usize,
    /// The layers in the order they were asked for.
    pub layers: Vec<(ShadeLayer, Vec<f32>)>,
    /// Rays cast (the sky's search decides some directions without casting their rays).
    pub rays: u64,
}

impl ShadeMap {
    /// The values of `layer`, if it was made.
    pub fn layer(&self, layer: ShadeLayer) -> Option<&[f32]> {
        self.layers.iter().find(|(l, _)| *l == layer).map(|(_, values)| values.as_slice())
    }
}

/// Rows of samples traced together: a band is one parallel task, and a tile's height.
const BAND_ROWS: usize = 8;
/// Samples per row of a tile: a tile's 8 x 8 rays in one direction are traced as one batch,
/// a full packet of the mipmap tracer's.
const TILE_COLS: usize = 8;

/// Makes the shade map `params` asks for over every sample of `field`, tracing with `tracer`,
/// which must trace `field` (any tracer and surface: the map is exact for that surface).
///
/// A sample of `field` that is a hole, or is marked in `void` (indexed like the samples; the
/// voids a reader found before they were filled), is NaN in every layer. For each other sample:
/// - [`ShadeLayer::Shadow`]: the mean over the suns of the fraction of each sun's rays (one,
///   or `sun_rays` over its disc) that escape the terrain;
/// - [`ShadeLayer::Sky`]: the fraction of the `sky_rays` [`SkyDirections`] that escape (each
///   azimuth's decided by a search that traces a few of its rays);
/// - [`ShadeLayer::Hillshade`]: the mean over the suns of [`lambert`] with the [`horn_normal`];
/// - [`ShadeLayer::Combined`]: `(1 - SKY_SHARE)` times the mean over the suns of Lambert times
///   that sun's fraction seen, plus `SKY_SHARE` times the sky-view factor.
///
/// `progress` is called with the number of rows done, from any thread. The result is the same
/// whatever the number of threads. Errors: parameters out of range, a `void` mask of the
/// wrong length, or layers too large to allocate.
pub fn shade_map(
    field: &HeightField,
    tracer: &dyn Tracer,
    void: Option<&[bool]>,
    params: &ShadeMapParams,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ShadeMap, ShadeError> {
    params.validate()?;
    let (width, height) = (field.width(), field.height());
    let samples = width * height;
    if let Some(void) = void {
        if void.len() != samples {
            return Err(ShadeError::Mismatch(format!(
                "a void mask of {} samples for a {width}x{height} height field",
                void.len()
            )));
        }
    }
    let mut layers = Vec::with_capacity(params.layers.len());
    for &layer in &params.layers {
        let mut values = Vec::new();
        values.try_reserve_exact(samples).map_err(|_| {
            ShadeError::Limits(format!("a {width}x{height} {layer} layer does not fit in memory"))
        })?;
        layers.push((layer, values));
    }

    let rays = Rays::for_params(params);
    let done_rows = AtomicU64::new(0);
    let bands: Vec<Band> = (0..height.div_ceil(BAND_ROWS))
        .into_par_iter()
        .map(|band| {
            let rows = band * BAND_ROWS..((band + 1) * BAND_ROWS).min(height);
            let result = shade_band(field, tracer, void, params, &rays, rows.clone());
            progress(done_rows.fetch_add(rows.len() as u64, Ordering::Relaxed) + rows.len() as u64);
            result
        })
        .collect();
    let mut cast = 0;
    for band in bands {
        cast += band.rays;
        for ((_, values), band_values) in layers.iter_mut().zip(band.layers) {
            values.extend_from_slice(&band_values);
        }
    }
    Ok(ShadeMap { width, height, layers, rays: cast })
}

/// The directions a map's rays take, the same for every sample.
struct Rays {
    /// Per sun, the directions over its disc (its centre alone for a point sun).
    suns: Vec<Vec<DVec3>>,
    /// Per sun, the direction of its centre (for the hillshade).
    sun_centres: Vec<DVec3>,
    /// The sky's directions (`None` when no layer needs them).
    sky: Option<SkyDirections>,
}

impl Rays {
    fn for_params(params: &ShadeMapParams) -> Rays {
        let sun_centres: Vec<DVec3> = params.suns.iter().map(|s| s.direction()).collect();
        let per_sun = if params.sun_radius_deg > 0.0 { params.sun_rays } else { 1 };
        let suns = if params.needs_sun_rays() {
            sun_centres
                .iter()
                .map(|&c| disc_directions(c, params.sun_radius_deg, per_sun))
                .collect()
        } else {
            Vec::new()
        };
        let sky = params.needs_sky_rays().then(|| SkyDirections::new(params.sky_rays));
        Rays { suns, sun_centres, sky }
    }
}

/// One band's layers (`rows * width` values each) and the rays it cast.
struct Band {
    layers: Vec<Vec<f32>>,
    rays: u64,
}

/// Shades the samples of `rows`, tile by tile.
fn shade_band(
    field: &HeightField,
    tracer: &dyn Tracer,
    void: Option<&[bool]>,
    params: &ShadeMapParams,
    rays: &Rays,
    rows: std::ops::Range<usize>,
) -> Band {
    let width = field.width();
    let count = rows.len() * width;
    let mut layers = vec![vec![f32::NAN; count]; params.layers.len()];
    let mut cast = 0;
    let mut tile = TileRays::default();
    let needs_slope =
        params.layers.iter().any(|l| matches!(l, ShadeLayer::Hillshade | ShadeLayer::Combined));
    for first_col in (0..width).step_by(TILE_COLS) {
        let cols = first_col..(first_col + TILE_COLS).min(width);
        tile.gather(field, void, rows.clone(), cols);
        if tile.samples.is_empty() {
            continue;
        }
        let seen_per_sun: Vec<Vec<f32>> =
            rays.suns.iter().map(|dirs| tile.fraction_seen(tracer, dirs)).collect();
        cast += tile.samples.len() as u64 * rays.suns.iter().map(Vec::len).sum::<usize>() as u64;
        let sky = match &rays.sky {
            Some(sky) => {
                let (seen, sky_cast) = tile.sky_seen(tracer, sky);
                cast += sky_cast;
                seen
            }
            None => Vec::new(),
        };
        for (k, &(col, row)) in tile.samples.iter().enumerate() {
            // The slope only where a layer needs it.
            let normal = needs_slope.then(|| horn_normal(field, void, col, row));
            let lamberts = rays.sun_centres.iter().map(|&d| normal.map_or(0.0, |n| lambert(n, d)));
            let suns = rays.sun_centres.len().max(1) as f64;
            let index = col + (row - rows.start) * width;
            for (layer, values) in params.layers.iter().zip(layers.iter_mut()) {
                let value = match layer {
                    ShadeLayer::Shadow => {
                        seen_per_sun.iter().map(|seen| seen[k] as f64).sum::<f64>() / suns
                    }
                    ShadeLayer::Sky => sky[k] as f64,
                    ShadeLayer::Hillshade => lamberts.clone().sum::<f64>() / suns,
                    ShadeLayer::Combined => {
                        let sun = lamberts
                            .clone()
                            .zip(&seen_per_sun)
                            .map(|(l, seen)| l * seen[k] as f64)
                            .sum::<f64>()
                            / suns;
                        (1.0 - SKY_SHARE) * sun + SKY_SHARE * sky[k] as f64
                    }
                };
                values[index] = value as f32;
            }
        }
    }
    Band { layers, rays: cast }
}

/// The rays of one tile of samples in one direction, and the buffers to trace them.
#[derive(Default)]
struct TileRays {
    /// The tile's samples that are shaded (not void), as (column, row).
    samples: Vec<(usize, usize)>,
    /// Their rays' origins.
    origins: Vec<DVec3>,
    rays: Vec<Ray>,
    occluded: Vec<bool>,
    steps: Vec<u32>,
}

impl TileRays {
    /// Takes the samples of `cols` x `rows` that are not void, row by row.
    fn gather(
        &mut self,
        field: &HeightField,
        void: Option<&[bool]>,
        rows: std::ops::Range<usize>,
        cols: std::ops::Range<usize>,
    ) {
        self.samples.clear();
        self.origins.clear();
        for row in rows {
            for col in cols.clone() {
                let index = col + row * field.width();
                if field.is_hole(col, row) || void.is_some_and(|v| v[index]) {
                    continue;
                }
                self.samples.push((col, row));
                self.origins.push(surface_origin(field, col, row));
            }
        }
    }

    /// Per sample, the fraction of `directions` whose rays escape the terrain.
    fn fraction_seen(&mut self, tracer: &dyn Tracer, directions: &[DVec3]) -> Vec<f32> {
        let n = self.samples.len();
        let mut seen = vec![0u32; n];
        self.occluded.resize(n, false);
        self.steps.resize(n, 0);
        for &dir in directions {
            self.rays.clear();
            self.rays.extend(self.origins.iter().map(|&o| Ray::new(o, dir)));
            tracer.occluded_batch(&self.rays, &mut self.occluded, &mut self.steps);
            for (count, &blocked) in seen.iter_mut().zip(&self.occluded) {
                *count += u32::from(!blocked);
            }
        }
        let total = directions.len().max(1) as f32;
        seen.into_iter().map(|c| c as f32 / total).collect()
    }

    /// Per sample, the fraction of the `sky`'s directions whose rays escape the terrain, and
    /// the rays cast to find it.
    ///
    /// An azimuth's escaping rays are its highest ones (see [`SkyDirections`]), so per sample
    /// and azimuth only the lowest escaping band is searched for: the lowest band first (open
    /// terrain sees it, with one ray), then by bisection between the highest band known to be
    /// hidden and the lowest known to escape. An escaping ray crosses the whole grid and costs
    /// far more than a hidden one, which is why the search starts low rather than in the
    /// middle. Measured on 1201² with 64 directions: 2.9 s of tracing, against 7.3 s for
    /// bisection from the middle and 8.5 to 8.8 s for tracing every ray, the same values.
    fn sky_seen(&mut self, tracer: &dyn Tracer, sky: &SkyDirections) -> (Vec<f32>, u64) {
        let n = self.samples.len();
        let mut seen = vec![0usize; n];
        // Per sample, the bands below `hidden` are known to be hidden and those from `open`
        // up to escape.
        let mut hidden = vec![0usize; n];
        let mut open = vec![0usize; n];
        let mut probes: Vec<(usize, usize)> = Vec::with_capacity(n);
        let mut cast = 0;
        for azimuth in 0..sky.azimuths() {
            hidden.fill(0);
            open.fill(sky.bands());
            for round in 0.. {
                probes.clear();
                self.rays.clear();
                for k in (0..n).filter(|&k| hidden[k] < open[k]) {
                    let band = if round == 0 { 0 } else { (hidden[k] + open[k]) / 2 };
                    probes.push((k, band));
                    self.rays.push(Ray::new(self.origins[k], sky.direction(azimuth, band)));
                }
                if probes.is_empty() {
                    break;
                }
                let m = probes.len();
                self.occluded.resize(m, false);
                self.steps.resize(m, 0);
                tracer.occluded_batch(&self.rays, &mut self.occluded, &mut self.steps);
                cast += m as u64;
                for (&(k, band), &blocked) in probes.iter().zip(&self.occluded) {
                    if blocked {
                        hidden[k] = band + 1;
                    } else {
                        open[k] = band;
                    }
                }
            }
            for (seen, &hidden) in seen.iter_mut().zip(&hidden) {
                *seen += sky.bands() - hidden;
            }
        }
        let total = sky.all().len() as f32;
        (seen.into_iter().map(|c| c as f32 / total).collect(), cast)
    }
}
