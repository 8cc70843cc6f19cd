//! Where a GeoTIFF lies: its model tags (pixel scale, tie points, transformation) and the few
//! GeoKeys (tag 34735) that place it (model type, raster type, units), and the minimal GeoKey
//! directory relief's writer emits.

use crate::format_error::FormatError;
use crate::georef::geodesy::metres_per_degree;
use crate::georef::geokey_ids::{
    GEOGRAPHIC_TYPE, GEOG_ANGULAR_UNITS, GT_MODEL_TYPE, GT_RASTER_TYPE, PROJECTED_CS_TYPE,
    PROJ_LINEAR_UNITS, USER_DEFINED,
};
use crate::georef::projected_unit::projected_unit;
use crate::DegreeSpacing;
use relief_core::{DVec2, GridGeometry};

/// How model coordinates relate to the earth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ModelType {
    /// Projected coordinates, in a linear unit.
    Projected,
    /// Longitude and latitude.
    Geographic,
}

/// Where in a pixel the georeference puts the pixel's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RasterType {
    /// A pixel is an area: raster point (0, 0) is the outer corner of the first pixel.
    PixelIsArea,
    /// A pixel is a point: raster point (0, 0) is the centre of the first pixel.
    PixelIsPoint,
}

/// The short-valued keys of a GeoKey directory (keys stored in the double or ASCII parameter
/// tags are not needed and are skipped).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct GeoKeys {
    keys: Vec<(u16, u16)>,
    /// The GeoAsciiParams text (the citations), which may name the CRS's unit.
    citation: String,
}

impl GeoKeys {
    /// Parses the `u16` array of a GeoKeyDirectoryTag: a header (version 1, revision, minor
    /// revision, number of keys) and four values per key (id, location, count, value).
    pub(crate) fn parse(directory: &[u16]) -> Result<GeoKeys, FormatError> {
        let bad = |reason: String| FormatError::Format(format!("GeoKeyDirectoryTag: {reason}"));
        let [version, _, _, count, ref entries @ ..] = *directory else {
            return Err(bad(format!("{} values, fewer than its 4-value header", directory.len())));
        };
        if version != 1 {
            return Err(FormatError::Unsupported(format!("GeoKey directory version {version}")));
        }
        let count = usize::from(count);
        if entries.len() < count * 4 {
            return Err(bad(format!(
                "declares {count} keys but holds {} values after its header",
                entries.len()
            )));
        }
        let keys = entries[..count * 4]
            .chunks_exact(4)
            .filter(|key| key[1] == 0 && key[2] == 1)
            .map(|key| (key[0], key[3]))
            .collect();
        Ok(GeoKeys { keys, citation: String::new() })
    }

    /// These keys with the GeoAsciiParams text `ascii` (the citations), which may name the
    /// CRS's unit when no key does.
    pub(crate) fn with_citation(self, ascii: Option<&[u8]>) -> GeoKeys {
        let citation = String::from_utf8_lossy(ascii.unwrap_or(&[])).into_owned();
        GeoKeys { citation, ..self }
    }

    /// The value of the short-valued key `id`.
    fn get(&self, id: u16) -> Option<u16> {
        self.keys.iter().find(|&&(k, _)| k == id).map(|&(_, v)| v)
    }

    /// The model type: GTModelTypeGeoKey, else inferred from which CRS key is present, else
    /// projected. A geocentric model is refused.
    pub(crate) fn model_type(&self) -> Result<ModelType, FormatError> {
        match self.get(GT_MODEL_TYPE) {
            Some(1 | USER_DEFINED) => Ok(ModelType::Projected),
            Some(2) => Ok(ModelType::Geographic),
            Some(3) => {
                Err(FormatError::Unsupported("geocentric model (GTModelTypeGeoKey 3)".into()))
            }
            Some(other) => {
                Err(FormatError::Unsupported(format!("model type GTModelTypeGeoKey {other}")))
            }
            None if self.get(PROJECTED_CS_TYPE).is_none()
                && self.get(GEOGRAPHIC_TYPE).is_some() =>
            {
                Ok(ModelType::Geographic)
            }
            None => Ok(ModelType::Projected),
        }
    }

