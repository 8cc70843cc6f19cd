//! A file's georeference as it was stored, kept through reading so that a writer can place an
//! output exactly where its input lay, in the same CRS: the GeoTIFF tags that say so, and the
//! GDAL geotransform they amount to.

use crate::georef::geokey_ids::{
    GEOGRAPHIC_TYPE, GT_MODEL_TYPE, GT_RASTER_TYPE, MODEL_GEOGRAPHIC, PIXEL_IS_AREA, PIXEL_IS_POINT,
};
use std::fmt::Write as _;

/// EPSG code of WGS 84 in longitude and latitude, the CRS of SRTM tiles.
pub const EPSG_WGS84: u16 = 4326;

/// Where a raster lies on the earth and in which coordinate reference system, as its file
/// said it.
///
/// [`geotiff`](Self::geotiff) holds the GeoTIFF tags that reproduce the placement and the
/// CRS: copied unchanged from a GeoTIFF (so any CRS, EPSG-coded or user-defined, is written
/// back byte for byte), made up for other formats. [`geotransform`](Self::geotransform) is the
/// placement those tags amount to, as GDAL reads it.
///
/// ```
/// use relief_io::Georeference;
/// // A 1" SRTM tile whose south-west sample is at 36° N, 85° W.
/// let tile = Georeference::srtm_tile(36, -85, 3601);
/// let step = 1.0 / 3600.0;
/// assert_eq!(tile.geotransform, [-85.0 - 0.5 * step, step, 0.0, 37.0 + 0.5 * step, 0.0, -step]);
/// assert_eq!(tile.world_file().lines().nth(4), Some("-85"));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Georeference {
    /// GDAL's geotransform of the file's grid as stored (row 0 its first row, the northernmost
    /// for the usual north-up file): the model coordinates of raster point (u, v), counted in
    /// pixels from the outer corner of the first pixel, are
    /// `x = gt[0] + u * gt[1] + v * gt[2]` and `y = gt[3] + u * gt[4] + v * gt[5]`. A
    /// PixelIsPoint file's tie point is shifted by half a pixel as GDAL does, so `gt[0], gt[3]`
    /// is always the outer corner.
    pub geotransform: [f64; 6],
    /// The GeoTIFF tags that place the raster and name its CRS.
    pub geotiff: GeoTiffTags,
}

/// The georeferencing tags of a GeoTIFF, each with its values as stored, or `None` when
/// absent.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GeoTiffTags {
    /// ModelPixelScaleTag (33550): pixel size (x, y, z).
    pub model_pixel_scale: Option<Vec<f64>>,
    /// ModelTiepointTag (33922): (i, j, k, x, y, z) raster-to-model tie points.
    pub model_tiepoint: Option<Vec<f64>>,
    /// ModelTransformationTag (34264): a 4 x 4 row-major affine matrix.
    pub model_transformation: Option<Vec<f64>>,
    /// GeoKeyDirectoryTag (34735): the GeoKeys.
    pub geo_key_directory: Option<Vec<u16>>,
    /// GeoDoubleParamsTag (34736): the GeoKeys' double values.
    pub geo_double_params: Option<Vec<f64>>,
    /// GeoAsciiParamsTag (34737): the GeoKeys' text, its bytes as stored (terminating NUL
    /// included).
    pub geo_ascii_params: Option<Vec<u8>>,
}

impl Georeference {
    /// The georeference of `tags`, with its geotransform derived from them as GDAL does;
    /// `None` when the tags place nothing (neither a ModelTransformation of 16 values nor a
    /// ModelPixelScale of at least 2 values with a ModelTiepoint of at least 6).
    pub fn from_geotiff_tags(tags: GeoTiffTags) -> Option<Georeference> {
        let geotransform = geotransform_of(&tags)?;
        Some(Georeference { geotransform, geotiff: tags })
    }

    /// The placement of an SRTM tile of `side x side` samples whose south-west sample is at
    /// `latitude`, `longitude` (whole degrees), as GDAL reads a `.hgt`: WGS 84 (EPSG:4326),
    /// PixelIsPoint, samples `1 / (side - 1)` degrees apart, the north-west sample at
    /// (`longitude`, `latitude + 1`).
    pub fn srtm_tile(latitude: i32, longitude: i32, side: usize) -> Georeference {
        let step = 1.0 / (side.max(2) - 1) as f64;
        #[rustfmt::skip]
        let keys = vec![
            1, 1, 0, 3, // version 1, revision 1.0, 3 keys
            GT_MODEL_TYPE, 0, 1, MODEL_GEOGRAPHIC,
            GT_RASTER_TYPE, 0, 1, PIXEL_IS_POINT,
            GEOGRAPHIC_TYPE, 0, 1, EPSG_WGS84,
        ];
        let tags = GeoTiffTags {
            model_pixel_scale: Some(vec![step, step, 0.0]),
            model_tiepoint: Some(vec![
                0.0,
                0.0,
                0.0,
                f64::from(longitude),
                f64::from(latitude) + 1.0,
                0.0,
            ]),
            geo_key_directory: Some(keys),
            ..GeoTiffTags::default()
        };
        let geotransform = geotransform_of(&tags).unwrap_or([0.0; 6]);
        Georeference { geotransform, geotiff: tags }
    }

