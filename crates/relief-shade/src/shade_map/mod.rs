//! Shade maps: rasters aligned with a height field, sample for sample, that say how much of
//! the sun and of the sky each sample sees: exact cast shadows, the horizon and the layers
//! built on it (sky-view factor, openness, sky illumination, insolation), hillshades, and a map
//! layer combining them. Every sun ray starts on the surface at a sample point
//! ([`surface_ray`]) and is traced exactly by the tracer handed in; the horizons come from the
//! [`horizon`](crate::horizon) engine.

mod directions;
mod hillshade;
mod horizon_layers;
mod layer;
mod params;
pub(crate) mod surface_ray;

pub use directions::disc_directions;
pub use hillshade::{horn_normal, lambert};
pub use horizon_layers::{
    anisotropic_sky_view_factor, multidirectional_hillshade, openness_deg, sky_illumination,
    sky_view_factor, Anisotropy, SkyModel,
};
pub use layer::ShadeLayer;
pub use params::{
    InsolationSun, ShadeMapParams, SunPosition, MAX_RAYS_PER_SAMPLE, MAX_SUN_RADIUS_DEG, SKY_SHARE,
    SUN_SHARE_OF_SKY_ILLUMINATION,
};
pub use surface_ray::{surface_origin, surface_origin_within, surface_ray, SURFACE_LIFT};

use crate::horizon::{Facing, HorizonEngine};
use crate::solar::{direct_sun, SunOverGrid};
use crate::ShadeError;
use rayon::prelude::*;
use relief_core::{DVec3, HeightField, Ray};
use relief_trace::Tracer;
use std::ops::Range;
use std::sync::atomic::{AtomicU64, Ordering};

/// One band of a shade map: a value per sample of the height field, in its sample order
/// (row-major, row 0 south), NaN on a void.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadeBand {
    /// The layer the band belongs to.
    pub layer: ShadeLayer,
    /// The band's name: the layer's, or for the horizon one band per direction
    /// (`horizon-022.5`).
    pub name: String,
    /// The values, in the layer's unit ([`ShadeLayer::unit`]).
    pub values: Vec<f32>,
}

/// The layers of a shade map, each `width * height` values per band.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadeMap {
    /// Samples per row (the height field's width).
    pub width: usize,
    /// Rows (the height field's height).
    pub height: usize,
    /// The bands of the layers, in the order the layers were asked for.
    pub bands: Vec<ShadeBand>,
    /// Rays cast towards the suns.
    pub rays: u64,
}

impl ShadeMap {
    /// The values of `layer`'s first band, if it was made.
    pub fn layer(&self, layer: ShadeLayer) -> Option<&[f32]> {
        self.bands.iter().find(|b| b.layer == layer).map(|b| b.values.as_slice())
    }

    /// Every band of `layer`.
    pub fn layer_bands(&self, layer: ShadeLayer) -> impl Iterator<Item = &ShadeBand> {
        self.bands.iter().filter(move |b| b.layer == layer)
    }
}

/// Rows of samples shaded together: a band is one parallel task, and a tile's height.
const BAND_ROWS: usize = 32;
/// Samples per row of a tile: a tile's 8 x 8 rays in one direction are traced as one batch,
/// a full packet of the mipmap tracer's.
const TILE_COLS: usize = 8;

