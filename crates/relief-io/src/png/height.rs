//! Heights stored in PNG images: greyscale samples, Mapbox terrain-RGB and Terrarium tiles.
//!
//! | encoding | pixels | height |
//! |---|---|---|
//! | grey | 8- or 16-bit greyscale | the grey value, or grey * `height_scale` + `height_offset` when its tEXt chunks say so |
//! | terrain-RGB | 8-bit RGB or RGBA | -10000 + (R * 65536 + G * 256 + B) * 0.1 |
//! | Terrarium | 8-bit RGB or RGBA | R * 256 + G + B / 256 - 32768 |
//!
//! A fully transparent pixel (alpha 0, in an image with an alpha channel) is a void.

use crate::format_error::FormatError;
use crate::input_file::open_input;
use crate::png::decoding_error::png_decoding_error;
use crate::png::write::{write_png, PngCompression};
use crate::raster::{mark_voids, Format, PngEncoding, Raster, RasterInfo, ReadOptions};
use crate::{HeightUnit, IoError, LengthUnit};
use png::{BitDepth, ColorType, Transformations};
use relief_core::{GridGeometry, HeightField};
use std::io::{BufRead, BufReader, Seek};
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
/// A grey PNG whose tEXt chunks hold `height_scale` and `height_offset` (as
/// [`write_png16_height_in`] writes them) has heights `grey * height_scale + height_offset`,
/// in the unit its `height_unit` names (the raster's z scale its metres). A world file beside
/// the image (`.pgw`) places it, in the CRS of a `.prj` beside it (ESRI WKT); without one the
/// raster has spacing 1, origin 0. Rows are decoded one at a time (interlaced images, rare for
/// heights, are decoded whole).
///
/// Errors: [`IoError::Io`] when the file cannot be read (or is a directory),
/// [`IoError::Format`] for a malformed or truncated PNG or one whose header claims more pixels
/// than the file can hold, [`IoError::Unsupported`] for a colour type the encoding cannot use
/// (naming it; `--png-encoding` picks the encoding), [`IoError::Limits`] for an image over the
/// memory budget.
pub fn read_png_height(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let (file, len) = open_input(path)?;
    let raster =
        read_png_height_from(BufReader::new(file), len, options).map_err(|e| e.at(path))?;
    crate::georef::sidecars::with_world_file(path, raster)
}