    /// A north-up grid of `dx x dy` pixels whose north-west outer corner is (`west`, `north`),
    /// in no stated CRS (an ESRI ASCII grid without a `.prj`): PixelIsArea, no CRS keys.
    pub fn north_up_grid(west: f64, north: f64, dx: f64, dy: f64) -> Georeference {
        #[rustfmt::skip]
        let keys = vec![
            1, 1, 0, 1, // version 1, revision 1.0, 1 key
            GT_RASTER_TYPE, 0, 1, PIXEL_IS_AREA,
        ];
        let tags = GeoTiffTags {
            model_pixel_scale: Some(vec![dx, dy, 0.0]),
            model_tiepoint: Some(vec![0.0, 0.0, 0.0, west, north, 0.0]),
            geo_key_directory: Some(keys),
            ..GeoTiffTags::default()
        };
        Georeference { geotransform: [west, dx, 0.0, north, 0.0, -dy], geotiff: tags }
    }

    /// Whether the file's first row is its southernmost (the geotransform's y grows with the
    /// row); the usual north-up file says no.
    pub fn is_south_up(&self) -> bool {
        self.geotransform[5] > 0.0
    }

    /// The six lines of an ESRI world file (`.pgw`, `.tfw`, ...) for this placement: x and y
    /// size and rotation terms, then the centre of the first pixel, as GDAL writes them, each
    /// number in the shortest form that reads back exactly.
    pub fn world_file(&self) -> String {
        let [x0, a, b, y0, d, e] = self.geotransform;
        let centre_x = x0 + 0.5 * a + 0.5 * b;
        let centre_y = y0 + 0.5 * d + 0.5 * e;
        let mut text = String::new();
        for value in [a, d, b, e, centre_x, centre_y] {
            // Writing to a String cannot fail.
            let _ = writeln!(text, "{value}");
        }
        text
    }

    /// Whether the GeoKeys say PixelIsPoint (GTRasterTypeGeoKey 2): the sample values hold at
    /// the pixels' centres.
    pub fn is_pixel_is_point(&self) -> bool {
        self.geotiff.geo_key_directory.as_deref().is_some_and(|d| raster_type(d) == PIXEL_IS_POINT)
    }

    /// The GeoKeys that define the CRS, each with its value as text (short values, doubles
    /// from GeoDoubleParams, text from GeoAsciiParams), sorted by key; the raster type and the
    /// citations (free text) are left out. Two files with equal keys are in the same CRS.
    ///
    /// ```
    /// use relief_io::{Georeference, EPSG_WGS84};
    /// let tile = Georeference::srtm_tile(36, -85, 1201);
    /// // GTModelTypeGeoKey 2 (geographic), GeographicTypeGeoKey 4326.
    /// assert_eq!(tile.crs_keys(), vec![(1024, "2".into()), (2048, EPSG_WGS84.to_string())]);
    /// ```
    pub fn crs_keys(&self) -> Vec<(u16, String)> {
        let tags = &self.geotiff;
        let Some(directory) = tags.geo_key_directory.as_deref() else {
            return Vec::new();
        };
        let count = directory.get(3).map_or(0, |&c| usize::from(c));
        let mut keys: Vec<(u16, String)> = directory
            .get(4..)
            .unwrap_or(&[])
            .chunks_exact(4)
            .take(count)
            .filter(|key| key[0] != GT_RASTER_TYPE && !CITATION_KEYS.contains(&key[0]))
            .map(|key| {
                let (id, location, n, value) = (key[0], key[1], usize::from(key[2]), key[3]);
                let at = usize::from(value);
                let text = match location {
                    0 => value.to_string(),
                    34736 => {
                        let doubles = tags.geo_double_params.as_deref().unwrap_or(&[]);
                        format!("{:?}", doubles.get(at..at + n))
                    }
                    34737 => {
                        let ascii = tags.geo_ascii_params.as_deref().unwrap_or(&[]);
                        let text = ascii.get(at..at + n).map(String::from_utf8_lossy);
                        format!("{text:?}")
                    }
                    _ => format!("{:?}", directory.get(at..at + n)),
                };
                (id, text)
            })
            .collect();
        keys.sort();
        keys
    }
}

