//! The tags of a GeoTIFF image, read through the `tiff` crate: how its samples are laid out
//! (bands, sample type, compression), its GDAL_NODATA, its georeferencing tags as stored, and
//! the `tiff` crate's errors by cause.

use crate::format_error::FormatError;
use crate::georef::geokeys::{model_placement, GeoKeys, ModelTags, Placement};
use crate::sample_type::SampleType;
use crate::GeoTiffTags;
use std::fmt::Display;
use std::io::{ErrorKind, Read, Seek};
use tiff::decoder::Decoder;
use tiff::tags::{CompressionMethod, Tag, Type};
use tiff::TiffError;

/// Maps errors of the `tiff` crate reading `context` (a tag name, "strip 3") to
/// [`FormatError`]s.
pub(crate) fn tag_error(context: &str) -> impl Fn(TiffError) -> FormatError + Copy + '_ {
    move |e| tiff_error(context, e)
}

/// An error of the `tiff` crate as a [`FormatError`]; `context` (e.g. "strip 3") leads the
/// reason.
pub(crate) fn tiff_error(context: &str, error: TiffError) -> FormatError {
    let reason = |what: &dyn Display| {
        if context.is_empty() {
            what.to_string()
        } else {
            format!("{context}: {what}")
        }
    };
    match error {
        TiffError::IoError(e) if e.kind() == ErrorKind::UnexpectedEof => {
            FormatError::Format(reason(&format_args!("truncated ({e})")))
        }
        TiffError::IoError(e) if e.kind() == ErrorKind::InvalidData => {
            FormatError::Format(reason(&format_args!("corrupt data ({e})")))
        }
        TiffError::IoError(e) => FormatError::Io(e),
        TiffError::UnsupportedError(e) => FormatError::Unsupported(reason(&e)),
        TiffError::LimitsExceeded => {
            FormatError::Format(reason(&"a value is larger than the memory limit allows"))
        }
        other => FormatError::Format(reason(&other)),
    }
}

/// The sample type of SampleFormat (1 unsigned, 2 signed, 3 float) and BitsPerSample.
pub(crate) fn sample_type_of(format: u16, bits: u16) -> Option<SampleType> {
    Some(match (format, bits) {
        (1, 8) => SampleType::U8,
        (1, 16) => SampleType::U16,
        (1, 32) => SampleType::U32,
        (1, 64) => SampleType::U64,
        (2, 8) => SampleType::I8,
        (2, 16) => SampleType::I16,
        (2, 32) => SampleType::I32,
        (2, 64) => SampleType::I64,
        (3, 32) => SampleType::F32,
        (3, 64) => SampleType::F64,
        _ => return None,
    })
}

/// Refuses several bands, unread sample types, photometric interpretations that would alter
/// values, and compressions the build does not decode; returns the sample type and the
/// compression's TIFF code.
pub(crate) fn check_layout<R: Read + Seek>(
    decoder: &mut Decoder<R>,
    several_bands: bool,
) -> Result<(SampleType, u16, usize), FormatError> {
    let bands = decoder
        .find_tag_unsigned::<u16>(Tag::SamplesPerPixel)
        .map_err(tag_error("SamplesPerPixel"))?
        .unwrap_or(1);
    if bands != 1 && !several_bands {
        return Err(FormatError::Unsupported(format!(
            "image of {bands} bands (samples per pixel); relief reads single-band rasters"
        )));
    }
    let planar = decoder
        .find_tag_unsigned::<u16>(Tag::PlanarConfiguration)
        .map_err(tag_error("PlanarConfiguration"))?
        .unwrap_or(1);
    if bands == 0 || (bands > 1 && planar != 2) {
        return Err(FormatError::Unsupported(format!(
            "image of {bands} bands in planar configuration {planar}; relief reads several \
                 bands stored in separate planes (2)"
        )));
    }
    let first = |values: Option<Vec<u16>>, default: u16| {
        values.and_then(|v| v.first().copied()).unwrap_or(default)
    };
    let format = first(
        decoder.find_tag_unsigned_vec(Tag::SampleFormat).map_err(tag_error("SampleFormat"))?,
        1,
    );
    let bits = first(
        decoder.find_tag_unsigned_vec(Tag::BitsPerSample).map_err(tag_error("BitsPerSample"))?,
        1,
    );
    let sample_type = sample_type_of(format, bits).ok_or_else(|| {
        let kind = match format {
            1 => "unsigned integer",
            2 => "signed integer",
            3 => "floating-point",
            4 => "untyped (SampleFormat 4)",
            5 => "complex integer",
            6 => "complex floating-point",
            _ => "unknown-format",
        };
        FormatError::Unsupported(format!("{bits}-bit {kind} samples"))
    })?;
    let photometric = decoder
        .find_tag_unsigned::<u16>(Tag::PhotometricInterpretation)
        .map_err(tag_error("PhotometricInterpretation"))?;
    if photometric != Some(1) {
        // The decoder would invert WhiteIsZero samples; other interpretations are colour.
        return Err(FormatError::Unsupported(format!(
            "photometric interpretation {photometric:?}; relief reads BlackIsZero (1)"
        )));
    }
    let compression = read_compression(decoder, true, |other, code| {
        format!(
            "compression {other:?} (TIFF code {code}); relief reads uncompressed, LZW, Deflate, \
             ZSTD and PackBits"
        )
    })?;
    Ok((sample_type, compression, usize::from(bands)))
}

