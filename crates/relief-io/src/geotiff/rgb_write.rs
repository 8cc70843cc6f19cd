//! Writing an 8-bit RGB image as a GeoTIFF placed by a [`Georeference`]: ortho photos for
//! tests and benchmarks of textured tile stores.

use crate::atomic_write::write_atomically;
use crate::geotiff::write_tags::encoding_error;
use crate::{Georeference, IoError};
use tiff::encoder::{colortype, Compression, DeflateLevel, TiffEncoder};
use tiff::tags::Tag;

/// Writes `rgb` (`width * height` interleaved 8-bit RGB pixels, row 0 the image's top row) to
/// `path` as a Deflate-compressed RGB GeoTIFF carrying `georeference`'s tags as they are
/// (model tags, GeoKey directory and its parameters), which [`open_ortho`] reads back.
///
/// The file is written beside `path` and renamed into place. Errors: [`IoError::InvalidData`]
/// when `rgb` is not `width * height * 3` bytes, [`IoError::Io`] when writing fails.
///
/// [`open_ortho`]: crate::open_ortho
pub fn write_rgb_geotiff(
    path: &std::path::Path,
    width: u32,
    height: u32,
    rgb: &[u8],
    georeference: &Georeference,
) -> Result<(), IoError> {
    if width as u64 * height as u64 * 3 != rgb.len() as u64 || width == 0 || height == 0 {
        return Err(IoError::invalid_data(
            path,
            format!("{width} x {height} RGB needs 3 bytes per pixel, got {} bytes", rgb.len()),
        ));
    }
    let tags = &georeference.geotiff;
    write_atomically(path, |out| {
        let error = |e| encoding_error(path, e);
        let mut tiff = TiffEncoder::new(out)
            .map_err(error)?
            .with_compression(Compression::Deflate(DeflateLevel::default()));
        let mut image = tiff.new_image::<colortype::RGB8>(width, height).map_err(error)?;
        let d = image.encoder();
        if let Some(v) = &tags.model_pixel_scale {
            d.write_tag(Tag::ModelPixelScaleTag, &v[..]).map_err(error)?;
        }
        if let Some(v) = &tags.model_tiepoint {
            d.write_tag(Tag::ModelTiepointTag, &v[..]).map_err(error)?;
        }
        if let Some(v) = &tags.model_transformation {
            d.write_tag(Tag::ModelTransformationTag, &v[..]).map_err(error)?;
        }
        if let Some(v) = &tags.geo_key_directory {
            d.write_tag(Tag::GeoKeyDirectoryTag, &v[..]).map_err(error)?;
        }
        if let Some(v) = &tags.geo_double_params {
            d.write_tag(Tag::GeoDoubleParamsTag, &v[..]).map_err(error)?;
        }
        if let Some(v) = &tags.geo_ascii_params {
            let text = String::from_utf8_lossy(v.strip_suffix(&[0]).unwrap_or(v)).into_owned();
            d.write_tag(Tag::GeoAsciiParamsTag, text.as_str()).map_err(error)?;
        }
        image.write_data(rgb).map_err(error)
    })
}