/// [`read_png_height`] from `reader` holding the `len` bytes of a PNG, before the file is
/// named and without the placement of a world file beside it.
pub(crate) fn read_png_height_from<R: BufRead + Seek>(
    reader: R,
    len: u64,
    options: &ReadOptions,
) -> Result<Raster, FormatError> {
    // A damaged tEXt chunk must not be skipped: its scale and offset are the heights'.
    let mut checks = png::DecodeOptions::default();
    checks.set_skip_ancillary_crc_failures(false);
    let mut decoder = png::Decoder::new_with_options(reader, checks);
    decoder.set_transformations(Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(png_decoding_error)?;
    let info = reader.info();
    let (width, height) = info.size();
    let (color, depth, interlaced) = (info.color_type, info.bit_depth, info.interlaced);
    let encoding = options.png_encoding;
    let declared = if encoding == PngEncoding::Grey { declared_scale(info)? } else { None };
    let layout = layout(encoding, color, depth)?;
    options.check_samples(u64::from(width), u64::from(height))?;
    let pixel_bytes = (layout.channels * layout.channel_bytes) as u64;
    let image_bytes = (u64::from(width) * u64::from(height)).saturating_mul(pixel_bytes);
    if image_bytes > len.saturating_mul(MAX_INFLATION) {
        return Err(FormatError::Format(format!(
            "{width} x {height} pixels cannot fit in a file of {len} bytes"
        )));
    }
    // Both fit in usize: check_size bounds their product.
    let (w, h) = (width as usize, height as usize);
    let mut samples = vec![0f32; w * h];
    // The image's top row is the northernmost: it becomes the raster's last row.
    let mut rows = samples.chunks_exact_mut(w).rev();
    if interlaced {
        let size = reader.output_buffer_size().ok_or_else(|| {
            FormatError::Format(format!("{width} x {height} pixels is too large"))
        })?;
        let mut buf = vec![0u8; size];
        let frame = reader.next_frame(&mut buf).map_err(png_decoding_error)?;
        for (line, out) in buf.chunks_exact(frame.line_size.max(1)).zip(rows) {
            decode_row(line, layout, encoding, out);
        }
    } else {
        for out in rows.by_ref() {
            let row = reader.next_row().map_err(png_decoding_error)?;
            let row = row.ok_or_else(|| FormatError::Format("image data ends early".into()))?;
            decode_row(row.data(), layout, encoding, out);
        }
        if reader.next_row().map_err(png_decoding_error)?.is_some() {
            return Err(FormatError::Format("more rows than the header declares".into()));
        }
    }
    reader.finish().map_err(png_decoding_error)?;
    if let Some((scale, _)) = &declared {
        for v in samples.iter_mut().filter(|v| !v.is_nan()) {
            *v = scale.height(*v as u16) as f32;
        }
    }
    // Decoded heights are finite; transparent pixels are already NaN, the only voids.
    mark_voids(&mut samples, w, layout.alpha.then_some(f64::NAN), true)?;
    let (format, sample_type) = match encoding {
        PngEncoding::Grey => {
            (Format::Png16, if depth == BitDepth::Sixteen { "uint16" } else { "uint8" })
        }
        PngEncoding::TerrainRgb => {
            (Format::TerrainRgb, if layout.alpha { "rgba8" } else { "rgb8" })
        }
        PngEncoding::Terrarium => (Format::Terrarium, if layout.alpha { "rgba8" } else { "rgb8" }),
    };
    let height_unit = declared.map(|(_, unit)| unit).unwrap_or_default();
    Ok(Raster {
        width: w,
        height: h,
        samples,
        geometry: GridGeometry { z_scale: height_unit.unit.metres(), ..GridGeometry::unit() },
        info: RasterInfo {
            format,
            sample_type: sample_type.into(),
            georeferenced: false,
            height_unit,
            from_degrees: None,
            georeference: None,
            nodata: None,
        },
    })
}

/// The pixel layout of a `color`/`depth` image for `encoding`, or why it cannot be used.
fn layout(encoding: PngEncoding, color: ColorType, depth: BitDepth) -> Result<Layout, FormatError> {
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
    Err(FormatError::Unsupported(format!(
        "{}-bit {colour} PNG: {need} (choose how the pixels encode heights with \
         --png-encoding grey|terrain-rgb|terrarium)",
        depth as u8
    )))
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

/// The tEXt keyword of a height PNG's scale: height = grey * scale + offset.
pub const PNG_HEIGHT_SCALE: &str = "height_scale";
/// The tEXt keyword of a height PNG's offset: height = grey * scale + offset.
pub const PNG_HEIGHT_OFFSET: &str = "height_offset";
/// The tEXt keyword of a height PNG's unit: `metre`, `foot` or `US survey foot`.
pub const PNG_HEIGHT_UNIT: &str = "height_unit";

/// How a 16-bit height PNG maps grey values to heights: `height = grey * scale + offset`,
/// stored in the PNG's tEXt chunks `height_scale`, `height_offset` (and `height_unit`), which
/// [`read_png_height`] applies.
///
/// ```
/// use relief_core::{GridGeometry, HeightField};
/// use relief_io::png::PngHeightScale;
/// // Whole heights within 0..=65535 are stored as they are.
/// let whole = HeightField::new(2, 1, vec![3.0, 900.0], GridGeometry::unit())?;
/// assert_eq!(PngHeightScale::of(&whole), PngHeightScale { scale: 1.0, offset: 0.0 });
/// // Others use all 16 bits over their range.
/// let fbm = HeightField::new(2, 1, vec![-1.5, 188.7], GridGeometry::unit())?;
/// let s = PngHeightScale::of(&fbm);
/// assert_eq!(s.offset, -1.5f32 as f64);
/// assert!((s.scale - (188.7f32 as f64 + 1.5) / 65535.0).abs() < 1e-12);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PngHeightScale {
    /// Height units per grey level: the step of the stored heights.
    pub scale: f64,
    /// The height of grey 0.
    pub offset: f64,
}

impl PngHeightScale {
    /// The scale [`write_png16_height`] uses for `field`'s world heights (`sample * z_scale`,
    /// holes left out): 1 and 0 when they are whole numbers within 0..=65535 (stored exactly),
    /// else the lowest height at grey 0 and the highest at 65535.
    pub fn of(field: &HeightField) -> PngHeightScale {
        let z = field.geometry().z_scale;
        let mut range: Option<(f64, f64)> = None;
        let mut whole = true;
        for row in 0..field.height() {
            for col in 0..field.width() {
                if field.is_hole(col, row) {
                    continue;
                }
                let v = f64::from(field.sample(col, row)) * z;
                whole &= v.fract() == 0.0 && (0.0..=65535.0).contains(&v);
                range = Some(range.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))));
            }
        }
        match range {
            _ if whole => PngHeightScale { scale: 1.0, offset: 0.0 },
            Some((lo, hi)) if hi > lo => PngHeightScale { scale: (hi - lo) / 65535.0, offset: lo },
            Some((lo, _)) => PngHeightScale { scale: 1.0, offset: lo },
            None => PngHeightScale { scale: 1.0, offset: 0.0 },
        }
    }

    /// The grey level of `height`, rounded, clamped to 0..=65535.
    fn grey(&self, height: f64) -> u16 {
        ((height - self.offset) / self.scale).round().clamp(0.0, 65535.0) as u16
    }

    /// The height of grey level `grey`.
    pub fn height(&self, grey: u16) -> f64 {
        f64::from(grey) * self.scale + self.offset
    }
}

