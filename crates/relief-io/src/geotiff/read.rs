//! Reading a single-band GeoTIFF as a [`Raster`]: the `tiff` crate decodes strips and tiles
//! (compression, predictors, byte order); placement, nodata and row order are read here.

use crate::format_error::FormatError;
use crate::georef::geokeys::Placement;
use crate::geotiff::chunks::ChunkGrid;
use crate::geotiff::stored_chunk::{Predictor, StoredChunkDecoder, StoredCodec, COMPRESSION_ZSTD};
use crate::geotiff::tags::{check_layout, read_nodata, read_placement, tag_error, tiff_error};
use crate::input_file::open_input;
use crate::raster::mark_voids;
use crate::sample_type::{SampleOrder, SampleType};
use crate::{Format, Georeference, IoError, Raster, RasterInfo, ReadOptions};
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;
use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::tags::{ByteOrder, Tag};
use tiff::TiffError;

/// Reads the first image of the GeoTIFF at `path` as a [`Raster`].
///
/// The image must have one sample per pixel of type int8, uint8, int16, uint16, int32,
/// uint32, int64, uint64, float32 or float64, in strips or tiles, uncompressed or compressed
/// with LZW, Deflate, ZSTD or PackBits, with or without the horizontal or floating-point
/// predictor.
/// It is decoded one strip or tile at a time into the f32 samples, so reading needs the
/// samples plus one decoded strip or tile; larger rasters than `options.max_memory` allows are
/// refused before anything is allocated.
///
/// Placement, from ModelPixelScale + ModelTiepoint or a ModelTransformation without rotation
/// (PixelIsPoint rasters are shifted by half a pixel so sample centres land right):
/// - projected rasters keep their coordinates, taken as metres (feet are converted when
///   ProjLinearUnitsGeoKey says so); the origin is the raster's south-west corner;
/// - geographic rasters (GTModelTypeGeoKey 2, degrees) are converted to metres at the latitude
///   φ of the raster's centre, with `(m_lon, m_lat)` =
///   [`metres_per_degree`](crate::metres_per_degree)`(φ)`: spacing
///   `(dlon * m_lon, dlat * m_lat)` and origin `(west_lon * m_lon, south_lat * m_lat)`, a local
///   equirectangular frame that is exact in spacing at φ; [`RasterInfo::from_degrees`] keeps
///   the degrees;
/// - without a georeference the spacing is 1 and the origin 0, and
///   [`RasterInfo::georeferenced`] is false.
///
/// Row 0 of the result is the southernmost row: north-up files (the usual kind, and any TIFF
/// without a georeference, whose first row is its top) are flipped, south-up ones (negative
/// ModelPixelScale y, or a transformation whose y grows with the row) are not. Samples equal
/// to GDAL_NODATA become NaN voids; GDAL's sparse strips and tiles (no bytes) are nodata.
/// [`RasterInfo::georeference`] keeps the georeferencing tags as stored (model tags, GeoKey
/// directory, its double and ASCII parameters) and the geotransform GDAL derives from them.
///
/// Errors: [`IoError::Io`] when the file cannot be read; [`IoError::Format`] for a file that is
/// not a TIFF, is truncated, or whose header disagrees with itself or the file's length;
/// [`IoError::Unsupported`] for several bands, other sample types, other compressions, a
/// rotated or sheared georeference, a geocentric model; [`IoError::Limits`] for a raster over
/// the memory budget; [`IoError::InvalidData`] for a NaN or infinite sample that is not the
/// nodata value, naming its column and row (row 0 = the file's first row).
pub fn read_geotiff(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let (file, _) = open_input(path)?;
    read_geotiff_from(BufReader::new(file), options).map_err(|e| e.at(path))
}

/// [`read_geotiff`] from any seekable reader (a file, or bytes in memory when fuzzing), before
/// the file is named.
pub(crate) fn read_geotiff_from<R: Read + Seek>(
    reader: R,
    options: &ReadOptions,
) -> Result<Raster, FormatError> {
    let mut image = GeoTiffImage::open(reader, options, false)?;
    let samples = image.decode_band(0)?;
    let GeoTiffImage { width, height, placement, info, .. } = image;
    Ok(Raster { width, height, samples, geometry: placement.geometry, info })
}

