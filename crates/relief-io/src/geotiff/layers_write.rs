//! Writing a [`LayerRaster`] as a GeoTIFF: one float32 band per layer, each described by its
//! layer's name, placed and nodata-declared as the input it was computed from.

use crate::atomic_write::write_atomically;
use crate::geotiff::float_strips::{FloatStrips, BIG_TIFF_FROM};
use crate::geotiff::gdal_metadata::{band_descriptions_xml, GDAL_METADATA_TAG};
use crate::geotiff::write_tags::{encoding_error, write_ascii, write_georeference};
use crate::{IoError, LayerRaster};
use std::io::{Seek, Write};
use std::path::Path;
use tiff::encoder::{TiffEncoder, TiffKind, TiffKindBig, TiffKindStandard};
use tiff::tags::Tag;

/// Writes `layers` to `path` as a GeoTIFF that GDAL, QGIS and rasterio read as the input the
/// layers were computed from, one band per layer.
///
/// - Bands: one float32 band per layer, in the order of `layers.layers`, each in its own
///   Deflate-compressed strips with the floating-point predictor (PlanarConfiguration 2 when
///   there are several). Each band's description (GDAL's, rasterio's `descriptions`) is its
///   layer's name, through the GDAL_METADATA tag.
/// - Rows: north-up, the grid's last (northernmost) row first, unless the georeference says
///   its file was south-up; then row 0 comes first, as in that file.
/// - Georeference: the tags of `layers.georeference` written back unchanged (ModelPixelScale,
///   ModelTiepoint, ModelTransformation, the GeoKey directory and its double and ASCII
///   parameters), so the output lies sample for sample on the input in the same CRS. Without
///   one, no georeferencing tag is written (GDAL then sees pixel coordinates, no CRS).
/// - Voids: NaN samples are written as the nodata value, which GDAL_NODATA declares; without
///   one, voids stay NaN and GDAL_NODATA says "nan" (no GDAL_NODATA when there is no void). A
///   valid sample equal to the nodata value reads back as a void.
/// - Large rasters are written as BigTIFF.
///
/// The file is written beside `path` and renamed into place, so a failure leaves no partial
/// file. Errors: [`IoError::InvalidData`] for an empty grid, no layers, a layer of the wrong
/// length or a nodata value float32 cannot hold; [`IoError::Unsupported`] for a side longer
/// than 2^32 - 1 samples or more than 65535 layers; [`IoError::Io`] when writing fails.
pub fn write_layers_geotiff(path: &Path, layers: &LayerRaster) -> Result<(), IoError> {
    layers.check(path)?;
    let bytes = layers.width as u64 * layers.height as u64 * 4 * layers.layers.len() as u64;
    let big = bytes >= BIG_TIFF_FROM;
    write_atomically(path, |out| write_layers_to(out, path, layers, big))
}

/// Writes `layers` as a GeoTIFF (a BigTIFF when `big`) to `out`; `path` names it in errors.
pub(crate) fn write_layers_to<W: Write + Seek>(
    out: W,
    path: &Path,
    layers: &LayerRaster,
    big: bool,
) -> Result<(), IoError> {
    let error = |e| encoding_error(path, e);
    if big {
        encode(TiffEncoder::<W, TiffKindBig>::new_big(out).map_err(error)?, path, layers)
    } else {
        encode(TiffEncoder::<W, TiffKindStandard>::new(out).map_err(error)?, path, layers)
    }
}

/// Writes the one image of the file: every band's strips, then its directory.
fn encode<W: Write + Seek, K: TiffKind>(
    mut tiff: TiffEncoder<W, K>,
    path: &Path,
    layers: &LayerRaster,
) -> Result<(), IoError> {
    let error = |e| encoding_error(path, e);
    let (width, height) = (layers.width, layers.height);
    let mut strips = FloatStrips::new(path, width, height)?;
    let mut directory = tiff.image_directory().map_err(error)?;
    let (south_up, void) = (layers.south_up(), layers.void_value());
    for layer in &layers.layers {
        strips.push_band(&mut directory, |file_row, values| {
            let row = if south_up { file_row } else { height - 1 - file_row };
            for (value, &sample) in values.iter_mut().zip(&layer.samples[row * width..]) {
                *value = if sample.is_nan() { void } else { sample };
            }
        })?;
    }
    let d = &mut directory;
    // check() bounds the layer count by u16::MAX.
    strips.write_layout_tags(d, layers.layers.len() as u16)?;
    if let Some(georeference) = &layers.georeference {
        write_georeference(d, path, &georeference.geotiff)?;
    }
    let names: Vec<&str> = layers.layers.iter().map(|l| l.name.as_str()).collect();
    write_ascii(
        d,
        path,
        Tag::Unknown(GDAL_METADATA_TAG),
        band_descriptions_xml(&names).as_bytes(),
    )?;
    if let Some(text) = layers.nodata_text() {
        d.write_tag(Tag::GdalNodata, text.as_str()).map_err(error)?;
    }
    directory.finish().map_err(error)
}
