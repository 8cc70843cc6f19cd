//! A raster of named float32 layers on one grid, such as the shade layers relief computes for
//! a DEM, with the georeference and nodata value to write them with.

use crate::{Georeference, IoError};
use std::path::Path;

/// One named layer of a [`LayerRaster`].
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// The layer's name, written as its band's description (e.g. `shadow`).
    pub name: String,
    /// `width * height` samples, row-major, row 0 south as everywhere in relief; NaN for a
    /// void.
    pub samples: Vec<f32>,
}

/// Named float32 layers on one `width x height` grid, with where the grid lies.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerRaster {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// The layers, in the order they are written (band 1 first).
    pub layers: Vec<Layer>,
    /// The placement and CRS to write, usually the input's
    /// ([`RasterInfo::georeference`](crate::RasterInfo::georeference)); `None` writes no
    /// georeference.
    pub georeference: Option<Georeference>,
    /// The value declared for voids (GDAL_NODATA); NaN samples are written as it.
    pub nodata: Option<f64>,
}

impl LayerRaster {
    /// Refuses an empty grid, no layers, a layer whose sample count is not `width * height`,
    /// and a nodata value that float32 samples cannot hold exactly; `path` names the file.
    pub(crate) fn check(&self, path: &Path) -> Result<(), IoError> {
        let (width, height) = (self.width, self.height);
        if width == 0 || height == 0 {
            return Err(IoError::invalid_data(
                path,
                format!("raster of {width} x {height} samples is empty"),
            ));
        }
        if self.layers.is_empty() {
            return Err(IoError::invalid_data(path, "no layers to write"));
        }
        if self.layers.len() > usize::from(u16::MAX) {
            return Err(IoError::unsupported(path, format!("{} layers", self.layers.len())));
        }
        let needed = width.checked_mul(height);
        for layer in &self.layers {
            if Some(layer.samples.len()) != needed {
                return Err(IoError::invalid_data(
                    path,
                    format!(
                        "layer {:?} holds {} samples; a {width} x {height} grid needs {}",
                        layer.name,
                        layer.samples.len(),
                        width as u128 * height as u128
                    ),
                ));
            }
        }
        check_nodata(path, self.nodata)
    }

    /// Whether the file's first row is the grid's southernmost: only when the georeference
    /// says the file is south-up; otherwise files are written north-up.
    pub(crate) fn south_up(&self) -> bool {
        self.georeference.as_ref().is_some_and(Georeference::is_south_up)
    }

    /// The value a void is written as: the nodata value, or NaN.
    pub(crate) fn void_value(&self) -> f32 {
        self.nodata.map_or(f32::NAN, |v| v as f32)
    }

    /// The GDAL_NODATA text to write: the nodata value (in the shortest form that reads back
    /// exactly), "nan" when there is none but some sample is a void, else nothing.
    pub(crate) fn nodata_text(&self) -> Option<String> {
        let voids = || self.layers.iter().any(|l| l.samples.iter().any(|v| v.is_nan()));
        nodata_text(self.nodata, voids)
    }
}

/// Refuses a nodata value that float32 samples cannot hold exactly (NaN is fine); `path`
/// names the file.
pub(crate) fn check_nodata(path: &Path, nodata: Option<f64>) -> Result<(), IoError> {
    match nodata {
        Some(v) if !v.is_nan() && f64::from(v as f32) != v => {
            Err(IoError::invalid_data(path, format!("nodata value {v} is not a float32 value")))
        }
        _ => Ok(()),
    }
}

/// The GDAL_NODATA text of float32 bands declaring `nodata`: the value (in the shortest form
/// that reads back exactly), "nan" when there is none but `voids()` says some sample is a
/// void, else nothing.
pub(crate) fn nodata_text(nodata: Option<f64>, voids: impl FnOnce() -> bool) -> Option<String> {
    match nodata {
        Some(v) if v.is_nan() => Some("nan".into()),
        Some(v) => Some(format!("{v}")),
        None if voids() => Some("nan".into()),
        None => None,
    }
}
