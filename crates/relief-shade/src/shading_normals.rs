//! Which normal lights a hit: the exact facet's, as the G-buffer holds it, or a smooth one
//! interpolated from the height field's gradient at the samples.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use relief_core::{DVec3, SmoothNormals};

/// How a height field's `triangles` surface is shaded, as the command line and Python name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum NormalStyle {
    /// Normals interpolated over each triangle from the samples' gradients, as a DEM viewer
    /// shades a terrain: no facets show.
    #[default]
    Smooth,
    /// Each triangle's exact normal: the facets show.
    Faceted,
}

impl NormalStyle {
    /// Both styles, in a fixed order.
    pub const ALL: [NormalStyle; 2] = [NormalStyle::Smooth, NormalStyle::Faceted];

    /// The name on the command line and in Python.
    pub fn name(self) -> &'static str {
        match self {
            NormalStyle::Smooth => "smooth",
            NormalStyle::Faceted => "faceted",
        }
    }
}

impl fmt::Display for NormalStyle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for NormalStyle {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "smooth" => Ok(NormalStyle::Smooth),
            "faceted" => Ok(NormalStyle::Faceted),
            other => Err(format!("unknown shading normals '{other}' (expected smooth or faceted)")),
        }
    }
}

/// The normals the deferred pass lights hits with.
///
/// The G-buffer always holds the exact geometric normal (what `--normals` writes); with
/// `Smooth`, shading looks up the surface's smooth normal at each hit instead, for the
/// lighting, the specular lobe and the albedo's slope. Whether the sun can reach a hit (the
/// facing test and the shadow ray's origin) stays the geometric normal's: see
/// [`ShadingNormals::at`].
#[derive(Clone, Default)]
pub enum ShadingNormals {
    /// The G-buffer's geometric normal.
    #[default]
    Faceted,
    /// The smooth normal the surface gives at the hit (a height field, or a tiled terrain's
    /// tiles), where it gives one; the geometric normal elsewhere.
    Smooth(Arc<dyn SmoothNormals>),
}

impl ShadingNormals {
    /// Smooth normals of `surface`.
    pub fn smooth(surface: Arc<dyn SmoothNormals>) -> Self {
        ShadingNormals::Smooth(surface)
    }

    /// The style these normals are.
    pub fn style(&self) -> NormalStyle {
        match self {
            ShadingNormals::Faceted => NormalStyle::Faceted,
            ShadingNormals::Smooth(_) => NormalStyle::Smooth,
        }
    }

    /// The normal that lights a hit at `position`, `distance` from the eye, whose unit
    /// geometric normal is `geometric`.
    ///
    /// Smooth where the hit is on the terrain's top (its geometric normal points up) and the
    /// surface gives a normal there; the geometric normal on the solid's walls and bottom
    /// (normals with no upward part), for a ray that starts inside the solid (distance 0),
    /// and where the surface gives none (outside it, over a hole).
    #[inline]
    pub fn at(&self, position: DVec3, geometric: DVec3, distance: f64) -> DVec3 {
        match self {
            ShadingNormals::Faceted => geometric,
            ShadingNormals::Smooth(surface) => {
                if geometric.z > 0.0 && distance > 0.0 {
                    surface.smooth_normal(position).unwrap_or(geometric)
                } else {
                    geometric
                }
            }
        }
    }
}

impl fmt::Debug for ShadingNormals {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.style().name())
    }
}

impl PartialEq for ShadingNormals {
    /// Faceted equals faceted; smooth normals are equal when they are the same surface's.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (ShadingNormals::Faceted, ShadingNormals::Faceted) => true,
            (ShadingNormals::Smooth(a), ShadingNormals::Smooth(b)) => {
                std::ptr::addr_eq(Arc::as_ptr(a), Arc::as_ptr(b))
            }
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::{GridGeometry, HeightField};

    #[test]
    fn names_round_trip_and_bad_names_say_what_is_expected() {
        for style in NormalStyle::ALL {
            assert_eq!(style.name().parse::<NormalStyle>(), Ok(style));
        }
        let err = "flat".parse::<NormalStyle>().unwrap_err();
        assert!(err.contains("smooth or faceted"), "{err}");
    }

    #[test]
    fn walls_and_starts_inside_keep_the_geometric_normal() {
        let samples: Vec<f32> = (0..16).map(|k| ((k % 4) * (k % 4)) as f32).collect();
        let field = Arc::new(HeightField::new(4, 4, samples, GridGeometry::unit()).unwrap());
        let smooth = ShadingNormals::smooth(field.clone());
        let on_top = DVec3::new(1.7, 1.2, 2.0);
        let facet = DVec3::new(-0.9, 0.0, 0.3).normalize();
        let n = smooth.at(on_top, facet, 5.0);
        assert_eq!(Some(n), field.smooth_normal(on_top));
        assert_ne!(n, facet);
        assert_eq!(smooth.at(on_top, DVec3::X, 5.0), DVec3::X, "a wall");
        assert_eq!(smooth.at(on_top, facet, 0.0), facet, "a ray starting inside");
        assert_eq!(smooth.at(DVec3::new(9.0, 1.0, 0.0), facet, 5.0), facet, "outside");
        assert_eq!(ShadingNormals::Faceted.at(on_top, facet, 5.0), facet);
        assert_eq!(smooth, smooth.clone());
        assert_ne!(smooth, ShadingNormals::Faceted);
    }
}