/// The Compression tag's code (1, none, when absent), refused with `refusal(method, code)`'s
/// message unless it is one the decoder reads: none, LZW, Deflate, PackBits, and ZSTD where
/// `zstd` says so.
pub(crate) fn read_compression<R: Read + Seek>(
    decoder: &mut Decoder<R>,
    zstd: bool,
    refusal: impl FnOnce(CompressionMethod, u16) -> String,
) -> Result<u16, FormatError> {
    let code = decoder
        .find_tag_unsigned::<u16>(Tag::Compression)
        .map_err(tag_error("Compression"))?
        .unwrap_or(1);
    match CompressionMethod::from_u16_exhaustive(code) {
        CompressionMethod::None
        | CompressionMethod::LZW
        | CompressionMethod::Deflate
        | CompressionMethod::OldDeflate
        | CompressionMethod::PackBits => Ok(code),
        CompressionMethod::ZSTD if zstd => Ok(code),
        other => Err(FormatError::Unsupported(refusal(other, code))),
    }
}

/// GDAL_NODATA: ASCII text such as "-32768" or "nan", maybe padded with NULs or spaces.
pub(crate) fn read_nodata<R: Read + Seek>(
    decoder: &mut Decoder<R>,
) -> Result<Option<f64>, FormatError> {
    let tag_error = tag_error("GDAL_NODATA");
    let Some(value) = decoder.find_tag(Tag::GdalNodata).map_err(tag_error)? else {
        return Ok(None);
    };
    let text = value.into_string().map_err(tag_error)?;
    let text = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
    if text.is_empty() {
        return Ok(None);
    }
    text.parse::<f64>()
        .map(Some)
        .map_err(|_| FormatError::Format(format!("GDAL_NODATA {text:?} is not a number")))
}

/// The `f64` values of `tag`, if present.
fn f64_values<R: Read + Seek>(
    decoder: &mut Decoder<R>,
    tag: Tag,
    name: &str,
) -> Result<Option<Vec<f64>>, FormatError> {
    let Some(value) = decoder.find_tag(tag).map_err(tag_error(name))? else {
        return Ok(None);
    };
    value.into_f64_vec().map(Some).map_err(tag_error(name))
}

/// Reads the georeference of a `width x height` raster: its placement, and its tags as stored.
pub(crate) fn read_placement<R: Read + Seek>(
    decoder: &mut Decoder<R>,
    width: usize,
    height: usize,
) -> Result<(Placement, GeoTiffTags), FormatError> {
    let scale = f64_values(decoder, Tag::ModelPixelScaleTag, "ModelPixelScaleTag")?;
    let ties = f64_values(decoder, Tag::ModelTiepointTag, "ModelTiepointTag")?;
    let transform = f64_values(decoder, Tag::ModelTransformationTag, "ModelTransformationTag")?;
    let keys_error = tag_error("GeoKeyDirectoryTag");
    let directory = match decoder.find_tag(Tag::GeoKeyDirectoryTag).map_err(keys_error)? {
        Some(value) => Some(value.into_u16_vec().map_err(keys_error)?),
        None => None,
    };
    let geo_ascii_params = ascii_bytes(decoder, Tag::GeoAsciiParamsTag, "GeoAsciiParamsTag")?;
    let keys = match &directory {
        Some(directory) => GeoKeys::parse(directory)?,
        None => GeoKeys::default(),
    }
    .with_citation(geo_ascii_params.as_deref());
    let tags = ModelTags { scale, ties, transform };
    let placement = model_placement(&tags, &keys, (width, height))?;
    let geo_double_params = f64_values(decoder, Tag::GeoDoubleParamsTag, "GeoDoubleParamsTag")?;
    let tags = GeoTiffTags {
        model_pixel_scale: tags.scale,
        model_tiepoint: tags.ties,
        model_transformation: tags.transform,
        geo_key_directory: directory,
        geo_double_params,
        geo_ascii_params,
    };
    Ok((placement, tags))
}

/// The bytes of the ASCII tag `tag` as stored, terminating NUL included, if present.
fn ascii_bytes<R: Read + Seek>(
    decoder: &mut Decoder<R>,
    tag: Tag,
    name: &str,
) -> Result<Option<Vec<u8>>, FormatError> {
    let mut ifd = decoder.image_ifd();
    let Some(entry) = ifd.find_entry(tag) else {
        return Ok(None);
    };
    if entry.field_type() != Type::ASCII {
        return Err(FormatError::Format(format!("{name} is not ASCII text")));
    }
    // The limits bound the count before anything is allocated.
    let len = usize::try_from(entry.count())
        .ok()
        .filter(|&n| n <= MAX_ASCII_TAG)
        .ok_or_else(|| FormatError::Format(format!("{name} of {} bytes", entry.count())))?;
    let mut bytes = vec![0u8; len];
    ifd.find_tag_bytes(tag, &mut bytes, 0).map_err(tag_error(name))?;
    Ok(Some(bytes))
}

/// The longest GeoAsciiParams accepted: far more than any CRS's citations need.
const MAX_ASCII_TAG: usize = 1 << 20;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_types_from_tags() {
        assert_eq!(sample_type_of(2, 16), Some(SampleType::I16));
        assert_eq!(sample_type_of(3, 64), Some(SampleType::F64));
        assert_eq!(sample_type_of(3, 16), None);
        assert_eq!(sample_type_of(1, 12), None);
        assert_eq!(sample_type_of(6, 32), None);
    }
}