    /// The raster type (GTRasterTypeGeoKey), PixelIsArea when absent.
    pub(crate) fn raster_type(&self) -> Result<RasterType, FormatError> {
        match self.get(GT_RASTER_TYPE) {
            None | Some(1) => Ok(RasterType::PixelIsArea),
            Some(2) => Ok(RasterType::PixelIsPoint),
            Some(other) => {
                Err(FormatError::Unsupported(format!("raster type GTRasterTypeGeoKey {other}")))
            }
        }
    }

    /// Metres per projected unit: ProjLinearUnitsGeoKey (metre when user-defined), else the
    /// unit of the projected CRS's EPSG code (the EPSG codes in feet are known), else a
    /// citation naming `(ftUS)` or `(ft)`, else the metre. A unit key other than the metre,
    /// the foot and the US survey foot is refused.
    pub(crate) fn metres_per_linear_unit(&self) -> Result<f64, FormatError> {
        let (key, pcs) = (self.get(PROJ_LINEAR_UNITS), self.get(PROJECTED_CS_TYPE));
        match projected_unit(key, pcs, &self.citation) {
            Ok((unit, _)) => Ok(unit.metres()),
            Err(code) => {
                Err(FormatError::Unsupported(format!("linear unit EPSG:{code} (ProjLinearUnits)")))
            }
        }
    }

    /// Refuses geographic coordinates in a unit other than the degree (GeogAngularUnitsGeoKey).
    pub(crate) fn check_degrees(&self) -> Result<(), FormatError> {
        match self.get(GEOG_ANGULAR_UNITS) {
            None | Some(9102 | USER_DEFINED) => Ok(()),
            Some(code) => Err(FormatError::Unsupported(format!(
                "angular unit EPSG:{code} (GeogAngularUnits); relief reads degrees"
            ))),
        }
    }
}

/// Where the raster lies and which way its rows run.
pub(crate) struct Placement {
    /// Spacing and south-west corner, in metres (grid units without a georeference).
    pub(crate) geometry: GridGeometry,
    /// Whether the file's first row is its northernmost (then rows are flipped).
    pub(crate) north_up: bool,
    /// Whether the file had a georeference.
    pub(crate) georeferenced: bool,
    /// The degrees a geographic raster's spacing was converted from.
    pub(crate) from_degrees: Option<DegreeSpacing>,
    /// The grid in the model's own coordinates; `None` without a georeference.
    pub(crate) model: Option<ModelGrid>,
}

/// A north-up or south-up grid in its model's coordinates (projected units or degrees), before
/// its conversion to metres: what mosaics of several files are aligned on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ModelGrid {
    /// The grid's west edge (outer edge of its first column).
    pub(crate) west: f64,
    /// The grid's south edge (outer edge of its southernmost row).
    pub(crate) south: f64,
    /// Pixel width in model units.
    pub(crate) dx: f64,
    /// Pixel height in model units, positive.
    pub(crate) dy: f64,
    /// Metres per model unit for a projected model; `None` for a geographic one (degrees).
    pub(crate) metres_per_unit: Option<f64>,
}

