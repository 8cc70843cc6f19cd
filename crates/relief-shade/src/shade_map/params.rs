//! What a shade map is asked for: its layers, suns and ray counts.

use super::ShadeLayer;
use crate::{sun_direction, ShadeError};
use relief_core::DVec3;

/// A sun's place in the sky.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunPosition {
    /// Compass direction in degrees, clockwise from north (+y): 90 is east (+x).
    pub azimuth_deg: f64,
    /// Angle above the horizon in degrees, in `(0, 90]`.
    pub elevation_deg: f64,
}

impl SunPosition {
    /// The cartographers' light: from the north-west, 45 degrees up (`gdaldem`'s default).
    pub const CARTOGRAPHIC: SunPosition = SunPosition { azimuth_deg: 315.0, elevation_deg: 45.0 };

    /// Unit vector from the ground towards the sun's centre.
    pub fn direction(&self) -> DVec3 {
        sun_direction(self.azimuth_deg, self.elevation_deg)
    }
}

/// The share of the sky's light in the [`ShadeLayer::Combined`] layer: what a flat, open
/// sample gets from the sky, beside `1 - SKY_SHARE` times the sine of the sun's elevation
/// from the sun.
pub const SKY_SHARE: f64 = 0.3;

/// Most rays a map may cast per sample and sun, or to the sky.
pub const MAX_RAYS_PER_SAMPLE: u32 = 4096;

/// Largest angular radius of a sun's disc, in degrees.
pub const MAX_SUN_RADIUS_DEG: f64 = 45.0;

/// The parameters of [`shade_map`](super::shade_map).
#[derive(Debug, Clone, PartialEq)]
pub struct ShadeMapParams {
    /// The layers to make, in the order they are returned (each at most once).
    pub layers: Vec<ShadeLayer>,
    /// The suns: the shadow and hillshade layers are their mean.
    pub suns: Vec<SunPosition>,
    /// Angular radius of each sun's disc in degrees (0: a point; the real sun's is 0.27).
    pub sun_radius_deg: f64,
    /// Rays per sun spread over its disc when `sun_radius_deg > 0`.
    pub sun_rays: u32,
    /// Directions over the sky for the sky-view factor.
    pub sky_rays: u32,
}

impl Default for ShadeMapParams {
    /// The combined layer, one point sun from the north-west 45 degrees up, 64 sky rays.
    fn default() -> Self {
        ShadeMapParams {
            layers: vec![ShadeLayer::Combined],
            suns: vec![SunPosition::CARTOGRAPHIC],
            sun_radius_deg: 0.0,
            sun_rays: 16,
            sky_rays: 64,
        }
    }
}

impl ShadeMapParams {
    /// Checks every parameter, naming the one that is wrong.
    pub fn validate(&self) -> Result<(), ShadeError> {
        if self.layers.is_empty() {
            return Err(ShadeError::parameter("layers", "no layer asked for"));
        }
        for (k, layer) in self.layers.iter().enumerate() {
            if self.layers[..k].contains(layer) {
                return Err(ShadeError::parameter("layers", format!("{layer} is asked for twice")));
            }
        }
        if self.suns.is_empty() && self.layers.iter().any(|l| l.needs_suns()) {
            return Err(ShadeError::parameter("suns", "no sun given"));
        }
        for sun in &self.suns {
            if !sun.azimuth_deg.is_finite() {
                return Err(ShadeError::parameter(
                    "sun azimuth",
                    format!("{} is not finite", sun.azimuth_deg),
                ));
            }
            if !(sun.elevation_deg > 0.0 && sun.elevation_deg <= 90.0) {
                return Err(ShadeError::parameter(
                    "sun elevation",
                    format!("{} is not above 0 and at most 90 degrees", sun.elevation_deg),
                ));
            }
        }
        if !(0.0..=MAX_SUN_RADIUS_DEG).contains(&self.sun_radius_deg) {
            return Err(ShadeError::parameter(
                "sun radius",
                format!(
                    "{} is not between 0 and {MAX_SUN_RADIUS_DEG} degrees",
                    self.sun_radius_deg
                ),
            ));
        }
        for (name, rays) in [("sun rays", self.sun_rays), ("sky rays", self.sky_rays)] {
            if !(1..=MAX_RAYS_PER_SAMPLE).contains(&rays) {
                return Err(ShadeError::parameter(
                    name,
                    format!("{rays} is not between 1 and {MAX_RAYS_PER_SAMPLE}"),
                ));
            }
        }
        Ok(())
    }

    /// Whether any layer asked for needs rays towards the suns.
    pub fn needs_sun_rays(&self) -> bool {
        self.layers.iter().any(|l| l.needs_sun_rays())
    }

    /// Whether any layer asked for needs rays towards the sky.
    pub fn needs_sky_rays(&self) -> bool {
        self.layers.iter().any(|l| l.needs_sky_rays())
    }

    /// Rays per sample the map casts.
    pub fn rays_per_sample(&self) -> u64 {
        let sun_rays = if self.sun_radius_deg > 0.0 { self.sun_rays } else { 1 };
        let sun = if self.needs_sun_rays() { self.suns.len() as u64 * sun_rays as u64 } else { 0 };
        let sky = if self.needs_sky_rays() { self.sky_rays as u64 } else { 0 };
        sun + sky
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_is_valid_and_bad_values_are_named() {
        assert_eq!(ShadeMapParams::default().validate(), Ok(()));
        let low = ShadeMapParams {
            suns: vec![SunPosition { azimuth_deg: 10.0, elevation_deg: 0.0 }],
            ..Default::default()
        };
        assert!(low.validate().unwrap_err().to_string().contains("sun elevation"));
        let twice =
            ShadeMapParams { layers: vec![ShadeLayer::Sky, ShadeLayer::Sky], ..Default::default() };
        assert!(twice.validate().unwrap_err().to_string().contains("sky is asked for twice"));
        let rays = ShadeMapParams { sky_rays: 0, ..Default::default() };
        assert!(rays.validate().unwrap_err().to_string().contains("sky rays"));
        let radius = ShadeMapParams { sun_radius_deg: f64::NAN, ..Default::default() };
        assert!(radius.validate().unwrap_err().to_string().contains("sun radius"));
        let sky_only =
            ShadeMapParams { layers: vec![ShadeLayer::Sky], suns: vec![], ..Default::default() };
        assert_eq!(sky_only.validate(), Ok(()));
    }

    #[test]
    fn rays_per_sample_counts_what_the_layers_need() {
        let mut params = ShadeMapParams::default();
        assert_eq!(params.rays_per_sample(), 1 + 64);
        params.sun_radius_deg = 0.5;
        params.suns.push(SunPosition { azimuth_deg: 0.0, elevation_deg: 30.0 });
        assert_eq!(params.rays_per_sample(), 2 * 16 + 64);
        params.layers = vec![ShadeLayer::Hillshade];
        assert_eq!(params.rays_per_sample(), 0);
    }
}
