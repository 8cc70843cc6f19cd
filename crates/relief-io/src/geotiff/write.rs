//! Writing a height field as a GeoTIFF: float32 samples, north-up, Deflate with the
//! floating-point predictor, placed by ModelPixelScale and ModelTiepoint, holes as NaN nodata.

use crate::atomic_write::write_atomically;
use crate::geotiff::float_strips::{FloatStrips, BIG_TIFF_FROM};
use crate::geotiff::write_tags::{encoding_error, write_geometry_tags, write_georeference};
use crate::{Georeference, IoError};
use relief_core::HeightField;
use std::io::{Seek, Write};
use std::path::Path;
use tiff::encoder::{TiffEncoder, TiffKind, TiffKindBig, TiffKindStandard};
use tiff::tags::Tag;

/// Writes `field` to `path` as a GeoTIFF that GDAL, QGIS and [`read_geotiff`] read back.
///
/// The file holds one band of float32 samples, `value * z_scale` (metres when the field's
/// geometry is in metres), north-up: its first row is the field's last (northernmost) row.
/// Strips are Deflate-compressed with the floating-point predictor. The placement is a
/// ModelPixelScale of `(dx, dy)` and a ModelTiepoint putting the north-west corner at
/// `(origin.x, origin.y + height * dy)`, with a GeoKey directory saying projected, PixelIsArea,
/// user-defined CRS in metres. Holes are written as NaN, declared by GDAL_NODATA "nan", so they
/// read back as voids. Large rasters are written as BigTIFF.
///
/// The file is written beside `path` and renamed into place, so a failure leaves no partial
/// file. Errors: [`IoError::Io`] when writing fails, [`IoError::Unsupported`] for a side
/// longer than 2^32 - 1 samples, [`IoError::InvalidData`] when `value * z_scale` overflows f32.
///
/// [`read_geotiff`]: crate::geotiff::read_geotiff
pub fn write_geotiff(path: &Path, field: &HeightField) -> Result<(), IoError> {
    write_geotiff_placed(path, field, None)
}

/// Writes `field` to `path` as [`write_geotiff`] does, but placed by `georeference` when
/// given: its tags written back unchanged (the input's CRS, EPSG-coded or user-defined, and
/// its placement, which must be that of a grid of the field's size), its rows in the input's
/// order (north-up, or south-up as the input was). The heights are `value * z_scale`, in the
/// unit the caller declares in the tags (a VerticalUnitsGeoKey, or the CRS's linear unit).
pub fn write_geotiff_placed(
    path: &Path,
    field: &HeightField,
    georeference: Option<&Georeference>,
) -> Result<(), IoError> {
    let samples_bytes = field.width() as u64 * field.height() as u64 * 4;
    let big = samples_bytes >= BIG_TIFF_FROM;
    write_atomically(path, |out| write_geotiff_to(out, path, field, big, georeference))
}

/// Writes `field` as a GeoTIFF (a BigTIFF when `big`) to `out`; `path` names it in errors.
fn write_geotiff_to<W: Write + Seek>(
    out: W,
    path: &Path,
    field: &HeightField,
    big: bool,
    georeference: Option<&Georeference>,
) -> Result<(), IoError> {
    let error = |e| encoding_error(path, e);
    if big {
        let tiff = TiffEncoder::<W, TiffKindBig>::new_big(out).map_err(error)?;
        encode(tiff, path, field, georeference)
    } else {
        let tiff = TiffEncoder::<W, TiffKindStandard>::new(out).map_err(error)?;
        encode(tiff, path, field, georeference)
    }
}

/// Writes the one image of the file: its strips, then its directory.
fn encode<W: Write + Seek, K: TiffKind>(
    mut tiff: TiffEncoder<W, K>,
    path: &Path,
    field: &HeightField,
    georeference: Option<&Georeference>,
) -> Result<(), IoError> {
    let error = |e| encoding_error(path, e);
    let (width, height) = (field.width(), field.height());
    let south_up = georeference.is_some_and(Georeference::is_south_up);
    let geometry = field.geometry();
    let mut strips = FloatStrips::new(path, width, height)?;
    let mut directory = tiff.image_directory().map_err(error)?;
    let mut values = vec![0f32; width];
    for file_row in 0..height {
        let row = if south_up { file_row } else { height - 1 - file_row };
        for (col, value) in values.iter_mut().enumerate() {
            *value = if field.is_hole(col, row) {
                f32::NAN
            } else {
                (f64::from(field.sample(col, row)) * geometry.z_scale) as f32
            };
            if value.is_infinite() {
                return Err(IoError::invalid_data(
                    path,
                    format!(
                        "sample at column {col}, row {row} times z scale {} overflows f32",
                        geometry.z_scale
                    ),
                ));
            }
        }
        strips.push_row(&mut directory, &values)?;
    }
    strips.write_layout_tags(&mut directory, 1)?;
    match georeference {
        Some(georeference) => {
            write_georeference(&mut directory, path, &georeference.geotiff)?;
            directory.write_tag(Tag::GdalNodata, "nan").map_err(error)?;
        }
        None => write_geometry_tags(&mut directory, path, geometry, height)?,
    }
    directory.finish().map_err(error)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geotiff::read::read_geotiff_from;
    use crate::ReadOptions;
    use relief_core::{DVec2, GridGeometry};
    use std::io::Cursor;

    fn field() -> HeightField {
        let (w, h) = (37, 23);
        let samples = (0..w * h).map(|i| ((i * 7919) % 1000) as f32 * 0.25 - 100.0).collect();
        let geometry =
            GridGeometry { dx: 30.0, dy: 20.0, z_scale: 2.0, origin: DVec2::new(-500.0, 7.5) };
        let holes = (0..w * h).map(|i| i % 17 == 3).collect();
        HeightField::new(w, h, samples, geometry).unwrap().with_holes(holes).unwrap()
    }

    #[test]
    fn standard_and_big_tiff_read_back_with_z_scale_applied() {
        let field = field();
        let path = Path::new("memory.tif");
        for big in [false, true] {
            let mut bytes = Cursor::new(Vec::new());
            write_geotiff_to(&mut bytes, path, &field, big, None).unwrap();
            let bytes = bytes.into_inner();
            assert_eq!(&bytes[..4], if big { b"II+\0" } else { b"II*\0" });
            let raster = read_geotiff_from(Cursor::new(bytes), &ReadOptions::default()).unwrap();
            assert_eq!((raster.width, raster.height), (37, 23));
            let g = raster.geometry;
            assert_eq!((g.dx, g.dy, g.z_scale), (30.0, 20.0, 1.0));
            assert!((g.origin - DVec2::new(-500.0, 7.5)).length() < 1e-9, "{}", g.origin);
            assert_eq!(raster.info.sample_type, "float32");
            assert!(raster.info.nodata.is_some_and(f64::is_nan));
            for row in 0..23 {
                for col in 0..37 {
                    let got = raster.samples[col + row * 37];
                    if field.is_hole(col, row) {
                        assert!(got.is_nan(), "({col}, {row}) {got}");
                    } else {
                        assert_eq!(got, field.sample(col, row) * 2.0, "({col}, {row})");
                    }
                }
            }
        }
    }

    #[test]
    fn overflowing_z_scale_is_invalid_data() {
        let geometry = GridGeometry { z_scale: 1e300, ..GridGeometry::unit() };
        let field = HeightField::new(2, 1, vec![0.0, 1.0], geometry).unwrap();
        let err =
            write_geotiff_to(Cursor::new(Vec::new()), Path::new("x.tif"), &field, false, None)
                .unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        assert!(err.to_string().contains("column 1, row 0"), "{err}");
    }
}
