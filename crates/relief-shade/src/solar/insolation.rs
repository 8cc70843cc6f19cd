//! Insolation: the hours of direct sun and the direct-beam energy every sample of a height
//! field receives from a series of [`SunSample`]s, with cast shadows decided by its horizon
//! angles.

use super::sun_samples::SunSample;
use crate::horizon::HorizonMap;
use crate::shade_map::horn_normal;
use crate::shade_map::InsolationSun;
use crate::ShadeError;
use rayon::prelude::*;
use relief_core::{DVec3, HeightField};

/// Direct sun on every sample of a height field, in its sample order (row-major, row 0
/// south), NaN on voids.
#[derive(Debug, Clone, PartialEq)]
pub struct Insolation {
    /// Hours during which the sun stands above the sample's horizon.
    pub sun_hours: Vec<f32>,
    /// Direct-beam energy on the tilted cell, in Wh/m^2.
    pub energy_wh_m2: Vec<f32>,
}

/// The hours of direct sun and the direct-beam energy of every sample of `field` under the
/// suns `suns`.
///
/// A sample is in direct sun when the sun stands above the horizontal and above its horizon
/// angle towards the sun (the horizons clamped at the horizontal, interpolated as
/// [`HorizonMap::angle_towards`] does): night is night even from a peak whose horizon dips
/// below the horizontal, as in the insolation layers of
/// [`shade_map`](crate::shade_map::shade_map). It then receives `beam * max(0, n . s) * hours`, `n`
/// the cell's normal ([`horn_normal`], the tilted cell), `s` the unit vector towards the sun.
/// Samples marked in `void` (or holes of the field) are NaN. Rows are computed in parallel;
/// each sample sums its suns in their order, so the result does not depend on the threads.
///
/// ```
/// use relief_core::{GridGeometry, HeightField};
/// use relief_shade::horizon::HorizonMap;
/// use relief_shade::solar::{insolation, SunSample};
/// let field = HeightField::new(4, 3, vec![0.0; 12], GridGeometry::unit()).unwrap();
/// let open = HorizonMap {
///     width: 4, height: 3, azimuths_deg: vec![0.0, 90.0, 180.0, 270.0],
///     angles: vec![vec![0.0; 12]; 4],
/// };
/// let noon = SunSample { azimuth_deg: 180.0, elevation_deg: 30.0, hours: 2.0, beam_w_m2: 800.0 };
/// let sun = insolation(&field, None, &open, &[noon]).unwrap();
/// assert_eq!(sun.sun_hours[5], 2.0);
/// assert!((sun.energy_wh_m2[5] - 800.0).abs() < 1e-3); // 800 W/m^2 * sin 30 * 2 h
/// ```
pub fn insolation(
    field: &HeightField,
    void: Option<&[bool]>,
    horizons: &HorizonMap,
    suns: &[SunSample],
) -> Result<Insolation, ShadeError> {
    let (width, height) = (field.width(), field.height());
    check_shapes(width, height, void, horizons)?;
    for (k, sun) in suns.iter().enumerate() {
        check_sun(k, sun)?;
    }
    let lowest = lowest_horizon(horizons);
    // A sun below the horizontal or below every horizon angle of the map lights nothing:
    // left out.
    let suns: Vec<SunOverGrid> = suns
        .iter()
        .filter(|sun| (sun.elevation_deg.to_radians() as f32) > lowest.max(0.0))
        .filter_map(|&sun| SunOverGrid::new(sun, horizons.azimuths_deg.len()))
        .collect();

    let mut sun_hours = vec![0.0f32; width * height];
    let mut energy_wh_m2 = vec![0.0f32; width * height];
    sun_hours.par_chunks_mut(width).zip(energy_wh_m2.par_chunks_mut(width)).enumerate().for_each(
        |(row, (hours_row, energy_row))| {
            let start = row * width;
            let normals: Vec<DVec3> =
                (0..width).map(|col| horn_normal(field, void, col, row)).collect();
            let mut hours = vec![0.0f64; width];
            let mut energy = vec![0.0f64; width];
            for (col, (hours, energy)) in hours.iter_mut().zip(&mut energy).enumerate() {
                let index = start + col;
                (*hours, *energy) = direct_sun(&suns, |k| horizons.angles[k][index], normals[col]);
            }
            for col in 0..width {
                let is_void = void.is_some_and(|v| v[start + col]) || field.is_hole(col, row);
                (hours_row[col], energy_row[col]) = if is_void {
                    (f32::NAN, f32::NAN)
                } else {
                    (hours[col] as f32, energy[col] as f32)
                };
            }
        },
    );
    Ok(Insolation { sun_hours, energy_wh_m2 })
}

