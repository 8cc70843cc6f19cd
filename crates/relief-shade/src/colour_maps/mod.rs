//! Named colour maps for heights: the hypsometric `terrain` ramp, `bathymetry` (blues below
//! the sea level, land colours above), `greys`, and the perceptually uniform `viridis`,
//! `cividis` and `magma` from their published control points.

mod bathymetry;
mod cividis;
mod height_colour_map;
mod magma;
mod map_table;
mod viridis;

pub use height_colour_map::HeightColourMap;
pub(crate) use map_table::MapTable;

use std::fmt;
use std::str::FromStr;

use relief_core::DVec3;

use crate::colour_ramp::hypsometric_colour;
use crate::tonemap::srgb_to_linear;
use crate::ShadeError;

/// A named colour map: a colour for every position `u` from 0 (the low end of the heights) to
/// 1 (the high end).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ColourMap {
    /// The hypsometric ramp (green lowlands, brown, grey rock, white snow): relief's default.
    Terrain,
    /// Blues below the sea level, deep to shallow, for `u` in `[0, 0.5)`; the land colours of
    /// `terrain` above it, for `u` in `[0.5, 1]`: [`HeightColourMap`] puts the sea level at 0.5.
    Bathymetry,
    /// Dark grey to white, even steps in sRGB.
    Greys,
    /// viridis (van der Walt and Smith 2015): perceptually uniform, blue-purple to yellow.
    Viridis,
    /// cividis (Nuñez et al. 2018): perceptually uniform and readable with colour-vision
    /// deficiency, blue to yellow.
    Cividis,
    /// magma (van der Walt and Smith 2015): perceptually uniform, black to light yellow.
    Magma,
}

impl ColourMap {
    /// Every colour map, in the order their names are listed.
    pub const ALL: [ColourMap; 6] = [
        ColourMap::Terrain,
        ColourMap::Bathymetry,
        ColourMap::Greys,
        ColourMap::Viridis,
        ColourMap::Cividis,
        ColourMap::Magma,
    ];

    /// The map's name, as the command line and Python take it.
    pub fn name(self) -> &'static str {
        match self {
            ColourMap::Terrain => "terrain",
            ColourMap::Bathymetry => "bathymetry",
            ColourMap::Greys => "greys",
            ColourMap::Viridis => "viridis",
            ColourMap::Cividis => "cividis",
            ColourMap::Magma => "magma",
        }
    }

    /// Every map's name, comma-separated, for messages.
    pub fn known_names() -> String {
        Self::ALL.map(ColourMap::name).join(", ")
    }

    /// The map named `name` (case-insensitive); an error listing the known names otherwise.
    pub fn from_name(name: &str) -> Result<ColourMap, ShadeError> {
        Self::ALL.into_iter().find(|map| map.name().eq_ignore_ascii_case(name.trim())).ok_or_else(
            || {
                ShadeError::parameter(
                    "colour map",
                    format!("unknown name '{name}' (known: {})", Self::known_names()),
                )
            },
        )
    }

    /// Whether the map splits at a sea level (`bathymetry`).
    pub fn has_sea_level(self) -> bool {
        self == ColourMap::Bathymetry
    }

    /// The map's linear-RGB colour at position `u` (clamped to `[0, 1]`, NaN taken as 0),
    /// from its tabulated samples (within half an 8-bit sRGB step of
    /// [`ColourMap::colour_by_formula`]): the colour the shading uses.
    pub fn colour(self, u: f64) -> DVec3 {
        self.table().colour(u)
    }

    /// The map's linear-RGB colour at position `u` (clamped to `[0, 1]`, NaN taken as 0),
    /// computed: control points interpolated in sRGB (which looks even), then made linear.
    pub fn colour_by_formula(self, u: f64) -> DVec3 {
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
        match self {
            ColourMap::Terrain => hypsometric_colour(u),
            ColourMap::Bathymetry if u < 0.5 => bathymetry::water_colour(2.0 * u),
            ColourMap::Bathymetry => hypsometric_colour(2.0 * u - 1.0),
            ColourMap::Greys => linear_from_srgb(DVec3::splat(0.12 + 0.84 * u)),
            ColourMap::Viridis => listed(&viridis::VIRIDIS, u),
            ColourMap::Cividis => listed(&cividis::CIVIDIS, u),
            ColourMap::Magma => listed(&magma::MAGMA, u),
        }
    }

    /// The map's samples, tabulated once.
    pub(crate) fn table(self) -> &'static MapTable {
        use std::sync::LazyLock;
        type Lazy = LazyLock<MapTable>;
        static TERRAIN: Lazy = Lazy::new(|| MapTable::build(ColourMap::Terrain));
        static BATHYMETRY: Lazy = Lazy::new(|| MapTable::build(ColourMap::Bathymetry));
        static GREYS: Lazy = Lazy::new(|| MapTable::build(ColourMap::Greys));
        static VIRIDIS: Lazy = Lazy::new(|| MapTable::build(ColourMap::Viridis));
        static CIVIDIS: Lazy = Lazy::new(|| MapTable::build(ColourMap::Cividis));
        static MAGMA: Lazy = Lazy::new(|| MapTable::build(ColourMap::Magma));
        match self {
            ColourMap::Terrain => &TERRAIN,
            ColourMap::Bathymetry => &BATHYMETRY,
            ColourMap::Greys => &GREYS,
            ColourMap::Viridis => &VIRIDIS,
            ColourMap::Cividis => &CIVIDIS,
            ColourMap::Magma => &MAGMA,
        }
    }
}

