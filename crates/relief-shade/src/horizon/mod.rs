//! The horizon engine: for each of N compass directions, the exact elevation angle of the
//! horizon seen from every sample of a height field, to the edge of the data (or a radius),
//! from which the sky-view factor, openness, sky illumination and insolation follow.

mod band_pyramid;
mod cell_pyramid;
mod coarse_bounds;
mod far_field;
mod lane_engine;
mod lane_frame;
mod lane_vector;
mod lanes;
mod march;
mod params;
mod stencil;

pub use params::{
    HorizonParams, DEFAULT_AZIMUTHS, DEFAULT_OBSERVER_HEIGHT, MAX_AZIMUTHS, REFRACTION_COEFFICIENT,
};

pub use coarse_bounds::{block_bounds, CoarseBounds, BOUND_CELL};
pub use far_field::{FarField, FarSamples, FarTerrain, SamplePatch};

use crate::ShadeError;
use cell_pyramid::CellPyramid;
use far_field::{FarContext, FarError};
use lane_engine::LaneEngine;
use march::{DirectionMarch, MarchTerrain};
use rayon::prelude::*;
use relief_core::HeightField;
use std::ops::Range;
use std::sync::atomic::{AtomicU64, Ordering};

/// Rows of samples whose horizons are found together: one parallel task.
const BAND_ROWS: usize = 32;

/// Horizon angles of every sample in every direction of a [`HorizonParams`].
#[derive(Debug, Clone, PartialEq)]
pub struct HorizonMap {
    /// Samples per row (the height field's width).
    pub width: usize,
    /// Rows (the height field's height).
    pub height: usize,
    /// The directions in degrees clockwise from north: `k * 360 / N` for `k = 0..N`.
    pub azimuths_deg: Vec<f64>,
    /// Per direction, `width * height` horizon elevation angles in radians, in the height
    /// field's sample order (row-major, row 0 south); NaN on a void. An angle may be negative
    /// (the terrain ahead falls away); where no surface lies ahead it is 0.
    pub angles: Vec<Vec<f32>>,
}

impl HorizonMap {
    /// The horizon angle in radians of sample `index` towards `azimuth_deg` (any value,
    /// wrapped to [0, 360)): linear between the two neighbouring directions of the map.
    pub fn angle_towards(&self, index: usize, azimuth_deg: f64) -> f32 {
        let n = self.azimuths_deg.len();
        let step = 360.0 / n as f64;
        let position = azimuth_deg.rem_euclid(360.0) / step;
        let below = (position.floor() as usize).min(n - 1);
        let above = (below + 1) % n;
        let weight = (position - below as f64) as f32;
        let (a, b) = (self.angles[below][index], self.angles[above][index]);
        a + (b - a) * weight
    }
}

/// Which way up the terrain is seen: as it is, or upside down (for negative openness, the
/// horizon of the inverted terrain is the depth of the valleys around a sample).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Facing {
    /// The terrain as it is.
    Up,
    /// The terrain upside down, on the same triangles.
    Down,
}

/// The horizon engine over one height field: finds the exact horizon angles of any band of
/// rows in every direction of its [`HorizonParams`].
///
/// Over a height field without holes and a flat earth, it finds the horizons of 16
/// neighbouring samples at once (their lines cross the surface at the same points,
/// translated); with holes or the earth's curvature, it marches each sample's line alone.
pub struct HorizonEngine<'a> {
    method: Method<'a>,
    /// Where the height field is a window of a larger raster: that raster.
    far: Option<FarContext<'a>>,
    void: Option<&'a [bool]>,
    params: HorizonParams,
    /// Per direction, whether its angles are wanted.
    wanted: Vec<bool>,
}

/// How a [`HorizonEngine`] finds horizons.
enum Method<'a> {
    Lanes(LaneEngine),
    March(MarchTerrain<'a>),
}

impl<'a> HorizonEngine<'a> {
    /// Prepares the engine for `field` seen `facing` up or down. A sample that is a hole of
    /// `field`, or marked in `void` (indexed like the samples), has no horizon (NaN); the
    /// surface is absent only over the holes' cells.
    pub fn new(
        field: &'a HeightField,
        void: Option<&'a [bool]>,
        params: &HorizonParams,
        facing: Facing,
    ) -> Result<Self, ShadeError> {
        Self::for_directions(field, void, params, facing, None)
    }

    /// [`HorizonEngine::new`] for the directions marked in `wanted` only (indexed like the
    /// directions of `params`; all of them with `None`): [`HorizonEngine::band`] gives no
    /// angles (an empty list) in the others.
    pub fn for_directions(
        field: &'a HeightField,
        void: Option<&'a [bool]>,
        params: &HorizonParams,
        facing: Facing,
        wanted: Option<&[bool]>,
    ) -> Result<Self, ShadeError> {
        Self::in_window(field, void, params, facing, wanted, None)
    }