/// How much of an image is decoded at once, which sets the memory it must fit in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Decoding {
    /// Every band whole: the budget holds all samples and one stored chunk.
    Whole,
    /// One row of chunks at a time (see [`GeoTiffImage::decode_chunk_row`]): the budget holds
    /// that row of chunks as f32 and one stored chunk, whatever the raster's size.
    ChunkRows,
}

/// The first image of a GeoTIFF, its layout and georeference read and checked, its samples
/// not yet decoded.
pub(crate) struct GeoTiffImage<R: Read + Seek> {
    pub(crate) decoder: Decoder<R>,
    /// Columns.
    pub(crate) width: usize,
    /// Rows.
    pub(crate) height: usize,
    /// Bands (samples per pixel), each in its own planes when several.
    pub(crate) bands: usize,
    sample_type: SampleType,
    compression: u16,
    /// The predictor (Predictor tag) stored chunks were encoded with; `None` for one relief
    /// does not undo itself (the `tiff` crate decides).
    predictor: Option<Predictor>,
    /// Whether the file is big-endian.
    big_endian: bool,
    pub(crate) chunks: ChunkGrid,
    /// Where the raster lies.
    pub(crate) placement: Placement,
    /// What the file says about itself.
    pub(crate) info: RasterInfo,
    /// Buffers reused from one chunk to the next.
    scratch: ChunkScratch,
}

/// The buffers of chunk decoding, kept from one chunk to the next.
struct ChunkScratch {
    /// Decoded bytes of one chunk.
    buffer: Vec<u8>,
    /// A chunk cut by the raster's east edge, decoded with its padding.
    padded: DecodingResult,
    /// The stored bytes of a ZSTD chunk.
    compressed: Vec<u8>,
    /// The decoder of ZSTD-compressed images' chunks (the `tiff` crate decodes the others).
    zstd: Option<StoredChunkDecoder>,
}

impl ChunkScratch {
    /// No buffers and no ZSTD decoder.
    fn empty() -> Self {
        ChunkScratch {
            buffer: Vec::new(),
            padded: DecodingResult::U8(Vec::new()),
            compressed: Vec::new(),
            zstd: None,
        }
    }
}

impl<R: Read + Seek> GeoTiffImage<R> {
    /// Reads and checks the first image's tags. A single band unless `several_bands`, then
    /// any number of bands stored in separate planes (PlanarConfiguration 2); the memory budget
    /// must hold every band's samples and one stored chunk.
    pub(crate) fn open(
        reader: R,
        options: &ReadOptions,
        several_bands: bool,
    ) -> Result<Self, FormatError> {
        Self::open_for(reader, options, several_bands, Decoding::Whole)
    }

