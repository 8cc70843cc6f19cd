//! The layers a shade map holds, and their names on the command line and in files.

use crate::horizon::Facing;
use std::fmt;
use std::str::FromStr;

/// One layer of a shade map: a value per sample of the height field (the horizon: one per
/// direction), in the layer's [`unit`](ShadeLayer::unit).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShadeLayer {
    /// Cast shadows: the fraction of the suns (and of each sun's disc) that the sample sees.
    Shadow,
    /// The sky-view factor (Zakšek et al. 2011): the share of the sky's hemisphere the sample
    /// sees, from its exact horizons.
    Sky,
    /// The Lambert hillshade of the suns (local slope only, as `gdaldem hillshade`).
    Hillshade,
    /// The map layer: sunlight on the slope where the sun is seen, plus the sky's light.
    Combined,
    /// The horizon's elevation angle in each direction, in degrees: one band per direction.
    Horizon,
    /// The anisotropic sky-view factor of the Relief Visualization Toolbox.
    SkyAniso,
    /// Positive openness (Yokoyama et al. 2002), degrees: 90 minus the mean horizon angle.
    OpennessPos,
    /// Negative openness, degrees: the positive openness of the terrain upside down.
    OpennessNeg,
    /// The diffuse light of a uniform or overcast sky on the tilted cell (1 on an open plain),
    /// with the sun's cast shadows (as RVT's sky illumination).
    SkyIllumination,
    /// `gdaldem hillshade -multidirectional`'s hillshade.
    HillshadeMulti,
    /// Direct-beam energy on the tilted cell over the insolation suns, Wh/m².
    Insolation,
    /// Hours of direct sun over the insolation suns.
    SunHours,
}

impl ShadeLayer {
    /// Every layer, in the order of `--layers`' help.
    pub const ALL: [ShadeLayer; 12] = [
        ShadeLayer::Shadow,
        ShadeLayer::Sky,
        ShadeLayer::Hillshade,
        ShadeLayer::Combined,
        ShadeLayer::Horizon,
        ShadeLayer::SkyAniso,
        ShadeLayer::OpennessPos,
        ShadeLayer::OpennessNeg,
        ShadeLayer::SkyIllumination,
        ShadeLayer::HillshadeMulti,
        ShadeLayer::Insolation,
        ShadeLayer::SunHours,
    ];

    /// The layer's name: on the command line, and as a GeoTIFF band's description.
    pub fn name(self) -> &'static str {
        match self {
            ShadeLayer::Shadow => "shadow",
            ShadeLayer::Sky => "sky",
            ShadeLayer::Hillshade => "hillshade",
            ShadeLayer::Combined => "combined",
            ShadeLayer::Horizon => "horizon",
            ShadeLayer::SkyAniso => "sky-aniso",
            ShadeLayer::OpennessPos => "openness-pos",
            ShadeLayer::OpennessNeg => "openness-neg",
            ShadeLayer::SkyIllumination => "sky-illumination",
            ShadeLayer::HillshadeMulti => "hillshade-multi",
            ShadeLayer::Insolation => "insolation",
            ShadeLayer::SunHours => "sun-hours",
        }
    }

    /// The unit of the layer's values.
    pub fn unit(self) -> &'static str {
        match self {
            ShadeLayer::Horizon | ShadeLayer::OpennessPos | ShadeLayer::OpennessNeg => "degrees",
            ShadeLayer::Insolation => "Wh/m2",
            ShadeLayer::SunHours => "hours",
            _ => "0 to 1",
        }
    }

    /// Whether the layer needs rays towards the suns.
    pub fn needs_sun_rays(self) -> bool {
        matches!(self, ShadeLayer::Shadow | ShadeLayer::Combined | ShadeLayer::SkyIllumination)
    }

    /// Whether the layer depends on the suns (`--sun`).
    pub fn needs_suns(self) -> bool {
        matches!(
            self,
            ShadeLayer::Shadow
                | ShadeLayer::Hillshade
                | ShadeLayer::Combined
                | ShadeLayer::SkyIllumination
        )
    }

    /// Whether the layer is built on the horizons of the terrain seen `facing` up or down.
    pub fn needs_horizons(self, facing: Facing) -> bool {
        match facing {
            Facing::Up => matches!(
                self,
                ShadeLayer::Horizon
                    | ShadeLayer::Sky
                    | ShadeLayer::SkyAniso
                    | ShadeLayer::OpennessPos
                    | ShadeLayer::SkyIllumination
                    | ShadeLayer::Insolation
                    | ShadeLayer::SunHours
                    | ShadeLayer::Combined
            ),
            Facing::Down => self == ShadeLayer::OpennessNeg,
        }
    }

    /// Whether the layer is built on horizons, of the terrain or of the terrain upside down.
    pub fn builds_on_horizons(self) -> bool {
        self.needs_horizons(Facing::Up) || self.needs_horizons(Facing::Down)
    }

    /// Whether the layer needs each sample's normal.
    pub fn needs_normal(self) -> bool {
        matches!(
            self,
            ShadeLayer::Hillshade
                | ShadeLayer::Combined
                | ShadeLayer::SkyIllumination
                | ShadeLayer::HillshadeMulti
                | ShadeLayer::Insolation
        )
    }

    /// Whether the layer needs the insolation suns (place and time).
    pub fn needs_insolation_suns(self) -> bool {
        matches!(self, ShadeLayer::Insolation | ShadeLayer::SunHours)
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
            let names: Vec<&str> = ShadeLayer::ALL.iter().map(|l| l.name()).collect();
            format!("unknown layer '{s}' (expected one of {})", names.join(", "))
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
        assert!(
            error.starts_with("unknown layer 'shadows' (expected one of shadow, sky,"),
            "{error}"
        );
    }
}
