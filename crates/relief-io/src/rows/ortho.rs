//! Reading an ortho photo (an 8-bit RGB or RGBA PNG or GeoTIFF) row by row from its first
//! row on, with its georeference: the colour a tile store drapes over its DEM, read in bands so
//! that a photo far larger than memory can be tiled.

use crate::format_error::FormatError;
use crate::geotiff::tags::{read_compression, read_placement, tag_error, tiff_error};
use crate::input_file::open_input;
use crate::png::decoding_error::png_decoding_error;
use crate::{Georeference, IoError};
use png::{ColorType as PngColour, Transformations};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use tiff::decoder::{ChunkType, Decoder, DecodingResult};
use tiff::tags::Tag;
use tiff::ColorType as TiffColour;

/// The largest inflation deflate allows (about 1032:1) times the largest growth of a pixel
/// (1-bit palette index to 32-bit RGBA): bounds the pixels a file of a given length can hold,
/// so that a lying header cannot make a reader allocate.
const MAX_BYTES_PER_FILE_BYTE: u64 = 1032 * 32;

/// What an ortho photo's file says about itself.
#[derive(Debug, Clone, PartialEq)]
pub struct OrthoInfo {
    /// The file.
    pub path: PathBuf,
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// The GeoTIFF's placement and CRS; `None` for a PNG or a TIFF without model tags.
    pub georeference: Option<Georeference>,
}

/// An ortho photo read row by row, from the file's first row (the top row of a north-up
/// image) to its last, each row as 8-bit RGB (alpha is dropped, grey is replicated).
pub trait OrthoRows: Send {
    /// The file's size and georeference.
    fn info(&self) -> &OrthoInfo;
    /// Reads the file's next row into `out` (`width` pixels). Fails past the last row, or when
    /// the file cannot be read or decoded (the error names the file).
    fn read_next_row(&mut self, out: &mut [[u8; 3]]) -> Result<(), IoError>;
}

/// Opens the ortho photo at `path` for reading row by row: a PNG (`.png`, any colour type of 8
/// or 16 bits, reduced to 8-bit RGB) or a GeoTIFF (`.tif`, `.tiff`: 8-bit RGB or RGBA, or
/// 8-bit grey, chunky, in strips or tiles, uncompressed or compressed with LZW, Deflate or
/// PackBits), by extension.
///
/// A PNG is decoded a row at a time (an interlaced one, whose rows come in seven passes, is
/// decoded whole); a GeoTIFF a row of strips or tiles at a time. Errors:
/// [`IoError::Unsupported`] for another extension or another layout (JPEG compression, YCbCr,
/// 16-bit or planar colour), [`IoError::Format`] for a damaged file.
pub fn open_ortho(path: &Path) -> Result<Box<dyn OrthoRows>, IoError> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("png") => Ok(Box::new(PngOrtho::open(path)?)),
        Some("tif" | "tiff") => Ok(Box::new(TiffOrtho::open(path)?)),
        _ => Err(IoError::unsupported(
            path,
            "ortho photo format (relief reads 8-bit RGB PNG and GeoTIFF: .png, .tif, .tiff)",
        )),
    }
}

/// Refuses a header whose pixels could not fit in a file of `file_len` bytes.
fn check_fits(width: u32, height: u32, file_len: u64) -> Result<(), FormatError> {
    let pixels = width as u64 * height as u64;
    if width == 0 || height == 0 || pixels > file_len.saturating_mul(MAX_BYTES_PER_FILE_BYTE) {
        return Err(FormatError::Format(format!(
            "{width} x {height} pixels cannot fit in a file of {file_len} bytes"
        )));
    }
    Ok(())
}

/// Copies a decoded row of `channels` samples per pixel into RGB pixels.
fn to_rgb(row: &[u8], channels: usize, out: &mut [[u8; 3]]) {
    for (o, p) in out.iter_mut().zip(row.chunks_exact(channels)) {
        *o = match *p {
            [g] | [g, _] => [g, g, g],
            [r, g, b, ..] => [r, g, b],
            _ => [0, 0, 0],
        };
    }
}