impl fmt::Display for ColourMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ColourMap {
    type Err = ShadeError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ColourMap::from_name(s)
    }
}

/// The colour at `u` of evenly spaced sRGB control `points`, interpolated in sRGB, linear.
fn listed(points: &[[f64; 3]], u: f64) -> DVec3 {
    let x = u * (points.len() - 1) as f64;
    let k = (x as usize).min(points.len() - 2);
    let (a, b) = (DVec3::from(points[k]), DVec3::from(points[k + 1]));
    linear_from_srgb(a.lerp(b, x - k as f64))
}

/// A colour in sRGB (`[0, 1]` a channel) made linear.
pub(crate) fn linear_from_srgb(srgb: DVec3) -> DVec3 {
    let f = |v: f64| srgb_to_linear(v as f32) as f64;
    DVec3::new(f(srgb.x), f(srgb.y), f(srgb.z))
}

/// The CIE L* lightness (0 to 100) of a linear-RGB colour (sRGB primaries, D65).
pub fn lightness(linear: DVec3) -> f64 {
    let y = linear.dot(DVec3::new(0.2126, 0.7152, 0.0722));
    let f = if y > (6.0f64 / 29.0).powi(3) {
        y.cbrt()
    } else {
        y / (3.0 * (6.0f64 / 29.0).powi(2)) + 4.0 / 29.0
    };
    116.0 * f - 16.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn srgb_of(linear: DVec3) -> DVec3 {
        let f = |v: f64| crate::tonemap::linear_to_srgb(v as f32) as f64;
        DVec3::new(f(linear.x), f(linear.y), f(linear.z))
    }

    #[test]
    fn names_round_trip_and_unknown_names_list_the_known_ones() {
        for map in ColourMap::ALL {
            assert_eq!(ColourMap::from_name(map.name()).unwrap(), map);
            assert_eq!(map.to_string().parse::<ColourMap>().unwrap(), map);
        }
        assert_eq!(ColourMap::from_name("Viridis").unwrap(), ColourMap::Viridis);
        let error = ColourMap::from_name("jet").unwrap_err().to_string();
        assert_eq!(
            error,
            "invalid colour map: unknown name 'jet' (known: terrain, bathymetry, greys, \
             viridis, cividis, magma)"
        );
    }

    #[test]
    fn listed_maps_pass_through_their_published_control_points() {
        for (map, points) in [
            (ColourMap::Viridis, &viridis::VIRIDIS),
            (ColourMap::Cividis, &cividis::CIVIDIS),
            (ColourMap::Magma, &magma::MAGMA),
        ] {
            for (k, point) in points.iter().enumerate() {
                let u = k as f64 / 255.0;
                let got = srgb_of(map.colour_by_formula(u));
                let error = (got - DVec3::from(*point)).abs().max_element();
                assert!(error < 1e-5, "{map} at point {k}: {got} against {point:?}");
                // The table smooths each point's corner over 1/4096 of the map: a tenth of an
                // 8-bit step at most.
                let tabulated = srgb_of(map.colour(u));
                let error = (tabulated - DVec3::from(*point)).abs().max_element() * 255.0;
                assert!(error < 0.1, "{map}'s table at point {k}: {tabulated} against {point:?}");
            }
        }
        // The published ends, as matplotlib lists them.
        let viridis = srgb_of(ColourMap::Viridis.colour_by_formula(0.0));
        assert!((viridis - DVec3::new(0.267004, 0.004874, 0.329415)).abs().max_element() < 1e-5);
        let magma = srgb_of(ColourMap::Magma.colour_by_formula(1.0));
        assert!((magma - DVec3::new(0.987053, 0.991438, 0.749504)).abs().max_element() < 1e-5);
    }

    #[test]
    fn perceptually_uniform_maps_grow_lighter_all_the_way() {
        for map in [ColourMap::Viridis, ColourMap::Cividis, ColourMap::Magma, ColourMap::Greys] {
            let mut previous = lightness(map.colour(0.0));
            let start = previous;
            for k in 1..=1000 {
                let l = lightness(map.colour(k as f64 / 1000.0));
                assert!(l > previous - 1e-9, "{map}: lightness falls at {k}: {previous} to {l}");
                previous = l;
            }
            assert!(previous - start > 60.0, "{map} spans {start} to {previous} in L*");
        }
    }

    #[test]
    fn tables_follow_the_formulas() {
        for map in ColourMap::ALL {
            let mut worst = 0.0f64;
            for k in 0..=20_000 {
                let u = k as f64 / 20_000.0;
                // The one jump, bathymetry's at the sea level, is not a point a table can hold.
                if map == ColourMap::Bathymetry && (u - 0.5).abs() < 1e-3 {
                    continue;
                }
                let error = srgb_of(map.colour(u)) - srgb_of(map.colour_by_formula(u));
                worst = worst.max(error.abs().max_element() * 255.0);
            }
            // In 8-bit sRGB steps: the sharpest corner, the terrain ramp's snow line, is the
            // worst.
            assert!(worst < 0.5, "{map}'s table is {worst} steps off");
        }
    }

    #[test]
    fn bathymetry_is_blue_below_its_middle_and_land_above() {
        for k in 0..50 {
            let c = ColourMap::Bathymetry.colour(k as f64 / 100.0);
            assert!(c.z > c.x && c.z > c.y, "water at {k}: {c}");
        }
        for k in 50..=100 {
            let u = k as f64 / 100.0;
            assert_eq!(
                ColourMap::Bathymetry.colour_by_formula(u),
                hypsometric_colour(2.0 * u - 1.0)
            );
        }
        let shallow = lightness(ColourMap::Bathymetry.colour(0.49));
        assert!(shallow > lightness(ColourMap::Bathymetry.colour(0.0)) + 30.0, "deep is dark");
    }

    #[test]
    fn terrain_is_the_hypsometric_ramp() {
        for k in 0..=100 {
            let u = k as f64 / 100.0;
            assert_eq!(ColourMap::Terrain.colour_by_formula(u), hypsometric_colour(u));
        }
    }
}