    /// [`GeoTiffImage::open`] for `decoding`, which says what the memory budget must hold.
    pub(crate) fn open_for(
        mut reader: R,
        options: &ReadOptions,
        several_bands: bool,
        decoding: Decoding,
    ) -> Result<Self, FormatError> {
        let file_len = check_magic(&mut reader)?;
        let mut decoder =
            Decoder::new(reader).map_err(|e| tiff_error("", e))?.with_limits(limits(options));
        let (width, height) = decoder.dimensions().map_err(|e| tiff_error("", e))?;
        match decoding {
            Decoding::Whole => options.check_samples(width.into(), height.into())?,
            // Any size: only a row of chunks is held (checked below).
            Decoding::ChunkRows => ReadOptions { max_memory: u64::MAX, ..options.clone() }
                .check_samples(width.into(), height.into())?,
        }
        // check_size guarantees that width * height fits in usize.
        let (width, height) = (width as usize, height as usize);
        let (sample_type, compression, bands) = check_layout(&mut decoder, several_bands)?;
        let nodata = read_nodata(&mut decoder)?;
        let (placement, tags) = read_placement(&mut decoder, width, height)?;
        let layout = (sample_type, compression, bands);
        let chunks = ChunkGrid::read(&mut decoder, file_len, layout, width, height)?;
        let held = match decoding {
            Decoding::Whole => (width as u64 * height as u64).saturating_mul(bands as u64),
            Decoding::ChunkRows => width as u64 * chunks.chunk_height.min(height) as u64,
        };
        let mut needed = held.saturating_mul(4).saturating_add(chunks.stored_bytes);
        if compression == COMPRESSION_ZSTD {
            // The stored bytes of the largest chunk are read whole before decompression.
            needed = needed.saturating_add(chunks.byte_counts.iter().copied().max().unwrap_or(0));
        }
        if needed > options.max_memory {
            return Err(FormatError::Limits {
                width: width as u64,
                height: height as u64,
                needed,
                limit: options.max_memory,
            });
        }
        let predictor = decoder
            .find_tag_unsigned::<u16>(Tag::Predictor)
            .map_err(tag_error("Predictor"))?
            .unwrap_or(1);
        let unknown = || FormatError::Unsupported(format!("predictor {predictor}"));
        let predictor = Predictor::from_tag(predictor);
        let big_endian = decoder.byte_order() == ByteOrder::BigEndian;
        let zstd = if compression == COMPRESSION_ZSTD {
            let predictor = predictor.ok_or_else(unknown)?;
            Some(StoredChunkDecoder::new(
                StoredCodec::Zstd,
                predictor,
                sample_type.size(),
                big_endian,
            ))
        } else {
            None
        };
        let georeference = Georeference::from_geotiff_tags(tags);
        let height_unit = georeference.as_ref().map(Georeference::height_unit).unwrap_or_default();
        let mut placement = placement;
        placement.geometry.z_scale = height_unit.unit.metres();
        let info = RasterInfo {
            format: Format::GeoTiff,
            sample_type: sample_type.name().to_string(),
            georeferenced: placement.georeferenced,
            from_degrees: placement.from_degrees,
            nodata,
            georeference,
            height_unit,
        };
        let scratch = ChunkScratch {
            buffer: Vec::new(),
            padded: DecodingResult::U8(Vec::new()),
            compressed: Vec::new(),
            zstd,
        };
        Ok(GeoTiffImage {
            decoder,
            width,
            height,
            bands,
            sample_type,
            compression,
            predictor,
            big_endian,
            chunks,
            placement,
            info,
            scratch,
        })
    }

    /// The samples of band `band` (< bands): row 0 south, voids NaN.
    pub(crate) fn decode_band(&mut self, band: usize) -> Result<Vec<f32>, FormatError> {
        let width = self.width;
        let mut samples = vec![0f32; width * self.height];
        for index in 0..self.chunks.count {
            self.decode_chunk(band * self.chunks.count + index, &mut samples, 0)?;
        }
        if self.placement.north_up {
            flip_rows(&mut samples, width);
        }
        let north_up = self.placement.north_up;
        mark_voids(&mut samples, width, self.info.nodata, north_up)?;
        Ok(samples)
    }

    /// Decodes row `chunk_row` of the first band's chunks (a strip, or a row of tiles) into
    /// `out`, the file rows from `chunk_row * chunk_height` on, in the file's order and
    /// values (neither flipped nor voids marked); returns how many rows it holds.
    pub(crate) fn decode_chunk_row(
        &mut self,
        chunk_row: usize,
        out: &mut Vec<f32>,
    ) -> Result<usize, FormatError> {
        let first_row = chunk_row * self.chunks.chunk_height;
        let rows = self.chunks.chunk_height.min(self.height - first_row);
        out.clear();
        out.resize(rows * self.width, 0.0);
        let across = self.chunks.across;
        for index in chunk_row * across..(chunk_row + 1) * across {
            self.decode_chunk(index, out, first_row)?;
        }
        Ok(rows)
    }

