//! How a height field's heights are coloured: a named colour map over a range of heights
//! (relief-shade's [`ColourMap`]), given in metres and laid over the world's (exaggerated)
//! heights.

use crate::RenderError;
use relief_core::Aabb;
use relief_shade::{Albedo, ColourMap, HeightColourMap, HypsometricRamp};

/// How heights are coloured where no texture is draped: all `None` is relief's default look,
/// the hypsometric ramp over the terrain's own heights.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ColourSettings {
    /// The colour map [default: terrain, the hypsometric ramp with rock on steep slopes].
    pub map: Option<ColourMap>,
    /// The heights in metres (before `--z-scale`) at the map's low and high ends [default: the
    /// terrain's lowest and highest].
    pub height_range: Option<(f64, f64)>,
    /// The height in metres where `bathymetry` turns from water to land [default: 0].
    pub sea_level: Option<f64>,
}

impl ColourSettings {
    /// Whether any colour option is given.
    pub fn given(&self) -> bool {
        self.map.is_some() || self.height_range.is_some() || self.sea_level.is_some()
    }

    /// Refuses settings that are wrong whatever the terrain: a range that is not finite and
    /// increasing, a sea level that is not finite, or one given to a map without a sea.
    pub fn validate(&self) -> Result<(), RenderError> {
        if let Some((lo, hi)) = self.height_range {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(RenderError::Colours(format!(
                    "the height range {lo},{hi} must be two finite heights, the lower first"
                )));
            }
        }
        if let Some(sea) = self.sea_level {
            if !sea.is_finite() {
                return Err(RenderError::Colours(format!("the sea level {sea} is not finite")));
            }
            let map = self.map.unwrap_or(ColourMap::Terrain);
            if !map.has_sea_level() {
                return Err(RenderError::Colours(format!(
                    "a sea level applies to the bathymetry colour map only, not to {map}"
                )));
            }
        }
        Ok(())
    }

    /// Refuses any colour option for a scene coloured by its materials (`what`: "MLHM
    /// scenes", ...).
    pub fn refuse_for(&self, what: &str) -> Result<(), RenderError> {
        if self.given() {
            return Err(RenderError::Colours(format!(
                "a colour map applies to height fields and tile stores, not to {what} \
                 (coloured by their materials)"
            )));
        }
        Ok(())
    }

    /// The albedo of a terrain within `bounds` (world heights, which are `z_scale` times the
    /// metres): the hypsometric ramp for `terrain` (exactly relief's default look when no
    /// option is given), a [`HeightColourMap`] for any other map.
    pub fn albedo(&self, bounds: &Aabb, z_scale: f64) -> Result<Albedo, RenderError> {
        self.validate()?;
        let (lo, hi) = self.world_range(bounds, z_scale);
        Ok(match self.map.unwrap_or(ColourMap::Terrain) {
            ColourMap::Terrain => Albedo::Hypsometric(HypsometricRamp::new(lo, hi)?),
            map => Albedo::Mapped(HeightColourMap::new(map, lo, hi, self.sea_z() * z_scale)?),
        })
    }

    /// The colour map over heights in metres (before `z_scale`) for a terrain within
    /// `bounds`: what a legend shows.
    pub fn in_metres(&self, bounds: &Aabb, z_scale: f64) -> Result<HeightColourMap, RenderError> {
        self.validate()?;
        let (lo, hi) = self.world_range(bounds, z_scale);
        let map = self.map.unwrap_or(ColourMap::Terrain);
        Ok(HeightColourMap::new(map, lo / z_scale, hi / z_scale, self.sea_z())?)
    }

    /// The range in world heights: the one asked for, scaled, else the terrain's own.
    fn world_range(&self, bounds: &Aabb, z_scale: f64) -> (f64, f64) {
        match self.height_range {
            Some((lo, hi)) => (lo * z_scale, hi * z_scale),
            None => (bounds.min.z, bounds.max.z),
        }
    }

    /// The sea level in metres.
    fn sea_z(&self) -> f64 {
        self.sea_level.unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::DVec3;

    fn bounds() -> Aabb {
        Aabb::new(DVec3::new(0.0, 0.0, -300.0), DVec3::new(10.0, 10.0, 900.0))
    }

    #[test]
    fn no_option_is_the_default_ramp() {
        let albedo = ColourSettings::default().albedo(&bounds(), 3.0).unwrap();
        assert_eq!(albedo, Albedo::Hypsometric(HypsometricRamp::new(-300.0, 900.0).unwrap()));
        let metres = ColourSettings::default().in_metres(&bounds(), 3.0).unwrap();
        assert_eq!((metres.min_z, metres.max_z), (-100.0, 300.0));
    }

    #[test]
    fn ranges_and_sea_levels_are_in_metres() {
        let settings = ColourSettings {
            map: Some(ColourMap::Bathymetry),
            height_range: Some((-50.0, 50.0)),
            sea_level: Some(10.0),
        };
        let Albedo::Mapped(world) = settings.albedo(&bounds(), 2.0).unwrap() else {
            panic!("a mapped albedo")
        };
        assert_eq!((world.min_z, world.max_z, world.sea_level), (-100.0, 100.0, 20.0));
        let metres = settings.in_metres(&bounds(), 2.0).unwrap();
        assert_eq!((metres.min_z, metres.max_z, metres.sea_level), (-50.0, 50.0, 10.0));
    }

    #[test]
    fn wrong_settings_say_why() {
        let reversed = ColourSettings { height_range: Some((5.0, 1.0)), ..Default::default() };
        assert!(reversed.validate().unwrap_err().to_string().contains("the lower first"));
        let sea = ColourSettings {
            map: Some(ColourMap::Viridis),
            sea_level: Some(3.0),
            ..Default::default()
        };
        let message = sea.validate().unwrap_err().to_string();
        assert!(message.contains("bathymetry colour map only, not to viridis"), "{message}");
        let terrain_sea = ColourSettings { sea_level: Some(3.0), ..Default::default() };
        assert!(terrain_sea.validate().is_err());
    }
}