    /// [`HorizonEngine::for_directions`] where `field` may be a window of a larger raster,
    /// placed in it by `far`: then each line goes on past the window to the raster's edge (as
    /// over the whole raster, bit for bit), unless `params` has a radius (the window must then
    /// reach the radius around every sample whose horizons are asked for). Errors: besides
    /// those of [`HorizonEngine::new`], a window with holes or over a curved earth without a
    /// radius (the far field is followed over a flat earth without holes only).
    pub fn in_window(
        field: &'a HeightField,
        void: Option<&'a [bool]>,
        params: &HorizonParams,
        facing: Facing,
        wanted: Option<&[bool]>,
        far: Option<FarField<'a>>,
    ) -> Result<Self, ShadeError> {
        params.validate()?;
        let n = params.azimuths as usize;
        if wanted.is_some_and(|w| w.len() != n) {
            return Err(ShadeError::parameter(
                "wanted directions",
                format!("{} flags for {n} directions", wanted.map_or(0, <[bool]>::len)),
            ));
        }
        let wanted = wanted.map_or_else(|| vec![true; n], <[bool]>::to_vec);
        let (width, height) = (field.width(), field.height());
        crate::error::check_void_mask(void, width, height)?;
        let lanes = field.holes().is_none() && params.refraction.is_none();
        let far = far.filter(|_| params.radius.is_none());
        if far.is_some() && !lanes {
            return Err(ShadeError::Limits(
                "the horizons of a window of a larger raster are followed past the window over \
                 a flat earth without voids only: fill the voids, or give a radius"
                    .to_string(),
            ));
        }
        let method = if lanes && width >= 2 && height >= 2 {
            Method::Lanes(LaneEngine::new(field, params, facing, &wanted, far.as_ref()))
        } else {
            Method::March(march_terrain(field, facing))
        };
        let far = far.map(|field| FarContext { field, error: FarError::default() });
        Ok(HorizonEngine { method, far, void, params: *params, wanted })
    }

    /// The parameters the engine was made with.
    pub fn params(&self) -> &HorizonParams {
        &self.params
    }

    /// Per direction, the horizon angles in radians of the samples of `rows`, row by row (NaN
    /// on voids and holes). With `at_least_level`, only the horizons above the horizontal are
    /// wanted: each angle is `max(angle, 0)`, found faster (what the sky-view factor and the
    /// layers of the sky and the sun need). A direction not wanted (see
    /// [`HorizonEngine::for_directions`]) has no angles.
    pub fn band(&self, rows: Range<usize>, at_least_level: bool) -> Vec<Vec<f32>> {
        let width = match &self.method {
            Method::Lanes(lanes) => lanes.width(),
            Method::March(terrain) => terrain.width,
        };
        self.region(rows, 0..width, at_least_level)
    }

    /// [`HorizonEngine::band`] for the samples of columns `cols` of `rows` only, row by row.
    pub fn region(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        at_least_level: bool,
    ) -> Vec<Vec<f32>> {
        self.directions(rows, cols, at_least_level, None)
    }

    /// [`HorizonEngine::region`] in direction `k` alone: its angles (none if it is not
    /// wanted). A window's far field is read a direction at a time this way, so that the
    /// tiles its lines cross are read together.
    pub fn direction(
        &self,
        k: usize,
        rows: Range<usize>,
        cols: Range<usize>,
        at_least_level: bool,
    ) -> Vec<f32> {
        let mut all = self.directions(rows, cols, at_least_level, Some(k));
        if k < all.len() {
            std::mem::take(&mut all[k])
        } else {
            Vec::new()
        }
    }

    /// Frees what direction `k`'s lines past the window hold (their steps over the whole
    /// raster): once its angles are all found.
    pub fn release_direction(&self, k: usize) {
        if let Method::Lanes(lanes) = &self.method {
            lanes.release_far(k);
        }
    }

    /// The angles in every direction, or in `only`.
    fn directions(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        at_least_level: bool,
        only: Option<usize>,
    ) -> Vec<Vec<f32>> {
        match &self.method {
            Method::Lanes(lanes) => {
                lanes.band(rows, cols, self.void, at_least_level, self.far.as_ref(), only)
            }
            Method::March(terrain) => self.march_band(terrain, rows, cols, at_least_level, only),
        }
    }

    /// The first error met reading the far field, if any: the horizons found since are not
    /// to be used.
    pub fn far_error(&self) -> Option<ShadeError> {
        self.far.as_ref().and_then(|far| far.error.take())
    }

