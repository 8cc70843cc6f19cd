//! Heights stored in PNG images: greyscale samples, Mapbox terrain-RGB and Terrarium tiles.
//!
//! | encoding | pixels | height |
//! |---|---|---|
//! | grey | 8- or 16-bit greyscale | the grey value |
//! | terrain-RGB | 8-bit RGB or RGBA | -10000 + (R * 65536 + G * 256 + B) * 0.1 |
//! | Terrarium | 8-bit RGB or RGBA | R * 256 + G + B / 256 - 32768 |
//!
//! A fully transparent pixel (alpha 0, in an image with an alpha channel) is a void.

use crate::input_file::open_input;
use crate::raster::{mark_voids, Format, PngEncoding, Raster, RasterInfo, ReadOptions};
use crate::{write_png_gray16, IoError};
use png::{BitDepth, ColorType, DecodingError, Transformations};
use relief_core::{GridGeometry, HeightField};
use std::io::{BufRead, BufReader, ErrorKind, Seek};
use std::path::Path;

/// The largest inflation deflate allows (about 1032:1): a file of `n` bytes holds at most
/// `n * 1032` bytes of pixels, so a header that claims more is refused before allocating.
const MAX_INFLATION: u64 = 1032;

/// How the bytes of one pixel are laid out, as far as heights are concerned.
#[derive(Debug, Clone, Copy)]
struct Layout {
    /// Bytes per channel: 1 or 2.
    channel_bytes: usize,
    /// Channels per pixel: 1 to 4.
    channels: usize,
    /// Whether the last channel is alpha.
    alpha: bool,
}

/// Reads the PNG at `path` as heights encoded as `options.png_encoding` says, row 0 south
/// (the image's bottom row).
///
/// Grey heights need an 8- or 16-bit greyscale image (with or without alpha); terrain-RGB and
/// Terrarium heights need an 8-bit RGB or RGBA image. A pixel with alpha 0 is a void (NaN).
/// The raster has no georeference: spacing 1, origin 0. Rows are decoded one at a time
/// (interlaced images, rare for heights, are decoded whole).
///
/// Errors: [`IoError::Io`] when the file cannot be read (or is a directory),
/// [`IoError::Format`] for a malformed or truncated PNG or one whose header claims more pixels
/// than the file can hold, [`IoError::Unsupported`] for a colour type the encoding cannot use
/// (naming it; `--png-encoding` picks the encoding), [`IoError::Limits`] for an image over the
/// memory budget.
pub fn read_png_height(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let (file, len) = open_input(path)?;
    read_png_height_from(BufReader::new(file), len, path, options)
}

