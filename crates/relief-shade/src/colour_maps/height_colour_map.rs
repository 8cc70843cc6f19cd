//! A named colour map laid over a range of heights, split at the sea level for `bathymetry`.

use relief_core::DVec3;

use super::ColourMap;
use crate::ShadeError;

/// A [`ColourMap`] over the heights `[min_z, max_z]`: the map's position `u` is 0 at `min_z`
/// and 1 at `max_z`, linearly, except for `bathymetry`, whose water half (`u` in `[0, 0.5)`)
/// spans `[min_z, sea_level]` and whose land half spans `[sea_level, max_z]`, so that the
/// shore falls at the sea level whatever the range. Heights outside the range take the
/// colour of its nearer end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeightColourMap {
    /// The colour map.
    pub map: ColourMap,
    /// World height at the low end of the map.
    pub min_z: f64,
    /// World height at the high end of the map (above `min_z`, or equal to it: everything
    /// then takes the low end's colour).
    pub max_z: f64,
    /// World height of the sea level, where `bathymetry` turns from water to land (any other
    /// map ignores it).
    pub sea_level: f64,
}

/// The map's position as a function of height, in two linear pieces that meet at a pivot:
/// `u = pivot_u + (z - pivot_z) * (below if z < pivot_z else above)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pieces {
    /// The height where the pieces meet.
    pub pivot_z: f64,
    /// The position there.
    pub pivot_u: f64,
    /// Position per unit of height below the pivot.
    pub below: f64,
    /// Position per unit of height above it.
    pub above: f64,
}

impl HeightColourMap {
    /// `map` over `[min_z, max_z]` with the sea level at `sea_level`, checked.
    pub fn new(
        map: ColourMap,
        min_z: f64,
        max_z: f64,
        sea_level: f64,
    ) -> Result<HeightColourMap, ShadeError> {
        let mapped = HeightColourMap { map, min_z, max_z, sea_level };
        mapped.validate()?;
        Ok(mapped)
    }

    /// Checks that the range is finite and ordered and the sea level finite.
    pub fn validate(&self) -> Result<(), ShadeError> {
        if !(self.min_z.is_finite() && self.max_z.is_finite() && self.min_z <= self.max_z) {
            return Err(ShadeError::parameter(
                "height range",
                format!("[{}, {}] is not a finite, ordered range", self.min_z, self.max_z),
            ));
        }
        if !self.sea_level.is_finite() {
            return Err(ShadeError::parameter("sea level", format!("{}", self.sea_level)));
        }
        Ok(())
    }

    /// The position on the map (0 to 1) of world height `z`.
    pub fn position(&self, z: f64) -> f64 {
        let p = self.pieces();
        let h = z - p.pivot_z;
        let u = p.pivot_u + h * if h < 0.0 { p.below } else { p.above };
        if u.is_nan() {
            0.0
        } else {
            u.clamp(0.0, 1.0)
        }
    }

    /// The linear albedo at world height `z`.
    pub fn albedo(&self, z: f64) -> DVec3 {
        self.map.colour(self.position(z))
    }

    /// The two linear pieces of [`HeightColourMap::position`].
    pub(crate) fn pieces(&self) -> Pieces {
        let per_unit =
            |from: f64, to: f64, span: f64| if to > from { span / (to - from) } else { 0.0 };
        if self.map.has_sea_level() {
            Pieces {
                pivot_z: self.sea_level,
                pivot_u: 0.5,
                below: per_unit(self.min_z, self.sea_level, 0.5),
                above: per_unit(self.sea_level, self.max_z, 0.5),
            }
        } else {
            let slope = per_unit(self.min_z, self.max_z, 1.0);
            Pieces { pivot_z: self.min_z, pivot_u: 0.0, below: slope, above: slope }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_maps_span_the_range() {
        let m = HeightColourMap::new(ColourMap::Viridis, 100.0, 300.0, 0.0).unwrap();
        assert_eq!(m.position(100.0), 0.0);
        assert_eq!(m.position(200.0), 0.5);
        assert_eq!(m.position(300.0), 1.0);
        assert_eq!(m.position(-50.0), 0.0);
        assert_eq!(m.position(1e9), 1.0);
        assert_eq!(m.position(f64::NAN), 0.0);
        assert_eq!(m.albedo(300.0), ColourMap::Viridis.colour(1.0));
        let flat = HeightColourMap::new(ColourMap::Greys, 5.0, 5.0, 0.0).unwrap();
        assert_eq!(flat.position(5.0), 0.0);
        assert_eq!(flat.position(6.0), 0.0);
    }

    #[test]
    fn bathymetry_puts_the_shore_at_the_sea_level() {
        let m = HeightColourMap::new(ColourMap::Bathymetry, -1437.0, 2205.0, 0.0).unwrap();
        assert_eq!(m.position(-1437.0), 0.0);
        assert_eq!(m.position(0.0), 0.5);
        assert_eq!(m.position(2205.0), 1.0);
        assert!(m.position(-0.01) < 0.5);
        let (sea, land) = (m.albedo(-1.0), m.albedo(1.0));
        assert!(sea.z > sea.x && sea.z > sea.y, "below the sea level is blue: {sea}");
        assert!(land.y > land.z, "above it green: {land}");
        // A sea level of 100 m moves the shore.
        let raised = HeightColourMap { sea_level: 100.0, ..m };
        let c = raised.albedo(50.0);
        assert!(c.z > c.x && c.z > c.y, "50 m is under a sea at 100 m: {c}");
        // A range wholly above the sea: land colours only.
        let dry = HeightColourMap::new(ColourMap::Bathymetry, 10.0, 20.0, 0.0).unwrap();
        assert!(dry.position(10.0) > 0.5);
    }

    #[test]
    fn bad_ranges_are_refused() {
        assert!(HeightColourMap::new(ColourMap::Magma, 2.0, 1.0, 0.0).is_err());
        assert!(HeightColourMap::new(ColourMap::Magma, f64::NAN, 1.0, 0.0).is_err());
        assert!(HeightColourMap::new(ColourMap::Magma, 0.0, f64::INFINITY, 0.0).is_err());
        assert!(HeightColourMap::new(ColourMap::Bathymetry, 0.0, 1.0, f64::NAN).is_err());
    }
}
