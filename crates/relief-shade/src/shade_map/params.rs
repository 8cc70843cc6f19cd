//! What a shade map is asked for: its layers, suns and ray counts.

use super::{Anisotropy, ShadeLayer, SkyModel};
use crate::horizon::{Facing, HorizonParams};
use crate::{sun_direction, ShadeError};
use relief_core::{DVec3, GridGeometry, Surface};

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

/// The share of the sun's cast shadow in the [`ShadeLayer::SkyIllumination`] layer, beside
/// `1 - SUN_SHARE_OF_SKY_ILLUMINATION` times the sky's diffuse light (RVT's shaded sky
/// illumination: 0.8 sky, 0.2 shadow).
pub const SUN_SHARE_OF_SKY_ILLUMINATION: f64 = 0.2;

/// One position of the sun for the insolation layers, and what it stands for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InsolationSun {
    /// Compass direction in degrees, clockwise from north.
    pub azimuth_deg: f64,
    /// Apparent elevation above the horizon in degrees (may be negative: then it counts zero).
    pub elevation_deg: f64,
    /// The hours this position stands for (the time step).
    pub hours: f64,
    /// The direct-beam irradiance normal to the sun's rays, W/m².
    pub beam_w_m2: f64,
}

/// Most rays a map may cast per sample and sun.
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
    /// The horizons' directions, observer height, radius and curvature, for the layers built
    /// on them.
    pub horizon: HorizonParams,
    /// The weighting of the anisotropic sky-view factor.
    pub anisotropy: Anisotropy,
    /// The sky of the sky-illumination layer.
    pub sky_model: SkyModel,
    /// The sun's positions over the period of the insolation layers.
    pub insolation: Vec<InsolationSun>,
}