/// Makes the shade map `params` asks for over every sample of `field`, tracing the suns' rays
/// with `tracer`, which must trace `field` (any tracer and surface: those layers are exact for
/// that surface); the layers built on horizons are exact for the `triangles` surface.
///
/// A sample of `field` that is a hole, or is marked in `void` (indexed like the samples; the
/// voids a reader found before they were filled), is NaN in every layer. For each other
/// sample, with `h` its horizon angles in the [`HorizonParams`](crate::horizon::HorizonParams)
/// directions and `n` the normal of [`horn_normal`]:
/// - [`ShadeLayer::Shadow`]: the mean over the suns of the fraction of each sun's rays (one,
///   or `sun_rays` over its disc) that escape the terrain;
/// - [`ShadeLayer::Hillshade`]: the mean over the suns of [`lambert`];
/// - [`ShadeLayer::Horizon`]: `h` in degrees, one band per direction;
/// - [`ShadeLayer::Sky`]: [`sky_view_factor`]; [`ShadeLayer::SkyAniso`]:
///   [`anisotropic_sky_view_factor`];
/// - [`ShadeLayer::OpennessPos`] and [`ShadeLayer::OpennessNeg`]: [`openness_deg`] of the
///   terrain and of the terrain upside down;
/// - [`ShadeLayer::SkyIllumination`]: `(1 - SUN_SHARE_OF_SKY_ILLUMINATION)` times
///   [`sky_illumination`] plus that share times the shadow layer (RVT's shaded sky
///   illumination);
/// - [`ShadeLayer::HillshadeMulti`]: the hillshade of [`multidirectional_hillshade`];
/// - [`ShadeLayer::Insolation`] and [`ShadeLayer::SunHours`]: over the
///   [`ShadeMapParams::insolation`] suns, the direct-beam energy on the tilted cell (Wh/m²) and
///   the hours of direct sun, a sun counting where it stands above the horizontal and above
///   the horizon (`max(h, 0)` interpolated between the two nearest directions);
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
    let whole = ShadeRegion {
        cols: 0..field.width(),
        rows: 0..field.height(),
        far: None,
        raster_span: None,
    };
    shade_map_region(field, tracer, void, params, &whole, progress)
}

/// The samples of a height field that a shade map covers, and, where the height field is a
/// window of a larger raster, that raster.
#[derive(Clone)]
pub struct ShadeRegion<'a> {
    /// The columns of the height field shaded.
    pub cols: Range<usize>,
    /// The rows of the height field shaded.
    pub rows: Range<usize>,
    /// Where the height field is a window of a larger raster, that raster and the window's
    /// place in it: the horizons go on past the window to the raster's edge (see
    /// [`HorizonEngine::in_window`]). The window must hold every other sample a layer reads
    /// (the sun rays' reach, a radius, the hillshade's neighbours): then the map equals the
    /// whole raster's over the region, bit for bit.
    pub far: Option<crate::horizon::FarField<'a>>,
    /// The lowest and highest sample of the raster the height field is a window of (its own
    /// with `None`): the sun rays start as far above the surface as over the whole raster.
    pub raster_span: Option<[f32; 2]>,
}