impl ModelGrid {
    /// The geometry in metres of a `width x height` grid on this one, with its south-west
    /// corner at (`west`, `south`): projected coordinates scaled to metres, geographic ones
    /// converted at the latitude of the grid's centre (see
    /// [`read_geotiff`](crate::read_geotiff)).
    pub(crate) fn geometry(
        &self,
        (width, height): (usize, usize),
    ) -> Result<(GridGeometry, Option<DegreeSpacing>), FormatError> {
        let (west, south, dx, dy) = (self.west, self.south, self.dx, self.dy);
        let (geometry, from_degrees) = match self.metres_per_unit {
            Some(unit) => {
                let origin = DVec2::new(west * unit, south * unit);
                (GridGeometry { dx: dx * unit, dy: dy * unit, z_scale: 1.0, origin }, None)
            }
            None => {
                let north = south + height as f64 * dy;
                if south < -90.0 || north > 90.0 {
                    return Err(FormatError::Format(format!(
                        "latitudes {south}..{north} reach beyond the poles"
                    )));
                }
                let latitude = 0.5 * (south + north);
                let (per_lon, per_lat) = metres_per_degree(latitude);
                let origin = DVec2::new(west * per_lon, south * per_lat);
                let geometry =
                    GridGeometry { dx: dx * per_lon, dy: dy * per_lat, z_scale: 1.0, origin };
                (geometry, Some(DegreeSpacing { dlon: dx, dlat: dy, latitude }))
            }
        };
        geometry.validate().map_err(|e| {
            FormatError::Format(format!("georeference of the {width} x {height} raster: {e}"))
        })?;
        Ok((geometry, from_degrees))
    }
}

/// The model tags of a GeoTIFF, each with its values when present.
pub(crate) struct ModelTags {
    /// ModelPixelScaleTag (33550): pixel size (x, y, z).
    pub(crate) scale: Option<Vec<f64>>,
    /// ModelTiepointTag (33922): (i, j, k, x, y, z) raster-to-model tie points.
    pub(crate) ties: Option<Vec<f64>>,
    /// ModelTransformationTag (34264): a 4 x 4 row-major affine matrix.
    pub(crate) transform: Option<Vec<f64>>,
}

/// Places a `width x height` raster from its model tags and GeoKeys: spacing and south-west
/// corner in metres, geographic rasters converted at the latitude of their centre.
pub(crate) fn model_placement(
    tags: &ModelTags,
    keys: &GeoKeys,
    (width, height): (usize, usize),
) -> Result<Placement, FormatError> {
    let shift = match keys.raster_type()? {
        RasterType::PixelIsArea => 0.0,
        RasterType::PixelIsPoint => 0.5,
    };
    // Model coordinates of raster point (u, v), u and v counted in pixels from the outer
    // corner of the first pixel: x = x0 + u * ex, y = y0 + v * ey.
    let (x0, ex, y0, ey) = match (&tags.transform, &tags.scale, &tags.ties) {
        (Some(t), _, _) => {
            if t.len() != 16 {
                return Err(FormatError::Format(format!(
                    "ModelTransformationTag has {} values, not 16",
                    t.len()
                )));
            }
            if t[1] != 0.0 || t[4] != 0.0 {
                return Err(FormatError::Unsupported(format!(
                    "rotated or sheared georeference (ModelTransformation terms {} and {})",
                    t[1], t[4]
                )));
            }
            if t[12] != 0.0 || t[13] != 0.0 || t[14] != 0.0 || t[15] != 1.0 {
                return Err(FormatError::Unsupported("projective ModelTransformation".into()));
            }
            (t[3] - shift * t[0], t[0], t[7] - shift * t[5], t[5])
        }
        (None, Some(s), Some(tp)) => {
            if s.len() < 2 || tp.len() < 6 {
                return Err(FormatError::Format(format!(
                    "ModelPixelScaleTag has {} values (needs 3) and ModelTiepointTag {} \
                         (needs 6)",
                    s.len(),
                    tp.len()
                )));
            }
            let (i, j, x, y) = (tp[0], tp[1], tp[3], tp[4]);
            (x - (i + shift) * s[0], s[0], y + (j + shift) * s[1], -s[1])
        }
        (None, None, None) => {
            return Ok(Placement {
                geometry: GridGeometry::unit(),
                north_up: true,
                georeferenced: false,
                from_degrees: None,
                model: None,
            })
        }
        (None, Some(_), None) => {
            return Err(FormatError::Unsupported("ModelPixelScale without a ModelTiepoint".into()))
        }
        (None, None, Some(tp)) => {
            return Err(FormatError::Unsupported(format!(
                "georeference by {} tie points without ModelPixelScale",
                tp.len() / 6
            )))
        }
    };
    if ![x0, ex, y0, ey].iter().all(|v| v.is_finite()) {
        return Err(FormatError::Format("georeference has non-finite values".into()));
    }
    if ex < 0.0 {
        return Err(FormatError::Unsupported(format!(
            "east-west mirrored raster (pixel width {ex})"
        )));
    }
    if ex == 0.0 || ey == 0.0 {
        return Err(FormatError::Format(format!("georeference pixel size {ex} x {ey}")));
    }
    let north_up = ey < 0.0;
    let dy = ey.abs();
    let south = if north_up { y0 + height as f64 * ey } else { y0 };
    let metres_per_unit = match keys.model_type()? {
        ModelType::Projected => Some(keys.metres_per_linear_unit()?),
        ModelType::Geographic => {
            keys.check_degrees()?;
            None
        }
    };
    let model = ModelGrid { west: x0, south, dx: ex, dy, metres_per_unit };
    let (geometry, from_degrees) = model.geometry((width, height))?;
    Ok(Placement { geometry, north_up, georeferenced: true, from_degrees, model: Some(model) })
}