    /// Decodes chunk `index` (counted over every plane) into `out`, a grid of the raster's
    /// width whose row 0 is file row `first_row`; sparse chunks become the nodata value (0
    /// without one).
    fn decode_chunk(
        &mut self,
        index: usize,
        out: &mut [f32],
        first_row: usize,
    ) -> Result<(), FormatError> {
        let (width, sample_type) = (self.width, self.sample_type);
        let chunks = &self.chunks;
        let region = chunks.region(index % chunks.count, width);
        let at = |row: usize| (region.y - first_row + row) * width + region.x;
        if chunks.sparse[index] {
            // GDAL's sparse files omit blocks that hold nothing but nodata (or zeros).
            let fill = self.info.nodata.map_or(0.0, |v| v as f32);
            for row in 0..region.height {
                out[at(row)..][..region.width].fill(fill);
            }
            return Ok(());
        }
        if self.scratch.zstd.is_some() {
            let mut scratch = std::mem::replace(&mut self.scratch, ChunkScratch::empty());
            let decoded = self.read_stored(index, &mut scratch.compressed).and_then(|()| {
                let decoder = scratch.zstd.as_mut().expect("a ZSTD decoder");
                self.unpack_stored(index, &scratch.compressed, decoder, &mut scratch.buffer)
            });
            self.scratch = scratch;
            let decoded = decoded?;
            for (row, values) in decoded.chunks_exact(region.width).enumerate() {
                out[at(row)..][..region.width].copy_from_slice(values);
            }
            return Ok(());
        }
        let row_bytes = region.width * sample_type.size();
        let scratch = &mut self.scratch;
        let padded_view;
        let index_u32 = u32::try_from(index).map_err(|_| {
            FormatError::Unsupported(format!("{} {index} (index beyond u32)", chunks.name()))
        })?;
        let chunk_error = |e| tiff_error(&format!("{} {index}", chunks.name()), e);
        // tiff 0.11.3 finds a tile's padding from its index counted over every plane, so it
        // decodes the bottom tiles of the planes after the first whole, padding rows
        // included: those, like the tiles cut by the east edge, take the padded path.
        let later_plane_bottom_tile =
            chunks.tiled() && index >= chunks.count && region.height < chunks.chunk_height;
        let (bytes, stride): (&[u8], usize) =
            if region.width == chunks.chunk_width && !later_plane_bottom_tile {
                scratch.buffer.resize(row_bytes * region.height, 0);
                let bytes = &mut scratch.buffer[..row_bytes * region.height];
                self.decoder.read_chunk_bytes(index_u32, bytes).map_err(chunk_error)?;
                (bytes, row_bytes)
            } else {
                // A tile cut by the raster's east edge. Decoded row by row, tiff 0.11.3 fails
                // on some valid LZW tiles ("no lzw end code found"): decode whole stored rows
                // instead, padding included (the crate takes this output width in bytes).
                let stride = chunks.chunk_width * sample_type.size();
                self.decoder
                    .read_chunk_to_buffer(&mut scratch.padded, index_u32, stride)
                    .map_err(chunk_error)?;
                padded_view = scratch.padded.as_buffer(0);
                (padded_view.as_bytes(), stride)
            };
        for row in 0..region.height {
            let raw = bytes.get(row * stride..row * stride + row_bytes).ok_or_else(|| {
                FormatError::Format(format!("{} {index} decoded short", chunks.name()))
            })?;
            convert(raw, sample_type, &mut out[at(row)..][..region.width]);
        }
        Ok(())
    }

    /// A decoder of the image's stored chunks, for decoding them apart from this image (in
    /// parallel, see [`GeoTiffImage::unpack_stored`]); `None` unless the chunks are
    /// Deflate- or ZSTD-compressed with a predictor relief undoes itself.
    pub(crate) fn stored_decoder(&self) -> Option<StoredChunkDecoder> {
        let codec = StoredCodec::of(self.compression)?;
        let size = self.sample_type.size();
        Some(StoredChunkDecoder::new(codec, self.predictor?, size, self.big_endian))
    }

    /// Whether [`GeoTiffImage::stored_decoder`] gives a decoder.
    pub(crate) fn decodes_stored(&self) -> bool {
        StoredCodec::of(self.compression).is_some() && self.predictor.is_some()
    }

    /// Reads the stored bytes of chunk `index` into `out` (nothing for a sparse chunk).
    pub(crate) fn read_stored(
        &mut self,
        index: usize,
        out: &mut Vec<u8>,
    ) -> Result<(), FormatError> {
        let chunk = || format!("{} {index}", self.chunks.name());
        // ChunkGrid::read checked that the bytes lie within the file.
        let (offset, count) = (self.chunks.offsets[index], self.chunks.byte_counts[index]);
        let count = usize::try_from(count)
            .map_err(|_| FormatError::Format(format!("{}: {count} bytes", chunk())))?;
        out.resize(count, 0);
        if count == 0 {
            return Ok(());
        }
        let reader = self.decoder.inner();
        reader
            .seek(SeekFrom::Start(offset))
            .and_then(|_| reader.read_exact(out))
            .map_err(|e| tiff_error(&chunk(), TiffError::IoError(e)))
    }