/// Writes `field` as a 16-bit greyscale PNG of its heights in `unit`, north (the last grid
/// row) at the top, using all 16 bits.
///
/// - Heights: the world heights `sample * z_scale` (in `unit`, the metre for
///   [`write_png16_height`]), stored as grey levels of [`PngHeightScale::of`]: `height = grey
///   * height_scale + height_offset`, the scale and offset in tEXt chunks with the unit, so
///   that [`read_png_height`] (and any reader told of them) gets the heights back within half
///   a step (`height_scale / 2`); whole heights in 0..=65535 are stored exactly, scale 1.
/// - Voids: with holes the image is grey + alpha, a hole transparent (alpha 0), which
///   [`read_png_height`] reads as a void; without, plain grey.
///
/// The file is written atomically. Errors: [`IoError::InvalidData`] for a field too large for
/// a PNG, [`IoError::Io`] when the file cannot be written.
pub fn write_png16_height_in(
    path: &Path,
    field: &HeightField,
    unit: LengthUnit,
) -> Result<PngHeightScale, IoError> {
    let (w, h) = (field.width(), field.height());
    let (Ok(width), Ok(height)) = (u32::try_from(w), u32::try_from(h)) else {
        return Err(IoError::invalid_data(
            path,
            format!("{w} x {h} samples is too large for a PNG"),
        ));
    };
    let scale = PngHeightScale::of(field);
    let z = field.geometry().z_scale;
    let alpha = field.hole_count() > 0;
    let mut bytes = Vec::with_capacity(w * h * if alpha { 4 } else { 2 });
    for row in (0..h).rev() {
        for col in 0..w {
            let hole = field.is_hole(col, row);
            let grey = if hole { 0 } else { scale.grey(f64::from(field.sample(col, row)) * z) };
            bytes.extend(grey.to_be_bytes());
            if alpha {
                bytes.extend(if hole { [0, 0] } else { [255, 255] });
            }
        }
    }
    let text = [
        (PNG_HEIGHT_SCALE, scale.scale.to_string()),
        (PNG_HEIGHT_OFFSET, scale.offset.to_string()),
        (PNG_HEIGHT_UNIT, unit.name().to_string()),
    ];
    let color = if alpha { ColorType::GrayscaleAlpha } else { ColorType::Grayscale };
    let image = (color, BitDepth::Sixteen, PngCompression::Balanced);
    write_png(path, width, height, image, &bytes, &text)?;
    Ok(scale)
}

/// Writes `field` as a 16-bit greyscale PNG of its heights in metres: see
/// [`write_png16_height_in`].
pub fn write_png16_height(path: &Path, field: &HeightField) -> Result<(), IoError> {
    write_png16_height_in(path, field, LengthUnit::Metre).map(|_| ())
}

/// The scale, offset and unit a grey height PNG's tEXt chunks declare (see
/// [`write_png16_height_in`]); `None` when it declares none. A scale or offset that is not a
/// finite number (or a zero scale), or an unknown unit, is a format error.
fn declared_scale(
    info: &png::Info<'_>,
) -> Result<Option<(PngHeightScale, HeightUnit)>, FormatError> {
    let find = |keyword: &str| {
        info.uncompressed_latin1_text.iter().find(|t| t.keyword == keyword).map(|t| t.text.trim())
    };
    let (scale, offset) = match (find(PNG_HEIGHT_SCALE), find(PNG_HEIGHT_OFFSET)) {
        (None, None) => return Ok(None),
        (scale, offset) => (scale.unwrap_or("1"), offset.unwrap_or("0")),
    };
    let number = |keyword: &str, text: &str| {
        text.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| {
            FormatError::Format(format!("tEXt {keyword} '{text}' is not a finite number"))
        })
    };
    let scale = PngHeightScale {
        scale: number(PNG_HEIGHT_SCALE, scale)?,
        offset: number(PNG_HEIGHT_OFFSET, offset)?,
    };
    if scale.scale == 0.0 {
        return Err(FormatError::Format("tEXt height_scale is 0".into()));
    }
    let unit = match find(PNG_HEIGHT_UNIT) {
        None => HeightUnit::new(
            LengthUnit::Metre,
            "the PNG's height_scale, which names no unit: metres",
        ),
        Some(name) => {
            let unit = LengthUnit::ALL.into_iter().find(|u| u.name() == name).ok_or_else(|| {
                FormatError::Format(format!(
                    "tEXt height_unit '{name}' (expected metre, foot or US survey foot)"
                ))
            })?;
            HeightUnit::new(unit, "the PNG's tEXt height_unit")
        }
    };
    Ok(Some((scale, unit)))
}