impl Default for ShadeMapParams {
    /// The combined layer, one point sun from the north-west 45 degrees up, horizons in 32
    /// directions, RVT's anisotropy, an overcast sky, no insolation suns.
    fn default() -> Self {
        ShadeMapParams {
            layers: vec![ShadeLayer::Combined],
            suns: vec![SunPosition::CARTOGRAPHIC],
            sun_radius_deg: 0.0,
            sun_rays: 16,
            horizon: HorizonParams::default(),
            anisotropy: Anisotropy::default(),
            sky_model: SkyModel::Overcast,
            insolation: Vec::new(),
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
        if !(1..=MAX_RAYS_PER_SAMPLE).contains(&self.sun_rays) {
            return Err(ShadeError::parameter(
                "sun rays",
                format!("{} is not between 1 and {MAX_RAYS_PER_SAMPLE}", self.sun_rays),
            ));
        }
        self.horizon.validate()?;
        let a = &self.anisotropy;
        if !(a.main_direction_deg.is_finite()
            && (0.0..=1.0).contains(&a.min_weight)
            && a.polynomial >= 0)
        {
            return Err(ShadeError::parameter(
                "anisotropy",
                format!("{a:?}: the main direction must be finite, the minimum weight in [0, 1], the power >= 0"),
            ));
        }
        for sun in &self.insolation {
            if !(sun.azimuth_deg.is_finite()
                && sun.elevation_deg.is_finite()
                && sun.hours.is_finite()
                && sun.hours >= 0.0
                && sun.beam_w_m2.is_finite()
                && sun.beam_w_m2 >= 0.0)
            {
                return Err(ShadeError::parameter(
                    "insolation sun",
                    format!("{sun:?} is not finite and >= 0"),
                ));
            }
        }
        if self.layers.iter().any(|l| l.needs_insolation_suns()) && self.insolation.is_empty() {
            return Err(ShadeError::parameter(
                "insolation",
                "no sun position given (a date, a time or a period)",
            ));
        }
        Ok(())
    }

    /// The bands of the layers, in order, with their names: one per layer, but the horizon's
    /// one per direction (`horizon-000.0`, `horizon-011.2`, ...).
    pub fn band_names(&self) -> Vec<(ShadeLayer, String)> {
        let mut names = Vec::new();
        for &layer in &self.layers {
            if layer == ShadeLayer::Horizon {
                for k in 0..self.horizon.azimuths as usize {
                    names.push((layer, format!("horizon-{:05.1}", self.horizon.azimuth_deg(k))));
                }
            } else {
                names.push((layer, layer.name().to_string()));
            }
        }
        names
    }

    /// How many bands `layer` has.
    pub fn bands_of(&self, layer: ShadeLayer) -> usize {
        if layer == ShadeLayer::Horizon {
            self.horizon.azimuths as usize
        } else {
            1
        }
    }

    /// Whether any layer asked for is built on the horizons of the terrain seen `facing`.
    pub fn needs_horizons(&self, facing: Facing) -> bool {
        self.layers.iter().any(|l| l.needs_horizons(facing))
    }

    /// How many horizon engines the layers need: one for the terrain, one for it upside down.
    pub fn horizon_engines(&self) -> u32 {
        [Facing::Up, Facing::Down].into_iter().filter(|&f| self.needs_horizons(f)).count() as u32
    }

    /// Refuses a `surface` the layers cannot be exact for: those built on horizons are exact
    /// for the `triangles` surface only.
    pub fn check_surface(&self, surface: Surface) -> Result<(), ShadeError> {
        let built_on_horizons: Vec<&str> =
            self.layers.iter().filter(|l| l.builds_on_horizons()).map(|l| l.name()).collect();
        if surface == Surface::Boxes && !built_on_horizons.is_empty() {
            return Err(ShadeError::parameter(
                "surface",
                format!(
                    "boxes: the layers built on horizons ({}) are exact for the triangles \
                     surface only",
                    built_on_horizons.join(", ")
                ),
            ));
        }
        Ok(())
    }

    /// Whether any layer asked for needs each sample's normal.
    pub fn needs_normal(&self) -> bool {
        self.layers.iter().any(|l| l.needs_normal())
    }

    /// Whether any layer asked for needs rays towards the suns.
    pub fn needs_sun_rays(&self) -> bool {
        self.layers.iter().any(|l| l.needs_sun_rays())
    }

    /// How many samples around a block a window must hold for the map of the block to be the
    /// whole raster's: the sun rays' reach over a raster whose samples span `span` (its lowest
    /// and highest), placed by `geometry`; the radius of the horizons if one is given (without
    /// one they go on past the window, see [`super::ShadeRegion::far`]); and the hillshade's
    /// neighbours. `None` when the reach is not finite.
    pub fn halo_samples(&self, span: [f32; 2], geometry: &GridGeometry) -> Option<usize> {
        let spacing = geometry.dx.min(geometry.dy);
        let mut metres: f64 = 0.0;
        if self.needs_sun_rays() {
            let relief = f64::from(span[1] - span[0]).max(0.0) * geometry.z_scale;
            let lowest = self.suns.iter().map(|s| s.elevation_deg).fold(90.0, f64::min);
            let lowest = (lowest - self.sun_radius_deg).to_radians();
            if lowest <= 0.0 {
                return None;
            }
            // Past this horizontal distance a ray from the surface is above every sample.
            metres = metres.max(relief / lowest.tan() * (1.0 + 1e-6));
        }
        if let Some(radius) = self.horizon.radius {
            if [Facing::Up, Facing::Down].into_iter().any(|f| self.needs_horizons(f)) {
                metres = metres.max(radius);
            }
        }
        let samples = (metres / spacing).ceil();
        // The cells around the farthest point, and the hillshade's 3 x 3.
        (samples.is_finite() && samples < 1e12).then(|| samples as usize + 3)
    }

    /// Whether the horizons above the horizontal are all the layers need (all but the
    /// horizon and the positive openness).
    pub fn level_only(&self) -> bool {
        !self.layers.iter().any(|l| matches!(l, ShadeLayer::Horizon | ShadeLayer::OpennessPos))
    }

    /// Rays per sample the map casts.
    pub fn rays_per_sample(&self) -> u64 {
        let sun_rays = if self.sun_radius_deg > 0.0 { self.sun_rays } else { 1 };
        if self.needs_sun_rays() {
            self.suns.len() as u64 * sun_rays as u64
        } else {
            0
        }
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
        let rays = ShadeMapParams { sun_rays: 0, ..Default::default() };
        assert!(rays.validate().unwrap_err().to_string().contains("sun rays"));
        let directions = ShadeMapParams {
            horizon: HorizonParams { azimuths: 0, ..Default::default() },
            ..Default::default()
        };
        assert!(directions.validate().unwrap_err().to_string().contains("azimuths"));
        let no_period =
            ShadeMapParams { layers: vec![ShadeLayer::Insolation], ..Default::default() };
        assert!(no_period.validate().unwrap_err().to_string().contains("no sun position"));
        let radius = ShadeMapParams { sun_radius_deg: f64::NAN, ..Default::default() };
        assert!(radius.validate().unwrap_err().to_string().contains("sun radius"));
        let sky_only =
            ShadeMapParams { layers: vec![ShadeLayer::Sky], suns: vec![], ..Default::default() };
        assert_eq!(sky_only.validate(), Ok(()));
    }

    #[test]
    fn rays_per_sample_counts_what_the_layers_need() {
        let mut params = ShadeMapParams::default();
        assert_eq!(params.rays_per_sample(), 1);
        params.sun_radius_deg = 0.5;
        params.suns.push(SunPosition { azimuth_deg: 0.0, elevation_deg: 30.0 });
        assert_eq!(params.rays_per_sample(), 2 * 16);
        params.layers = vec![ShadeLayer::Hillshade];
        assert_eq!(params.rays_per_sample(), 0);
    }
}