/// A sun with what every sample needs of it: the two directions of a horizon map it lies
/// between and its weight between them, its elevation in radians and its unit vector.
pub(crate) struct SunOverGrid {
    below: usize,
    above: usize,
    weight: f32,
    elevation_rad: f32,
    towards: DVec3,
    hours: f64,
    beam_w_m2: f64,
}

impl SunOverGrid {
    /// The sun of `sun` over a map of `directions` evenly spaced horizon directions; `None`
    /// for a sun that lights nothing (below the horizontal, or standing for no time).
    pub(crate) fn new(sun: InsolationSun, directions: usize) -> Option<SunOverGrid> {
        if !(sun.hours > 0.0 && sun.elevation_deg > 0.0) || directions == 0 {
            return None;
        }
        let position = sun.azimuth_deg.rem_euclid(360.0) / (360.0 / directions as f64);
        let below = (position.floor() as usize).min(directions - 1);
        Some(SunOverGrid {
            below,
            above: (below + 1) % directions,
            weight: (position - below as f64) as f32,
            elevation_rad: sun.elevation_deg.to_radians() as f32,
            towards: crate::sun_direction(sun.azimuth_deg, sun.elevation_deg),
            hours: sun.hours,
            beam_w_m2: sun.beam_w_m2,
        })
    }

    /// The two horizon directions (indices) the sun lies between.
    pub(crate) fn directions(&self) -> [usize; 2] {
        [self.below, self.above]
    }
}

/// The hours of direct sun and the direct-beam energy (Wh/m²) of one sample with horizon
/// angles `angle(k)` (radians) in the map's directions and unit `normal`, under `suns`: a sun
/// counts where it stands above the horizon, the horizons clamped at the horizontal in each
/// direction and interpolated between the two the sun lies between (so whether the horizons
/// below the horizontal were found changes nothing), and brings `beam * max(0, n . s) * hours`.
pub(crate) fn direct_sun(
    suns: &[SunOverGrid],
    angle: impl Fn(usize) -> f32,
    normal: DVec3,
) -> (f64, f64) {
    let (mut hours, mut energy) = (0.0, 0.0);
    for sun in suns {
        let (a, b) = (angle(sun.below).max(0.0), angle(sun.above).max(0.0));
        if sun.elevation_rad > a + (b - a) * sun.weight {
            hours += sun.hours;
            energy += sun.beam_w_m2 * normal.dot(sun.towards).max(0.0) * sun.hours;
        }
    }
    (hours, energy)
}

/// The lowest horizon angle of the map (NaNs left out); +inf for a map of voids only.
fn lowest_horizon(horizons: &HorizonMap) -> f32 {
    horizons
        .angles
        .par_iter()
        .map(|angles| angles.iter().copied().filter(|a| !a.is_nan()).fold(f32::INFINITY, f32::min))
        .reduce(|| f32::INFINITY, f32::min)
}

/// Checks that the horizon map and the voids' mask fit a `width x height` field.
fn check_shapes(
    width: usize,
    height: usize,
    void: Option<&[bool]>,
    horizons: &HorizonMap,
) -> Result<(), ShadeError> {
    let samples = width * height;
    if horizons.width != width || horizons.height != height {
        return Err(ShadeError::Mismatch(format!(
            "a horizon map of {} x {} for a height field of {width} x {height}",
            horizons.width, horizons.height
        )));
    }
    if horizons.azimuths_deg.is_empty() || horizons.angles.len() != horizons.azimuths_deg.len() {
        return Err(ShadeError::Mismatch(format!(
            "a horizon map of {} directions with angles for {}",
            horizons.azimuths_deg.len(),
            horizons.angles.len()
        )));
    }
    if let Some(k) = horizons.angles.iter().position(|a| a.len() != samples) {
        return Err(ShadeError::Mismatch(format!(
            "horizon direction {k} has {} angles for {samples} samples",
            horizons.angles[k].len()
        )));
    }
    if let Some(void) = void.filter(|v| v.len() != samples) {
        return Err(ShadeError::Mismatch(format!(
            "a voids' mask of {} values for {samples} samples",
            void.len()
        )));
    }
    Ok(())
}

/// Checks sun `k`: finite azimuth, elevation in [-90, 90], hours and beam finite and >= 0.
fn check_sun(k: usize, sun: &SunSample) -> Result<(), ShadeError> {
    let fine = sun.azimuth_deg.is_finite()
        && (-90.0..=90.0).contains(&sun.elevation_deg)
        && sun.hours.is_finite()
        && sun.hours >= 0.0
        && sun.beam_w_m2.is_finite()
        && sun.beam_w_m2 >= 0.0;
    if fine {
        Ok(())
    } else {
        Err(ShadeError::parameter(
            "sun sample",
            format!(
                "number {k} ({sun:?}) needs a finite azimuth, an elevation in [-90, 90] and \
                 finite hours and beam >= 0"
            ),
        ))
    }
}