    /// The samples of chunk `index` (its region of the raster, row-major, file order, neither
    /// flipped nor voids marked) from its `stored` bytes (see [`GeoTiffImage::read_stored`]);
    /// a sparse chunk is the nodata value (0 without one). `buffer` holds the decompressed
    /// bytes. Needs only `&self`, so that chunks can be decoded in parallel.
    pub(crate) fn unpack_stored(
        &self,
        index: usize,
        stored: &[u8],
        decoder: &mut StoredChunkDecoder,
        buffer: &mut Vec<u8>,
    ) -> Result<Vec<f32>, FormatError> {
        let (chunks, sample_type) = (&self.chunks, self.sample_type);
        let region = chunks.region(index % chunks.count, self.width);
        if chunks.sparse[index] {
            let fill = self.info.nodata.map_or(0.0, |v| v as f32);
            return Ok(vec![fill; region.width * region.height]);
        }
        let chunk = || format!("{} {index}", chunks.name());
        let stride = chunks.chunk_width * sample_type.size();
        // stored_bytes (one whole stored chunk) was counted in the memory budget.
        buffer.resize(stride * chunks.chunk_height, 0);
        let decoded = decoder
            .decode(stored, buffer, stride)
            .map_err(|reason| FormatError::Format(format!("{}: {reason}", chunk())))?;
        let row_bytes = region.width * sample_type.size();
        let needed = (region.height - 1) * stride + row_bytes;
        if decoded < needed {
            return Err(FormatError::Format(format!(
                "{}: {} data decodes to {decoded} bytes; its {} x {} samples need {needed}",
                chunk(),
                decoder.codec_name(),
                region.width,
                region.height,
            )));
        }
        let mut samples = vec![0f32; region.width * region.height];
        for (row, values) in samples.chunks_exact_mut(region.width).enumerate() {
            convert(&buffer[row * stride..][..row_bytes], sample_type, values);
        }
        Ok(samples)
    }
}

/// Checks the byte-order mark and version of a TIFF or BigTIFF header; returns the length of
/// the source and leaves it at its start.
fn check_magic<R: Read + Seek>(reader: &mut R) -> Result<u64, FormatError> {
    let io = FormatError::Io;
    let len = reader.seek(SeekFrom::End(0)).map_err(io)?;
    reader.seek(SeekFrom::Start(0)).map_err(io)?;
    if len < 8 {
        return Err(FormatError::Format(format!(
            "{len} bytes is too short for a TIFF header (8 bytes)"
        )));
    }
    let mut magic = [0u8; 4];
    reader.read_exact(&mut magic).map_err(io)?;
    reader.seek(SeekFrom::Start(0)).map_err(io)?;
    match magic {
        [b'I', b'I', 42 | 43, 0] | [b'M', b'M', 0, 42 | 43] => Ok(len),
        _ => Err(FormatError::Format(format!(
            "not a TIFF file: starts with {magic:02x?}, not \"II*\\0\" or \"MM\\0*\""
        ))),
    }
}

/// The `tiff` crate's limits from the memory budget.
fn limits(options: &ReadOptions) -> Limits {
    let budget = usize::try_from(options.max_memory).unwrap_or(usize::MAX);
    let mut limits = Limits::default();
    limits.decoding_buffer_size = budget;
    limits.intermediate_buffer_size = budget;
    limits.ifd_value_size = budget;
    limits
}

/// Converts native-endian samples (as the decoder leaves them) to f32.
fn convert(bytes: &[u8], sample_type: SampleType, out: &mut [f32]) {
    sample_type.decode(bytes, SampleOrder::Native, out)
}