/// The GeoKey directory relief writes: a projected model, PixelIsArea, a user-defined projected
/// CRS whose linear unit is the metre.
#[rustfmt::skip]
pub(crate) const PROJECTED_METRES: [u16; 20] = [
    1, 1, 0, 4, // version 1, revision 1.0, 4 keys
    GT_MODEL_TYPE, 0, 1, 1, // projected
    GT_RASTER_TYPE, 0, 1, 1, // PixelIsArea
    PROJECTED_CS_TYPE, 0, 1, USER_DEFINED, // user-defined projected CRS
    PROJ_LINEAR_UNITS, 0, 1, 9001, // metre
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_written_directory_and_defaults() {
        let keys = GeoKeys::parse(&PROJECTED_METRES).unwrap();
        assert_eq!(keys.model_type().unwrap(), ModelType::Projected);
        assert_eq!(keys.raster_type().unwrap(), RasterType::PixelIsArea);
        assert_eq!(keys.metres_per_linear_unit().unwrap(), 1.0);
        let empty = GeoKeys::default();
        assert_eq!(empty.model_type().unwrap(), ModelType::Projected);
        assert_eq!(empty.raster_type().unwrap(), RasterType::PixelIsArea);
    }

    #[test]
    fn geographic_point_and_units() {
        // The Jacksboro fixture's directory: geographic, PixelIsArea, EPSG:4326.
        let jacksboro = [1, 1, 0, 3, 1024, 0, 1, 2, 1025, 0, 1, 1, 2048, 0, 1, 4326];
        let keys = GeoKeys::parse(&jacksboro).unwrap();
        assert_eq!(keys.model_type().unwrap(), ModelType::Geographic);
        assert!(keys.check_degrees().is_ok());
        let point_feet = [1, 1, 0, 2, 1025, 0, 1, 2, 3076, 0, 1, 9002];
        let keys = GeoKeys::parse(&point_feet).unwrap();
        assert_eq!(keys.raster_type().unwrap(), RasterType::PixelIsPoint);
        assert_eq!(keys.metres_per_linear_unit().unwrap(), 0.3048);
        // Without GTModelTypeGeoKey, a geographic CRS key alone means geographic.
        let keys = GeoKeys::parse(&[1, 1, 0, 1, 2048, 0, 1, 4326]).unwrap();
        assert_eq!(keys.model_type().unwrap(), ModelType::Geographic);
    }

    #[test]
    fn refuses_short_or_foreign_directories() {
        let format = |r: Result<GeoKeys, FormatError>| matches!(r, Err(FormatError::Format(_)));
        assert!(format(GeoKeys::parse(&[1, 1, 0])));
        assert!(format(GeoKeys::parse(&[1, 1, 0, 2, 1024, 0, 1, 1])));
        assert!(matches!(GeoKeys::parse(&[2, 1, 0, 0]), Err(FormatError::Unsupported(_))));
        let geocentric = GeoKeys::parse(&[1, 1, 0, 1, 1024, 0, 1, 3]).unwrap();
        assert!(matches!(geocentric.model_type(), Err(FormatError::Unsupported(_))));
        let radians = GeoKeys::parse(&[1, 1, 0, 1, 2054, 0, 1, 9101]).unwrap();
        assert!(matches!(radians.check_degrees(), Err(FormatError::Unsupported(_))));
        // Keys stored in the double or ASCII parameter tags are skipped, not misread.
        let elsewhere = GeoKeys::parse(&[1, 1, 0, 1, 1025, 34736, 1, 0]).unwrap();
        assert_eq!(elsewhere.raster_type().unwrap(), RasterType::PixelIsArea);
    }

    #[test]
    fn placement_from_tags() {
        let tags = |scale: Option<Vec<f64>>, ties: Option<Vec<f64>>, transform| ModelTags {
            scale,
            ties,
            transform,
        };
        let keys = GeoKeys::default();
        // A 4 x 2 raster of 10 x 20 m pixels whose north-west corner is (100, 900).
        let scaled =
            tags(Some(vec![10.0, 20.0, 0.0]), Some(vec![0.0, 0.0, 0.0, 100.0, 900.0, 0.0]), None);
        let p = model_placement(&scaled, &keys, (4, 2)).unwrap();
        assert!(p.north_up && p.georeferenced && p.from_degrees.is_none());
        assert_eq!(
            (p.geometry.dx, p.geometry.dy, p.geometry.origin),
            (10.0, 20.0, DVec2::new(100.0, 860.0))
        );
        // The same by a transformation; then south-up.
        let mut t = vec![10.0, 0.0, 0.0, 100.0, 0.0, -20.0, 0.0, 900.0];
        t.extend([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
        let p = model_placement(&tags(None, None, Some(t.clone())), &keys, (4, 2)).unwrap();
        assert_eq!(p.geometry.origin, DVec2::new(100.0, 860.0));
        t[5] = 20.0;
        let p = model_placement(&tags(None, None, Some(t.clone())), &keys, (4, 2)).unwrap();
        assert!(!p.north_up);
        assert_eq!(p.geometry.origin, DVec2::new(100.0, 900.0));
        // Shear, perspective, a short matrix, non-finite values, a mirrored raster.
        let unsupported =
            |r: Result<Placement, FormatError>| matches!(r, Err(FormatError::Unsupported(_)));
        let format = |r: Result<Placement, FormatError>| matches!(r, Err(FormatError::Format(_)));
        let mut sheared = t.clone();
        sheared[1] = 0.5;
        assert!(unsupported(model_placement(&tags(None, None, Some(sheared)), &keys, (4, 2))));
        let mut projective = t.clone();
        projective[12] = 1.0;
        assert!(unsupported(model_placement(&tags(None, None, Some(projective)), &keys, (4, 2))));
        assert!(format(model_placement(&tags(None, None, Some(t[..12].to_vec())), &keys, (4, 2))));
        let nan = tags(Some(vec![f64::NAN, 1.0, 0.0]), Some(vec![0.0; 6]), None);
        assert!(format(model_placement(&nan, &keys, (4, 2))));
        let mirrored = tags(Some(vec![-1.0, 1.0, 0.0]), Some(vec![0.0; 6]), None);
        assert!(unsupported(model_placement(&mirrored, &keys, (4, 2))));
        // No georeference: unit geometry, still north-up.
        let p = model_placement(&tags(None, None, None), &keys, (4, 2)).unwrap();
        assert!(p.north_up && !p.georeferenced && p.geometry == GridGeometry::unit());
    }
}