/// [`shade_map`] over the samples of `region` only: a map of `region.cols.len()` x
/// `region.rows.len()` samples; `progress` is called with its rows done. Errors: those of
/// [`shade_map`], a region outside the field, and a far field that could not be read.
pub fn shade_map_region(
    field: &HeightField,
    tracer: &dyn Tracer,
    void: Option<&[bool]>,
    params: &ShadeMapParams,
    region: &ShadeRegion,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ShadeMap, ShadeError> {
    params.validate()?;
    crate::error::check_void_mask(void, field.width(), field.height())?;
    let ShadeRegion { cols, rows, far, raster_span } = region.clone();
    if cols.end > field.width() || rows.end > field.height() || cols.is_empty() || rows.is_empty() {
        return Err(ShadeError::parameter(
            "region",
            format!(
                "columns {cols:?} and rows {rows:?} are not a region of {} x {} samples",
                field.width(),
                field.height()
            ),
        ));
    }
    let (width, height) = (cols.len(), rows.len());
    let samples = width * height;
    let names = params.band_names();
    let mut bands = Vec::with_capacity(names.len());
    for (layer, name) in names {
        let mut values = Vec::new();
        values.try_reserve_exact(samples).map_err(|_| {
            ShadeError::Limits(format!("a {width}x{height} {name} band does not fit in memory"))
        })?;
        bands.push(ShadeBand { layer, name, values });
    }

    let n = params.horizon.azimuths as usize;
    let insolation_suns: Vec<SunOverGrid> =
        params.insolation.iter().filter_map(|&sun| SunOverGrid::new(sun, n)).collect();
    // Where only the sun's layers need the horizons, only the directions beside its path.
    let sun_only = params
        .layers
        .iter()
        .filter(|l| l.needs_horizons(Facing::Up))
        .all(|l| matches!(l, ShadeLayer::Insolation | ShadeLayer::SunHours));
    let wanted = sun_only.then(|| {
        let mut wanted = vec![false; n];
        for direction in insolation_suns.iter().flat_map(SunOverGrid::directions) {
            wanted[direction] = true;
        }
        wanted
    });
    let context = Context {
        field,
        tracer,
        void,
        params,
        rays: Rays::for_params(params),
        up: params
            .needs_horizons(Facing::Up)
            .then(|| {
                HorizonEngine::in_window(
                    field,
                    void,
                    &params.horizon,
                    Facing::Up,
                    wanted.as_deref(),
                    far,
                )
            })
            .transpose()?,
        down: params
            .needs_horizons(Facing::Down)
            .then(|| {
                HorizonEngine::in_window(field, void, &params.horizon, Facing::Down, None, far)
            })
            .transpose()?,
        cols: cols.clone(),
        raster_span: raster_span.unwrap_or([field.min_sample(), field.max_sample()]),
        angles: None,
        azimuths_deg: (0..n).map(|k| params.horizon.azimuth_deg(k)).collect(),
        insolation_suns,
    };
    // Over a far field, the horizons are found first, a direction at a time (the progress
    // counts them as all rows but one, the layers as the last).
    let directions =
        context.up.iter().chain(&context.down).map(|e| e.params().azimuths as u64).sum::<u64>();
    let mut context = context;
    let base = if far.is_some() && directions > 0 {
        let scale = |done: usize| done as u64 * height as u64 / (directions + 1);
        context.angles = Some(RegionAngles::direction_by_direction(
            context.up.as_ref(),
            context.down.as_ref(),
            rows.clone(),
            cols.clone(),
            params.level_only(),
            &|done| progress(scale(done)),
        ));
        scale(directions as usize)
    } else {
        0
    };
    let context = context;
    let done_rows = AtomicU64::new(0);
    let results: Vec<BandValues> = (0..height.div_ceil(BAND_ROWS))
        .into_par_iter()
        .map(|band| {
            let band_rows =
                rows.start + band * BAND_ROWS..rows.start + ((band + 1) * BAND_ROWS).min(height);
            let result = context.shade_rows(band_rows.clone());
            let done = band_rows.len() as u64;
            let rows_done = done_rows.fetch_add(done, Ordering::Relaxed) + done;
            progress(base + rows_done * (height as u64 - base) / height as u64);
            result
        })
        .collect();
    if let Some(error) =
        [&context.up, &context.down].into_iter().flatten().find_map(|e| e.far_error())
    {
        return Err(error);
    }
    let mut cast = 0;
    for result in results {
        cast += result.rays;
        for (band, values) in bands.iter_mut().zip(result.bands) {
            band.values.extend_from_slice(&values);
        }
    }
    Ok(ShadeMap { width, height, bands, rays: cast })
}

/// The directions a map's sun rays take, the same for every sample.
struct Rays {
    /// Per sun, the directions over its disc (its centre alone for a point sun).
    suns: Vec<Vec<DVec3>>,
    /// Per sun, the direction of its centre (for the hillshade).
    sun_centres: Vec<DVec3>,
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
        Rays { suns, sun_centres }
    }
}

/// One band of rows' values (`rows * width` a band) and the rays it cast.
struct BandValues {
    bands: Vec<Vec<f32>>,
    rays: u64,
}