/// A PNG read row by row.
struct PngOrtho {
    info: OrthoInfo,
    reader: png::Reader<BufReader<File>>,
    channels: usize,
    /// An interlaced image, decoded whole, and the next row to serve from it.
    whole: Option<(Vec<u8>, usize, usize)>,
    next: u32,
}

impl PngOrtho {
    /// Opens the PNG at `path` and reads its header.
    fn open(path: &Path) -> Result<Self, IoError> {
        let (file, file_len) = open_input(path)?;
        Self::start(file, file_len, path.to_path_buf()).map_err(|e| e.at(path))
    }

    /// Reads the header of the PNG `file` of `file_len` bytes (an interlaced image whole),
    /// before the file is named; `path`, the file's, is kept in its info.
    fn start(file: File, file_len: u64, path: PathBuf) -> Result<Self, FormatError> {
        let mut decoder = png::Decoder::new(BufReader::new(file));
        decoder.set_transformations(Transformations::EXPAND | Transformations::STRIP_16);
        let mut reader = decoder.read_info().map_err(png_decoding_error)?;
        let (width, height) = reader.info().size();
        check_fits(width, height, file_len)?;
        let channels = match reader.output_color_type().0 {
            PngColour::Grayscale => 1,
            PngColour::GrayscaleAlpha => 2,
            PngColour::Rgb => 3,
            PngColour::Rgba => 4,
            PngColour::Indexed => {
                return Err(FormatError::Unsupported(
                    "palette image that did not expand to RGB".into(),
                ))
            }
        };
        let whole = if reader.info().interlaced {
            let size = reader.output_buffer_size().ok_or_else(|| {
                FormatError::Format(format!("{width} x {height} pixels overflow"))
            })?;
            let mut buf = vec![0u8; size];
            let frame = reader.next_frame(&mut buf).map_err(png_decoding_error)?;
            Some((buf, frame.line_size, 0))
        } else {
            None
        };
        let info = OrthoInfo { path, width, height, georeference: None };
        Ok(PngOrtho { info, reader, channels, whole, next: 0 })
    }
}

impl OrthoRows for PngOrtho {
    fn info(&self) -> &OrthoInfo {
        &self.info
    }

    fn read_next_row(&mut self, out: &mut [[u8; 3]]) -> Result<(), IoError> {
        self.next_row(out).map_err(|e| e.at(&self.info.path))
    }
}

impl PngOrtho {
    /// [`OrthoRows::read_next_row`] before the file is named.
    fn next_row(&mut self, out: &mut [[u8; 3]]) -> Result<(), FormatError> {
        if self.next >= self.info.height {
            return Err(FormatError::Format("read past the last row".into()));
        }
        self.next += 1;
        let width = self.info.width as usize;
        if let Some((buf, line, row)) = &mut self.whole {
            let bytes = &buf[*row * *line..][..width * self.channels];
            *row += 1;
            to_rgb(bytes, self.channels, out);
            return Ok(());
        }
        let row = self.reader.next_row().map_err(png_decoding_error)?;
        let row = row.ok_or_else(|| FormatError::Format("truncated".into()))?;
        let data = row.data();
        if data.len() < width * self.channels {
            return Err(FormatError::Format("a row decoded short".into()));
        }
        to_rgb(data, self.channels, out);
        Ok(())
    }
}

/// A GeoTIFF read a row of strips or tiles at a time.
struct TiffOrtho {
    info: OrthoInfo,
    decoder: Decoder<BufReader<File>>,
    channels: usize,
    /// Pixels per stored chunk row and column.
    chunk: (usize, usize),
    /// Chunks across the image.
    chunks_across: usize,
    /// The decoded chunk row: `chunk.1` rows of `width * channels` bytes, and its index.
    band: Vec<u8>,
    band_index: Option<usize>,
    scratch: DecodingResult,
    next: u32,
}

impl TiffOrtho {
    /// Opens the GeoTIFF at `path` and reads its tags.
    fn open(path: &Path) -> Result<Self, IoError> {
        let (file, file_len) = open_input(path)?;
        Self::start(file, file_len, path.to_path_buf()).map_err(|e| e.at(path))
    }