    /// [`HorizonEngine::band`], each sample's line marched alone.
    fn march_band(
        &self,
        terrain: &MarchTerrain,
        rows: Range<usize>,
        cols: Range<usize>,
        at_least_level: bool,
        only: Option<usize>,
    ) -> Vec<Vec<f32>> {
        let width = terrain.width;
        let p = &self.params;
        (0..p.azimuths as usize)
            .map(|k| {
                if !self.wanted[k] || only.is_some_and(|o| o != k) {
                    return Vec::new();
                }
                let azimuth = p.azimuth_deg(k);
                let march = DirectionMarch::new(
                    terrain,
                    azimuth,
                    p.observer_height,
                    p.radius,
                    p.refraction,
                );
                // Where the previous sample's horizon (west in the row) and the one below's
                // (south, the row before) lie, seen along this sample's line: hints.
                let (sin, cos) = azimuth.to_radians().sin_cos();
                let (west, south) = (-terrain.dx * sin, -terrain.dy * cos);
                let mut below = vec![f64::NAN; width];
                let mut angles = Vec::with_capacity(rows.len() * cols.len());
                for row in rows.clone() {
                    let mut previous = f64::NAN;
                    for (col, below) in below.iter_mut().enumerate().take(cols.end).skip(cols.start)
                    {
                        let index = col + row * width;
                        let void = self.void.is_some_and(|v| v[index]);
                        if void || terrain.holes.is_some_and(|h| h[index]) {
                            angles.push(f32::NAN);
                            (previous, *below) = (f64::NAN, f64::NAN);
                            continue;
                        }
                        let hints = [previous + west, *below + south];
                        let horizon = march.horizon(col, row, &hints, at_least_level);
                        angles.push(horizon.angle as f32);
                        previous = horizon.distance;
                        *below = horizon.distance;
                    }
                }
                angles
            })
            .collect()
    }
}

/// The terrain as the march reads it: `field` seen `facing` up, with its pyramid of maxima.
fn march_terrain(field: &HeightField, facing: Facing) -> MarchTerrain<'_> {
    let (width, height) = (field.width(), field.height());
    let sign = match facing {
        Facing::Up => 1.0,
        Facing::Down => -1.0,
    };
    let holes = field.holes();
    let samples = field.samples();
    let (cells_x, cells_y) = (width.saturating_sub(1), height.saturating_sub(1));
    let hole = |k: usize| holes.is_some_and(|h| h[k]);
    let whole = |c: usize, r: usize| {
        let k = c + r * width;
        !(hole(k) || hole(k + 1) || hole(k + width) || hole(k + width + 1))
    };
    // With holes, the samples that are points of the surface: corners of a whole cell.
    let on_surface = holes.map(|_| {
        let mut on = vec![false; width * height];
        for r in 0..cells_y {
            for c in 0..cells_x {
                if whole(c, r) {
                    let k = c + r * width;
                    for corner in [k, k + 1, k + width, k + width + 1] {
                        on[corner] = true;
                    }
                }
            }
        }
        on
    });
    // A cell's bound: its highest corner that is a point of the surface.
    let pyramid = CellPyramid::build(cells_x, cells_y, &|c, r| {
        let k = c + r * width;
        [k, k + 1, k + width, k + width + 1]
            .into_iter()
            .filter(|&k| on_surface.as_ref().is_none_or(|on| on[k]))
            .map(|k| sign as f32 * samples[k])
            .fold(f32::NEG_INFINITY, f32::max)
    });
    let g = field.geometry();
    MarchTerrain {
        samples,
        width,
        height,
        sign,
        z_scale: g.z_scale,
        dx: g.dx,
        dy: g.dy,
        pyramid,
        holes,
        on_surface,
    }
}

/// The horizon map of `field` (see [`HorizonEngine`]), every band in parallel; `progress` is
/// called with the rows done. The same result whatever the number of threads. Errors: bad
/// parameters, a void mask of the wrong size, or a map too large for memory.
pub fn horizon_map(
    field: &HeightField,
    void: Option<&[bool]>,
    params: &HorizonParams,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<HorizonMap, ShadeError> {
    let engine = HorizonEngine::new(field, void, params, Facing::Up)?;
    let (width, height) = (field.width(), field.height());
    let n = params.azimuths as usize;
    let mut angles = Vec::with_capacity(n);
    for _ in 0..n {
        let mut values = Vec::new();
        values.try_reserve_exact(width * height).map_err(|_| {
            ShadeError::Limits(format!(
                "{n} directions of horizons of {width}x{height} samples do not fit in memory"
            ))
        })?;
        angles.push(values);
    }
    let done = AtomicU64::new(0);
    let bands: Vec<Vec<Vec<f32>>> = (0..height.div_ceil(BAND_ROWS))
        .into_par_iter()
        .map(|band| {
            let rows = band * BAND_ROWS..((band + 1) * BAND_ROWS).min(height);
            let result = engine.band(rows.clone(), false);
            progress(done.fetch_add(rows.len() as u64, Ordering::Relaxed) + rows.len() as u64);
            result
        })
        .collect();
    for band in bands {
        for (values, band_values) in angles.iter_mut().zip(band) {
            values.extend_from_slice(&band_values);
        }
    }
    let azimuths_deg = (0..n).map(|k| params.azimuth_deg(k)).collect();
    Ok(HorizonMap { width, height, azimuths_deg, angles })
}
