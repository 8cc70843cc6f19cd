//! Writing a height field in the format its file name's extension names.

use crate::IoError;
use relief_core::HeightField;
use std::path::Path;

/// Writes `field` to `path` as `.tif`/`.tiff` (float32 GeoTIFF), `.hgt`, `.asc`, `.png`
/// (16-bit grey) or `.npy` (float32), by extension. GeoTIFF, .hgt and .asc store heights in
/// world units (sample value times z scale); PNG and .npy store the samples themselves. Holes
/// become the format's nodata.
pub fn write_height_field(path: &Path, field: &HeightField) -> Result<(), IoError> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("tif" | "tiff") => crate::geotiff_write::write_geotiff(path, field),
        Some("hgt") => crate::hgt::write_hgt(path, field),
        Some("asc") => crate::asc::write_asc(path, field),
        Some("png") => crate::png_height::write_png16_height(path, field),
        Some("npy") => {
            if field.holes().is_some() {
                return Err(IoError::unsupported(
                    path,
                    "voids in .npy, which has no nodata value: fill them (--voids fill) or write .tif, .asc or .hgt",
                ));
            }
            crate::write_height_field_npy(path, field)
        }
        _ => Err(IoError::unsupported(
            path,
            "output type: expected .tif, .tiff, .hgt, .asc, .png or .npy",
        )),
    }
}
