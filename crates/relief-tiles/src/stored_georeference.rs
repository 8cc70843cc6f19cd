//! Where a store's raster lies on the earth: the GeoTIFF tags of its source as the index keeps
//! them, so that layers computed from the store are written in the source's CRS.

use relief_io::{GeoTiffTags, Georeference};
use serde::{Deserialize, Serialize};

/// A [`Georeference`] as `index.json` holds it (the tags' values as stored in the source).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredGeoreference {
    /// GDAL's geotransform of the source's grid as stored (see [`Georeference::geotransform`]).
    pub geotransform: [f64; 6],
    /// ModelPixelScaleTag.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_pixel_scale: Option<Vec<f64>>,
    /// ModelTiepointTag.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_tiepoint: Option<Vec<f64>>,
    /// ModelTransformationTag.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_transformation: Option<Vec<f64>>,
    /// GeoKeyDirectoryTag.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geo_key_directory: Option<Vec<u16>>,
    /// GeoDoubleParamsTag.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geo_double_params: Option<Vec<f64>>,
    /// GeoAsciiParamsTag, its bytes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geo_ascii_params: Option<Vec<u8>>,
}

impl From<&Georeference> for StoredGeoreference {
    fn from(g: &Georeference) -> Self {
        let t = &g.geotiff;
        StoredGeoreference {
            geotransform: g.geotransform,
            model_pixel_scale: t.model_pixel_scale.clone(),
            model_tiepoint: t.model_tiepoint.clone(),
            model_transformation: t.model_transformation.clone(),
            geo_key_directory: t.geo_key_directory.clone(),
            geo_double_params: t.geo_double_params.clone(),
            geo_ascii_params: t.geo_ascii_params.clone(),
        }
    }
}

impl From<&StoredGeoreference> for Georeference {
    fn from(s: &StoredGeoreference) -> Self {
        Georeference {
            geotransform: s.geotransform,
            geotiff: GeoTiffTags {
                model_pixel_scale: s.model_pixel_scale.clone(),
                model_tiepoint: s.model_tiepoint.clone(),
                model_transformation: s.model_transformation.clone(),
                geo_key_directory: s.geo_key_directory.clone(),
                geo_double_params: s.geo_double_params.clone(),
                geo_ascii_params: s.geo_ascii_params.clone(),
            },
        }
    }
}