/// What every band of a map shares.
struct Context<'a> {
    field: &'a HeightField,
    tracer: &'a dyn Tracer,
    void: Option<&'a [bool]>,
    params: &'a ShadeMapParams,
    rays: Rays,
    /// The horizons of the terrain, and of the terrain upside down, where layers need them.
    up: Option<HorizonEngine<'a>>,
    down: Option<HorizonEngine<'a>>,
    azimuths_deg: Vec<f64>,
    /// The insolation suns that light anything, placed between the horizons' directions.
    insolation_suns: Vec<SunOverGrid>,
    /// The columns shaded.
    cols: Range<usize>,
    /// The lowest and highest sample of the whole raster.
    raster_span: [f32; 2],
    /// The region's horizon angles, where they are found beforehand.
    angles: Option<RegionAngles>,
}

/// The horizon angles of every sample of a region, per direction, of the terrain and of the
/// terrain upside down (where the layers need them).
struct RegionAngles {
    rows: Range<usize>,
    up: Option<Vec<Vec<f32>>>,
    down: Option<Vec<Vec<f32>>>,
}

impl RegionAngles {
    /// Finds the angles of `rows` x `cols` a direction at a time, each direction's bands of
    /// rows in parallel: the lines of one direction cross the same part of a far field, so
    /// the tiles they read are read together. `progress` is called with the directions done.
    fn direction_by_direction(
        up: Option<&HorizonEngine>,
        down: Option<&HorizonEngine>,
        rows: Range<usize>,
        cols: Range<usize>,
        level_only: bool,
        progress: &dyn Fn(usize),
    ) -> RegionAngles {
        let mut done = 0;
        let mut all = |engine: &HorizonEngine, level: bool| {
            (0..engine.params().azimuths as usize)
                .map(|k| {
                    let bands: Vec<Vec<f32>> = (0..rows.len().div_ceil(BAND_ROWS))
                        .into_par_iter()
                        .map(|band| {
                            let first = rows.start + band * BAND_ROWS;
                            let band_rows = first..(first + BAND_ROWS).min(rows.end);
                            engine.direction(k, band_rows, cols.clone(), level)
                        })
                        .collect();
                    engine.release_direction(k);
                    done += 1;
                    progress(done);
                    bands.concat()
                })
                .collect()
        };
        let up = up.map(|e| all(e, level_only));
        let down = down.map(|e| all(e, false));
        RegionAngles { rows, up, down }
    }
}

