//! The horizon engine: for each of N compass directions, the exact elevation angle of the
//! horizon seen from every sample of a height field, to the edge of the data (or a radius),
//! from which the sky-view factor, openness, sky illumination and insolation follow.

mod params;

pub use params::{
    HorizonParams, DEFAULT_AZIMUTHS, DEFAULT_OBSERVER_HEIGHT, REFRACTION_COEFFICIENT,
};

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