/// [`read_png_height`] from `reader` holding the `len` bytes of a PNG; `path` names the file
/// in errors.
pub(crate) fn read_png_height_from<R: BufRead + Seek>(
    reader: R,
    len: u64,
    path: &Path,
    options: &ReadOptions,
) -> Result<Raster, IoError> {
    let map = |e: DecodingError| match e {
        DecodingError::IoError(e) if e.kind() == ErrorKind::UnexpectedEof => {
            IoError::format(path, "truncated")
        }
        DecodingError::IoError(e) => IoError::io(path, e),
        other => IoError::format(path, other.to_string()),
    };
    let mut decoder = png::Decoder::new(reader);
    decoder.set_transformations(Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(map)?;
    let info = reader.info();
    let (width, height) = info.size();
    let (color, depth, interlaced) = (info.color_type, info.bit_depth, info.interlaced);
    let encoding = options.png_encoding;
    let layout = layout(path, encoding, color, depth)?;
    options.check_size(path, u64::from(width), u64::from(height))?;
    let pixel_bytes = (layout.channels * layout.channel_bytes) as u64;
    let image_bytes = (u64::from(width) * u64::from(height)).saturating_mul(pixel_bytes);
    if image_bytes > len.saturating_mul(MAX_INFLATION) {
        return Err(IoError::format(
            path,
            format!("{width} x {height} pixels cannot fit in a file of {len} bytes"),
        ));
    }
    // Both fit in usize: check_size bounds their product.
    let (w, h) = (width as usize, height as usize);
    let mut samples = vec![0f32; w * h];
    // The image's top row is the northernmost: it becomes the raster's last row.
    let mut rows = samples.chunks_exact_mut(w).rev();
    if interlaced {
        let size = reader.output_buffer_size().ok_or_else(|| {
            IoError::format(path, format!("{width} x {height} pixels is too large"))
        })?;
        let mut buf = vec![0u8; size];
        let frame = reader.next_frame(&mut buf).map_err(map)?;
        for (line, out) in buf.chunks_exact(frame.line_size.max(1)).zip(rows) {
            decode_row(line, layout, encoding, out);
        }
    } else {
        for out in rows.by_ref() {
            let row = reader.next_row().map_err(map)?;
            let row = row.ok_or_else(|| IoError::format(path, "image data ends early"))?;
            decode_row(row.data(), layout, encoding, out);
        }
        if reader.next_row().map_err(map)?.is_some() {
            return Err(IoError::format(path, "more rows than the header declares"));
        }
    }
    reader.finish().map_err(map)?;
    // Decoded heights are finite; transparent pixels are already NaN, the only voids.
    mark_voids(path, &mut samples, w, layout.alpha.then_some(f64::NAN), true)?;
    let (format, sample_type) = match encoding {
        PngEncoding::Grey => {
            (Format::Png16, if depth == BitDepth::Sixteen { "uint16" } else { "uint8" })
        }
        PngEncoding::TerrainRgb => {
            (Format::TerrainRgb, if layout.alpha { "rgba8" } else { "rgb8" })
        }
        PngEncoding::Terrarium => (Format::Terrarium, if layout.alpha { "rgba8" } else { "rgb8" }),
    };
    Ok(Raster {
        width: w,
        height: h,
        samples,
        geometry: GridGeometry::unit(),
        info: RasterInfo {
            format,
            sample_type: sample_type.into(),
            georeferenced: false,
            from_degrees: None,
            georeference: None,
            nodata: None,
        },
    })
}

/// The pixel layout of a `color`/`depth` image for `encoding`, or why it cannot be used.
fn layout(
    path: &Path,
    encoding: PngEncoding,
    color: ColorType,
    depth: BitDepth,
) -> Result<Layout, IoError> {
    let channel_bytes = match depth {
        BitDepth::Eight => 1,
        BitDepth::Sixteen => 2,
        _ => 0,
    };
    let (channels, alpha) = match color {
        ColorType::Grayscale => (1, false),
        ColorType::GrayscaleAlpha => (2, true),
        ColorType::Rgb => (3, false),
        ColorType::Rgba => (4, true),
        ColorType::Indexed => (0, false),
    };
    let layout = Layout { channel_bytes, channels, alpha };
    let grey = matches!(color, ColorType::Grayscale | ColorType::GrayscaleAlpha);
    let rgb = matches!(color, ColorType::Rgb | ColorType::Rgba);
    let (usable, need) = match encoding {
        PngEncoding::Grey => {
            (grey && channel_bytes > 0, "grey heights need 8- or 16-bit greyscale")
        }
        PngEncoding::TerrainRgb => {
            (rgb && channel_bytes == 1, "terrain-RGB heights need 8-bit RGB or RGBA")
        }
        PngEncoding::Terrarium => {
            (rgb && channel_bytes == 1, "Terrarium heights need 8-bit RGB or RGBA")
        }
    };
    if usable {
        return Ok(layout);
    }
    let colour = match color {
        ColorType::Grayscale => "greyscale",
        ColorType::GrayscaleAlpha => "greyscale+alpha",
        ColorType::Rgb => "RGB",
        ColorType::Rgba => "RGBA",
        ColorType::Indexed => "palette (indexed-colour)",
    };
    Err(IoError::unsupported(
        path,
        format!(
            "{}-bit {colour} PNG: {need} (choose how the pixels encode heights with \
             --png-encoding grey|terrain-rgb|terrarium)",
            depth as u8
        ),
    ))
}

/// Decodes one image row of `layout` pixels into heights, NaN for a transparent pixel.
fn decode_row(line: &[u8], layout: Layout, encoding: PngEncoding, out: &mut [f32]) {
    let pixel_bytes = layout.channels * layout.channel_bytes;
    for (v, p) in out.iter_mut().zip(line.chunks_exact(pixel_bytes)) {
        let channel = |i: usize| match layout.channel_bytes {
            2 => u32::from(u16::from_be_bytes([p[2 * i], p[2 * i + 1]])),
            _ => u32::from(p[i]),
        };
        if layout.alpha && channel(layout.channels - 1) == 0 {
            *v = f32::NAN;
            continue;
        }
        let (r, g, b) =
            (channel(0), channel(1.min(layout.channels - 1)), channel(2.min(layout.channels - 1)));
        *v = match encoding {
            PngEncoding::Grey => r as f32,
            PngEncoding::TerrainRgb => (-10000.0 + f64::from(r * 65536 + g * 256 + b) * 0.1) as f32,
            PngEncoding::Terrarium => {
                (f64::from(r * 256 + g) + f64::from(b) / 256.0 - 32768.0) as f32
            }
        };
    }
}

/// Writes `field` as a 16-bit greyscale PNG, north (the last grid row) at the top: each
/// sample rounded to the nearest integer is the grey value, holes are 0.
///
/// The samples are written as they are, without `z_scale`, to keep all 16 bits of precision;
/// the PNG stores no geometry, so give the scale and spacing again when reading it back.
/// The file is written atomically.
///
/// Errors: [`IoError::InvalidData`] naming the first sample that rounds outside 0..=65535 (or
/// a field too large for a PNG), [`IoError::Io`] when the file cannot be written.
pub fn write_png16_height(path: &Path, field: &HeightField) -> Result<(), IoError> {
    let (w, h) = (field.width(), field.height());
    let (Ok(width), Ok(height)) = (u32::try_from(w), u32::try_from(h)) else {
        return Err(IoError::invalid_data(
            path,
            format!("{w} x {h} samples is too large for a PNG"),
        ));
    };
    let mut grey = Vec::with_capacity(w * h);
    for row in (0..h).rev() {
        for col in 0..w {
            if field.is_hole(col, row) {
                grey.push(0);
                continue;
            }
            let v = field.sample(col, row).round();
            if !(0.0..=65535.0).contains(&v) {
                return Err(IoError::invalid_data(
                    path,
                    format!(
                        "sample {} at column {col}, row {row} is outside the 0..=65535 range of \
                         a 16-bit PNG",
                        field.sample(col, row)
                    ),
                ));
            }
            grey.push(v as u16);
        }
    }
    write_png_gray16(path, width, height, &grey)
}