    /// Reads and checks the tags of the GeoTIFF `file` of `file_len` bytes, before the file is
    /// named; `path`, the file's, is kept in its info.
    fn start(file: File, file_len: u64, path: PathBuf) -> Result<Self, FormatError> {
        let tiff = |e| tiff_error("", e);
        let mut decoder = Decoder::new(BufReader::new(file)).map_err(tiff)?;
        let (width, height) = decoder.dimensions().map_err(tiff)?;
        check_fits(width, height, file_len)?;
        let colour = decoder.colortype().map_err(tiff)?;
        let channels = match colour {
            TiffColour::RGB(8) => 3,
            TiffColour::RGBA(8) => 4,
            TiffColour::Gray(8) => 1,
            other => {
                return Err(FormatError::Unsupported(format!(
                    "{other:?} ortho photo; relief reads 8-bit RGB, RGBA or grey"
                )))
            }
        };
        let planar = decoder
            .find_tag_unsigned::<u16>(Tag::PlanarConfiguration)
            .map_err(tag_error("PlanarConfiguration"))?
            .unwrap_or(1);
        if planar != 1 && channels > 1 {
            return Err(FormatError::Unsupported(
                "colour in separate planes (PlanarConfiguration 2); relief reads interleaved RGB"
                    .into(),
            ));
        }
        read_compression(&mut decoder, false, |other, code| {
            format!(
                "{other:?} compression (TIFF code {code}) of an ortho photo; relief reads \
                 uncompressed, LZW, Deflate and PackBits (convert with gdal_translate -co \
                 COMPRESS=DEFLATE)"
            )
        })?;
        let (placement, tags) = read_placement(&mut decoder, width as usize, height as usize)?;
        let georeference =
            if placement.georeferenced { Georeference::from_geotiff_tags(tags) } else { None };
        let (cw, ch) = decoder.chunk_dimensions();
        let chunk = (cw as usize, ch as usize);
        if chunk.0 == 0 || chunk.1 == 0 {
            return Err(FormatError::Format("chunks of no pixels".into()));
        }
        let chunks_across = match decoder.get_chunk_type() {
            ChunkType::Strip => 1,
            ChunkType::Tile => (width as usize).div_ceil(chunk.0),
        };
        let info = OrthoInfo { path, width, height, georeference };
        Ok(TiffOrtho {
            info,
            decoder,
            channels,
            chunk,
            chunks_across,
            band: Vec::new(),
            band_index: None,
            scratch: DecodingResult::U8(Vec::new()),
            next: 0,
        })
    }

    /// Decodes chunk row `index` into `band`.
    fn decode_band(&mut self, index: usize) -> Result<(), FormatError> {
        let width = self.info.width as usize;
        let row_bytes = width * self.channels;
        let rows = self.chunk.1.min(self.info.height as usize - index * self.chunk.1);
        self.band.resize(rows * row_bytes, 0);
        for across in 0..self.chunks_across {
            let chunk = index * self.chunks_across + across;
            let name = format!("chunk {chunk}");
            let chunk_u32 = u32::try_from(chunk)
                .map_err(|_| FormatError::Unsupported(format!("{name} (index beyond u32)")))?;
            // Whole stored rows, padding included (see geotiff_read: tiff 0.11.3 fails on some
            // LZW tiles cut by the east edge when asked for their data width only).
            let stride = self.chunk.0 * self.channels;
            self.decoder
                .read_chunk_to_buffer(&mut self.scratch, chunk_u32, stride)
                .map_err(|e| tiff_error(&name, e))?;
            let DecodingResult::U8(bytes) = &self.scratch else {
                return Err(FormatError::Format(format!("{name} decoded to other samples")));
            };
            let x0 = across * self.chunk.0;
            let cols = self.chunk.0.min(width - x0);
            for r in 0..rows {
                let src = bytes
                    .get(r * stride..r * stride + cols * self.channels)
                    .ok_or_else(|| FormatError::Format(format!("{name} decoded short")))?;
                self.band[r * row_bytes + x0 * self.channels..][..cols * self.channels]
                    .copy_from_slice(src);
            }
        }
        self.band_index = Some(index);
        Ok(())
    }
}