/// GeoKeys that name a citation (free text, not the CRS itself): GTCitation, GeogCitation,
/// PCSCitation.
const CITATION_KEYS: [u16; 3] = [1026, 2049, 3073];

/// GTRasterTypeGeoKey of a GeoKey directory: PixelIsArea when absent or unreadable.
fn raster_type(directory: &[u16]) -> u16 {
    let count = directory.get(3).map_or(0, |&c| usize::from(c));
    directory
        .get(4..)
        .unwrap_or(&[])
        .chunks_exact(4)
        .take(count)
        .find(|key| key[0] == GT_RASTER_TYPE && key[1] == 0)
        .map_or(PIXEL_IS_AREA, |key| key[3])
}

/// GDAL's geotransform of GeoTIFF tags: from a ModelTransformation, else from ModelPixelScale
/// and the first ModelTiepoint; PixelIsPoint shifts the corner by half a pixel.
fn geotransform_of(tags: &GeoTiffTags) -> Option<[f64; 6]> {
    let mut gt = match (&tags.model_transformation, &tags.model_pixel_scale, &tags.model_tiepoint) {
        (Some(m), _, _) if m.len() == 16 => [m[3], m[0], m[1], m[7], m[4], m[5]],
        (_, Some(s), Some(t)) if s.len() >= 2 && t.len() >= 6 => {
            let (dx, dy) = (s[0], -s[1]);
            [t[3] - t[0] * dx, dx, 0.0, t[4] - t[1] * dy, 0.0, dy]
        }
        _ => return None,
    };
    if tags.geo_key_directory.as_deref().is_some_and(|d| raster_type(d) == PIXEL_IS_POINT) {
        gt[0] -= gt[1] * 0.5 + gt[2] * 0.5;
        gt[3] -= gt[4] * 0.5 + gt[5] * 0.5;
    }
    Some(gt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geotransform_from_scale_and_tiepoint_or_a_matrix() {
        let tags = GeoTiffTags {
            model_pixel_scale: Some(vec![10.0, 20.0, 0.0]),
            model_tiepoint: Some(vec![2.0, 1.0, 0.0, 100.0, 900.0, 0.0]),
            ..GeoTiffTags::default()
        };
        let g = Georeference::from_geotiff_tags(tags.clone()).unwrap();
        assert_eq!(g.geotransform, [80.0, 10.0, 0.0, 920.0, 0.0, -20.0]);
        assert!(!g.is_south_up() && !g.is_pixel_is_point());
        // PixelIsPoint: the tie point is a pixel's centre.
        let point = GeoTiffTags {
            geo_key_directory: Some(vec![1, 1, 0, 1, GT_RASTER_TYPE, 0, 1, PIXEL_IS_POINT]),
            ..tags
        };
        let g = Georeference::from_geotiff_tags(point).unwrap();
        assert_eq!(g.geotransform, [75.0, 10.0, 0.0, 930.0, 0.0, -20.0]);
        assert!(g.is_pixel_is_point());
        #[rustfmt::skip]
        let matrix = vec![
            10.0, 0.0, 0.0, 100.0,
            0.0, 20.0, 0.0, 900.0,
            0.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 1.0,
        ];
        let tags = GeoTiffTags { model_transformation: Some(matrix), ..GeoTiffTags::default() };
        let g = Georeference::from_geotiff_tags(tags).unwrap();
        assert_eq!(g.geotransform, [100.0, 10.0, 0.0, 900.0, 0.0, 20.0]);
        assert!(g.is_south_up());
        assert_eq!(Georeference::from_geotiff_tags(GeoTiffTags::default()), None);
    }

    #[test]
    fn world_file_names_the_first_pixel_centre() {
        let g = Georeference::north_up_grid(1000.0, 2000.0, 30.0, 10.0);
        assert_eq!(g.world_file(), "30\n0\n0\n-10\n1015\n1995\n");
        let tile = Georeference::srtm_tile(-12, 45, 1201);
        let lines: Vec<f64> = tile.world_file().lines().map(|l| l.parse().unwrap()).collect();
        assert_eq!(lines, [1.0 / 1200.0, 0.0, 0.0, -1.0 / 1200.0, 45.0, -11.0]);
        assert!(tile.is_pixel_is_point());
    }
}