/// Reverses the order of the rows of a row-major grid in place.
fn flip_rows(samples: &mut [f32], width: usize) {
    let height = samples.len() / width;
    for row in 0..height / 2 {
        let (top, bottom) = samples.split_at_mut((height - 1 - row) * width);
        top[row * width..][..width].swap_with_slice(&mut bottom[..width]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    const JACKSBORO: &[u8] = include_bytes!("../../tests/fixtures/jacksboro_fault_dem.tif");

    fn read(bytes: &[u8]) -> Result<Raster, FormatError> {
        read_geotiff_from(Cursor::new(bytes), &ReadOptions::default())
    }

    #[test]
    fn reads_from_memory() {
        let raster = read(JACKSBORO).unwrap();
        assert_eq!((raster.width, raster.height), (403, 344));
        assert_eq!(raster.value_range(), Some((236.0, 1076.0)));
    }

    #[test]
    fn flips_rows_in_place() {
        for height in 1..6 {
            let mut grid: Vec<f32> = (0..3 * height).map(|v| v as f32).collect();
            flip_rows(&mut grid, 3);
            for row in 0..height {
                let want: Vec<f32> = (0..3).map(|c| (c + 3 * (height - 1 - row)) as f32).collect();
                assert_eq!(grid[row * 3..][..3], want[..], "height {height}");
            }
        }
    }

    #[test]
    fn corruptions_are_refused_or_read_as_the_fixture_or_a_smaller_raster() {
        // Every single-byte change in the header and the first IFD, to three values.
        let mut header = Outcomes::default();
        for at in 0..448 {
            for value in [0x00, 0xff, JACKSBORO[at].wrapping_add(1)] {
                let mut bad = JACKSBORO.to_vec();
                bad[at] = value;
                header.count(read(&bad));
            }
        }
        // Random changes anywhere, a few bytes at a time.
        let mut anywhere = Outcomes::default();
        for bad in crate::test_corruption::corrupted_copies(JACKSBORO, 300, 4) {
            anywhere.count(read(&bad));
        }
        // No checksum guards the header: a changed tag that does not matter (a description,
        // the nodata string, a georeference) reads as the fixture, and an ImageWidth made
        // smaller reads the first samples of each row from strips that hold more. But the tags
        // that say how samples are stored (bits, sample format, compression) are refused
        // when changed: a reader accepting one would reinterpret the samples.
        assert_eq!(header.other_samples, 0, "{header:?}");
        assert!(header.other_size.len() <= 10, "{header:?}");
        assert!(header.other_size.iter().all(|&(w, h)| w * h < 403 * 344), "{header:?}");
        assert!(header.refused >= 300, "{header:?}");
        // The strips are zlib streams: their Adler-32 sees a changed byte, so nearly every
        // copy changed anywhere is refused.
        assert!(anywhere.refused >= 290, "{anywhere:?}");
    }

    /// How corrupted copies of the fixture fared.
    #[derive(Debug, Default)]
    struct Outcomes {
        refused: usize,
        /// Read with the fixture's size and samples.
        same: usize,
        /// Read with the fixture's size, other samples.
        other_samples: usize,
        /// Read with another size.
        other_size: Vec<(usize, usize)>,
    }

    impl Outcomes {
        /// Counts `result`; a raster read must hold as many samples as its size says.
        fn count(&mut self, result: Result<Raster, FormatError>) {
            let Ok(raster) = result else {
                self.refused += 1;
                return;
            };
            assert_eq!(raster.samples.len(), raster.width * raster.height);
            if (raster.width, raster.height) != (403, 344) {
                self.other_size.push((raster.width, raster.height));
            } else if raster.samples.iter().zip(&*FIXTURE).all(|(a, b)| a.to_bits() == b.to_bits())
            {
                self.same += 1;
            } else {
                self.other_samples += 1;
            }
        }
    }

    /// The fixture's samples.
    static FIXTURE: std::sync::LazyLock<Vec<f32>> =
        std::sync::LazyLock::new(|| read(JACKSBORO).unwrap().samples);

    #[test]
    fn samples_convert_to_f32() {
        let mut out = [0f32; 2];
        let bytes: Vec<u8> = [-2i16, 300].iter().flat_map(|v| v.to_ne_bytes()).collect();
        convert(&bytes, SampleType::I16, &mut out);
        assert_eq!(out, [-2.0, 300.0]);
    }
}