impl OrthoRows for TiffOrtho {
    fn info(&self) -> &OrthoInfo {
        &self.info
    }

    fn read_next_row(&mut self, out: &mut [[u8; 3]]) -> Result<(), IoError> {
        self.next_row(out).map_err(|e| e.at(&self.info.path))
    }
}

impl TiffOrtho {
    /// [`OrthoRows::read_next_row`] before the file is named.
    fn next_row(&mut self, out: &mut [[u8; 3]]) -> Result<(), FormatError> {
        if self.next >= self.info.height {
            return Err(FormatError::Format("read past the last row".into()));
        }
        let row = self.next as usize;
        self.next += 1;
        let index = row / self.chunk.1;
        if self.band_index != Some(index) {
            self.decode_band(index)?;
        }
        let row_bytes = self.info.width as usize * self.channels;
        let local = row - index * self.chunk.1;
        to_rgb(&self.band[local * row_bytes..][..row_bytes], self.channels, out);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;
    use crate::{write_png_rgb8, write_rgb_geotiff};

    fn pixels(width: u32, height: u32) -> Vec<u8> {
        (0..width * height * 3).map(|k| (k * 7 % 251) as u8).collect()
    }

    fn read_all(rows: &mut dyn OrthoRows) -> Vec<u8> {
        let (w, h) = (rows.info().width as usize, rows.info().height as usize);
        let mut row = vec![[0u8; 3]; w];
        let mut all = Vec::new();
        for _ in 0..h {
            rows.read_next_row(&mut row).unwrap();
            all.extend(row.iter().flatten());
        }
        assert!(rows.read_next_row(&mut row).is_err(), "a row past the last");
        all
    }

    #[test]
    fn png_and_geotiff_orthos_read_back_row_by_row() {
        let dir = TestDir::new("ortho");
        let rgb = pixels(37, 23);
        let png = dir.path().join("o.png");
        write_png_rgb8(&png, 37, 23, &rgb).unwrap();
        let mut rows = open_ortho(&png).unwrap();
        assert_eq!(rows.info().georeference, None);
        assert_eq!(read_all(rows.as_mut()), rgb);
        let tif = dir.path().join("o.tif");
        let place = Georeference::north_up_grid(1000.0, 5000.0, 0.5, 0.25);
        write_rgb_geotiff(&tif, 37, 23, &rgb, &place).unwrap();
        let mut rows = open_ortho(&tif).unwrap();
        assert_eq!(rows.info().georeference.as_ref().unwrap().geotransform, place.geotransform);
        assert_eq!(read_all(rows.as_mut()), rgb);
    }

    #[test]
    fn a_tiled_geotiff_reads_back_with_its_edge_tiles() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ortho_tiled_deflate.tif");
        let mut rows = open_ortho(&path).unwrap();
        let geotransform = rows.info().georeference.as_ref().unwrap().geotransform;
        assert_eq!(geotransform, [1000.0, 0.5, 0.0, 5000.0, 0.0, -0.25]);
        let want: Vec<u8> = (0..37 * 23 * 3).map(|k| (k * 7 % 251) as u8).collect();
        assert_eq!(read_all(rows.as_mut()), want);
    }

    #[test]
    fn other_files_are_refused() {
        let dir = TestDir::new("ortho-refused");
        let npy = dir.path().join("o.npy");
        std::fs::write(&npy, b"x").unwrap();
        assert!(matches!(open_ortho(&npy), Err(IoError::Unsupported { .. })));
        let png = dir.path().join("o.png");
        std::fs::write(&png, b"not a png").unwrap();
        assert!(matches!(open_ortho(&png), Err(IoError::Format { .. })));
        let tif = dir.path().join("h.tif");
        let field =
            relief_core::HeightField::new(2, 2, vec![0.0; 4], relief_core::GridGeometry::unit())
                .unwrap();
        crate::write_geotiff(&tif, &field).unwrap();
        let err = open_ortho(&tif).err().unwrap();
        assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
    }
}
