//! The tags relief's GeoTIFF writers share: a georeference written back as it was stored, or
//! the placement of a grid in metres; and the encoder's errors as [`IoError`]s.

use crate::georef::geokeys::PROJECTED_METRES;
use crate::{GeoTiffTags, IoError};
use relief_core::GridGeometry;
use std::io::{Seek, Write};
use std::path::Path;
use tiff::encoder::{DirectoryEncoder, TiffKind};
use tiff::tags::{Tag, Type};
use tiff::{Directory, TiffError};

/// An error of the `tiff` encoder as an [`IoError`].
pub(crate) fn encoding_error(path: &Path, error: TiffError) -> IoError {
    match error {
        TiffError::IoError(e) => IoError::io(path, e),
        other => IoError::invalid_data(path, format!("encoding the GeoTIFF: {other}")),
    }
}

/// Writes the tags that place a north-up `height`-row grid of `geometry` (ModelPixelScale,
/// ModelTiepoint at its north-west corner, a projected GeoKey directory in metres) and
/// declare NaN as nodata, after the layout tags, as [`write_geotiff`] does.
pub(crate) fn write_geometry_tags<W: Write + Seek, K: TiffKind>(
    d: &mut DirectoryEncoder<'_, W, K>,
    path: &Path,
    geometry: &GridGeometry,
    height: usize,
) -> Result<(), IoError> {
    let error = |e| encoding_error(path, e);
    let north = geometry.origin.y + height as f64 * geometry.dy;
    d.write_tag(Tag::ModelPixelScaleTag, &[geometry.dx, geometry.dy, 0.0][..]).map_err(error)?;
    let tiepoint = [0.0, 0.0, 0.0, geometry.origin.x, north, 0.0];
    d.write_tag(Tag::ModelTiepointTag, &tiepoint[..]).map_err(error)?;
    d.write_tag(Tag::GeoKeyDirectoryTag, &PROJECTED_METRES[..]).map_err(error)?;
    d.write_tag(Tag::GdalNodata, "nan").map_err(error)
}

/// The values of one georeferencing tag, as stored.
pub(crate) enum GeoTagValues<'a> {
    /// DOUBLE values (pixel scale, tie points, transformation, GeoKey doubles).
    Doubles(&'a [f64]),
    /// SHORT values (the GeoKey directory).
    Shorts(&'a [u16]),
    /// ASCII bytes (the GeoKeys' text).
    Ascii(&'a [u8]),
}

/// The georeferencing tags present in `tags`, each with its values, in the order relief's
/// writers write them.
pub(crate) fn georeference_tags(tags: &GeoTiffTags) -> Vec<(Tag, GeoTagValues<'_>)> {
    let doubles = [
        (Tag::ModelPixelScaleTag, &tags.model_pixel_scale),
        (Tag::ModelTiepointTag, &tags.model_tiepoint),
        (Tag::ModelTransformationTag, &tags.model_transformation),
        (Tag::GeoDoubleParamsTag, &tags.geo_double_params),
    ];
    let mut out: Vec<(Tag, GeoTagValues<'_>)> = doubles
        .into_iter()
        .filter_map(|(tag, values)| Some((tag, GeoTagValues::Doubles(values.as_deref()?))))
        .collect();
    if let Some(keys) = &tags.geo_key_directory {
        out.push((Tag::GeoKeyDirectoryTag, GeoTagValues::Shorts(keys)));
    }
    if let Some(text) = &tags.geo_ascii_params {
        out.push((Tag::GeoAsciiParamsTag, GeoTagValues::Ascii(text)));
    }
    out
}

/// Writes the georeferencing tags present in `tags`, unchanged.
pub(crate) fn write_georeference<W: Write + Seek, K: TiffKind>(
    d: &mut DirectoryEncoder<'_, W, K>,
    path: &Path,
    tags: &GeoTiffTags,
) -> Result<(), IoError> {
    let error = |e| encoding_error(path, e);
    for (tag, values) in georeference_tags(tags) {
        match values {
            GeoTagValues::Doubles(values) => d.write_tag(tag, values).map_err(error)?,
            GeoTagValues::Shorts(values) => d.write_tag(tag, values).map_err(error)?,
            GeoTagValues::Ascii(text) => write_ascii(d, path, tag, text)?,
        }
    }
    Ok(())
}

/// Writes an ASCII tag from its bytes (UTF-8 allowed, as GDAL writes it), adding the
/// terminating NUL when they lack one.
pub(crate) fn write_ascii<W: Write + Seek, K: TiffKind>(
    d: &mut DirectoryEncoder<'_, W, K>,
    path: &Path,
    tag: Tag,
    bytes: &[u8],
) -> Result<(), IoError> {
    let mut data = bytes.to_vec();
    if data.last() != Some(&0) {
        data.push(0);
    }
    let entry = d.write_entry_bytes(Type::ASCII, &data).map_err(|e| encoding_error(path, e))?;
    let mut entries = Directory::empty();
    entries.extend([(tag, entry)]);
    d.extend_from(&entries);
    Ok(())
}
