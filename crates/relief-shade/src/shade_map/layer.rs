//! The layers a shade map holds, and their names on the command line and in files.

use std::fmt;
use std::str::FromStr;

/// One layer of a shade map: a value per sample of the height field, from 0 (dark, or
/// closed to the sky) to 1 (lit, or open).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShadeLayer {
    /// Cast shadows: the fraction of the suns (and of each sun's disc) that the sample sees.
    Shadow,
    /// The sky-view factor: the fraction of the sky's hemisphere the sample sees.
    Sky,
    /// The Lambert hillshade of the suns (local slope only, as `gdaldem hillshade`).
    Hillshade,
    /// The map layer: sunlight on the slope where the sun is seen, plus the sky's light.
    Combined,
}

impl ShadeLayer {
    /// Every layer, in the order of `--layers`' help.
    pub const ALL: [ShadeLayer; 4] =
        [ShadeLayer::Shadow, ShadeLayer::Sky, ShadeLayer::Hillshade, ShadeLayer::Combined];

    /// The layer's name: on the command line, and as a GeoTIFF band's description.
    pub fn name(self) -> &'static str {
        match self {
            ShadeLayer::Shadow => "shadow",
            ShadeLayer::Sky => "sky",
            ShadeLayer::Hillshade => "hillshade",
            ShadeLayer::Combined => "combined",
        }
    }

    /// Whether the layer needs rays towards the suns.
    pub fn needs_sun_rays(self) -> bool {
        matches!(self, ShadeLayer::Shadow | ShadeLayer::Combined)
    }

    /// Whether the layer needs rays towards the sky.
    pub fn needs_sky_rays(self) -> bool {
        matches!(self, ShadeLayer::Sky | ShadeLayer::Combined)
    }

    /// Whether the layer depends on the suns at all.
    pub fn needs_suns(self) -> bool {
        !matches!(self, ShadeLayer::Sky)
    }
}

impl fmt::Display for ShadeLayer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for ShadeLayer {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ShadeLayer::ALL.into_iter().find(|layer| layer.name() == s).ok_or_else(|| {
            format!("unknown layer '{s}' (expected shadow, sky, hillshade or combined)")
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back() {
        for layer in ShadeLayer::ALL {
            assert_eq!(layer.name().parse::<ShadeLayer>(), Ok(layer));
        }
        let error = "shadows".parse::<ShadeLayer>().unwrap_err();
        assert_eq!(error, "unknown layer 'shadows' (expected shadow, sky, hillshade or combined)");
    }
}