impl Context<'_> {
    /// Shades the samples of `rows`.
    fn shade_rows(&self, rows: Range<usize>) -> BandValues {
        let (field, params, cols) = (self.field, self.params, self.cols.clone());
        let width = field.width();
        let count = rows.len() * cols.len();
        let (seen_per_sun, rays) = self.suns_seen(rows.clone());
        let level_only = params.level_only();
        let (up, down) = match &self.angles {
            // The region's angles, found direction by direction beforehand: this band's.
            Some(angles) => {
                let first = (rows.start - angles.rows.start) * cols.len();
                let slice = |a: &Option<Vec<Vec<f32>>>| {
                    a.as_ref().map(|per_direction| {
                        per_direction
                            .iter()
                            .map(|d| {
                                if d.is_empty() {
                                    Vec::new()
                                } else {
                                    d[first..first + count].to_vec()
                                }
                            })
                            .collect::<Vec<_>>()
                    })
                };
                (slice(&angles.up), slice(&angles.down))
            }
            None => (
                self.up.as_ref().map(|e| e.region(rows.clone(), cols.clone(), level_only)),
                self.down.as_ref().map(|e| e.region(rows.clone(), cols.clone(), false)),
            ),
        };
        let n_bands: usize = params.layers.iter().map(|&l| params.bands_of(l)).sum();
        let mut bands = vec![vec![f32::NAN; count]; n_bands];
        let suns = self.rays.sun_centres.len().max(1) as f64;
        for (k, (col, row)) in
            rows.clone().flat_map(|r| cols.clone().map(move |c| (c, r))).enumerate()
        {
            if field.is_hole(col, row) || self.void.is_some_and(|v| v[col + row * width]) {
                continue;
            }
            let normal = params.needs_normal().then(|| horn_normal(field, self.void, col, row));
            let lamberts =
                self.rays.sun_centres.iter().map(|&d| normal.map_or(0.0, |n| lambert(n, d)));
            let shadow = || seen_per_sun.iter().map(|seen| seen[k] as f64).sum::<f64>() / suns;
            let mut band = 0;
            for &layer in &params.layers {
                let value = match layer {
                    ShadeLayer::Horizon => {
                        for h in column(&up, k) {
                            bands[band][k] = h.to_degrees() as f32;
                            band += 1;
                        }
                        continue;
                    }
                    ShadeLayer::Shadow => shadow(),
                    ShadeLayer::Sky => sky_view_factor(column(&up, k)),
                    ShadeLayer::SkyAniso => anisotropic_sky_view_factor(
                        column(&up, k),
                        &self.azimuths_deg,
                        &params.anisotropy,
                    ),
                    ShadeLayer::OpennessPos => openness_deg(column(&up, k)),
                    ShadeLayer::OpennessNeg => openness_deg(column(&down, k)),
                    ShadeLayer::Hillshade => lamberts.clone().sum::<f64>() / suns,
                    ShadeLayer::HillshadeMulti => {
                        multidirectional_hillshade(normal.unwrap_or(DVec3::Z))
                    }
                    ShadeLayer::SkyIllumination => {
                        let sky = sky_illumination(
                            column(&up, k),
                            &self.azimuths_deg,
                            normal.unwrap_or(DVec3::Z),
                            params.sky_model,
                        );
                        (1.0 - SUN_SHARE_OF_SKY_ILLUMINATION) * sky
                            + SUN_SHARE_OF_SKY_ILLUMINATION * shadow()
                    }
                    ShadeLayer::Insolation | ShadeLayer::SunHours => {
                        let up = up.as_deref().unwrap_or_default();
                        let (hours, energy) = direct_sun(
                            &self.insolation_suns,
                            |d| up[d][k],
                            normal.unwrap_or(DVec3::Z),
                        );
                        if layer == ShadeLayer::Insolation {
                            energy
                        } else {
                            hours
                        }
                    }
                    ShadeLayer::Combined => {
                        let sun = lamberts
                            .clone()
                            .zip(&seen_per_sun)
                            .map(|(l, seen)| l * seen[k] as f64)
                            .sum::<f64>()
                            / suns;
                        (1.0 - SKY_SHARE) * sun + SKY_SHARE * sky_view_factor(column(&up, k))
                    }
                };
                bands[band][k] = value as f32;
                band += 1;
            }
        }
        BandValues { bands, rays }
    }

    /// Per sun, the fraction of its rays that escape from each sample of `rows` (band
    /// order; 0 on voids), tile by tile; and the rays cast.
    fn suns_seen(&self, rows: Range<usize>) -> (Vec<Vec<f32>>, u64) {
        let all = self.cols.clone();
        let width = all.len();
        let mut seen = vec![vec![0.0f32; rows.len() * width]; self.rays.suns.len()];
        if self.rays.suns.is_empty() {
            return (seen, 0);
        }
        let mut cast = 0;
        let mut tile = TileRays::default();
        for first_col in all.clone().step_by(TILE_COLS) {
            let cols = first_col..(first_col + TILE_COLS).min(all.end);
            tile.gather(self.field, self.void, rows.clone(), cols, self.raster_span);
            for (sun, dirs) in self.rays.suns.iter().enumerate() {
                let fractions = tile.fraction_seen(self.tracer, dirs);
                cast += (tile.samples.len() * dirs.len()) as u64;
                for (&(col, row), fraction) in tile.samples.iter().zip(fractions) {
                    seen[sun][col - all.start + (row - rows.start) * width] = fraction;
                }
            }
        }
        (seen, cast)
    }
}

/// The horizon angles (radians) of band sample `k` in every direction, from a band's angles
/// per direction (none if the band has none).
fn column(angles: &Option<Vec<Vec<f32>>>, k: usize) -> impl Iterator<Item = f64> + '_ {
    angles.iter().flatten().map(move |a| a[k] as f64)
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
        span: [f32; 2],
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
                self.origins.push(surface_origin_within(field, col, row, span));
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
}
