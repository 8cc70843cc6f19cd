//! The strips or tiles of a GeoTIFF image: where each lies in the file and in the raster,
//! checked against the file before anything is decoded.

use crate::format_error::FormatError;
use crate::geotiff::tags::tag_error;
use crate::sample_type::SampleType;
use std::io::{Read, Seek};
use tiff::decoder::{ChunkType, Decoder};
use tiff::tags::Tag;

/// The strips or tiles of an image, checked against the file before anything is decoded.
pub(crate) struct ChunkGrid {
    kind: ChunkType,
    /// Stored chunk width: the raster's width for strips, the tile width for tiles.
    pub(crate) chunk_width: usize,
    /// Stored chunk height: rows per strip (at most the raster's height), or the tile height.
    pub(crate) chunk_height: usize,
    /// Chunks per row of chunks.
    pub(crate) across: usize,
    /// Chunks of one plane (band) of the image.
    pub(crate) count: usize,
    /// Chunks stored with no bytes (GDAL's sparse files), every plane's: filled with nodata.
    pub(crate) sparse: Vec<bool>,
    /// Where each chunk's bytes start in the file.
    pub(crate) offsets: Vec<u64>,
    /// How many bytes each chunk holds in the file.
    pub(crate) byte_counts: Vec<u64>,
    /// Bytes of the largest stored chunk once decoded, padding included.
    pub(crate) stored_bytes: u64,
    /// Rows of the raster.
    pub(crate) raster_height: usize,
}

/// The part of the raster a chunk covers, in the file's rows (row 0 first in the file).
pub(crate) struct Region {
    /// First column.
    pub(crate) x: usize,
    /// First row.
    pub(crate) y: usize,
    /// Columns.
    pub(crate) width: usize,
    /// Rows.
    pub(crate) height: usize,
}

impl ChunkGrid {
    /// Reads the chunk layout of a `width x height` image of `(sample type, compression,
    /// planes)` (each plane, a band, in `count` chunks of its own, one plane after the other)
    /// and checks every chunk's bytes lie within the `file_len`-byte file, and that
    /// uncompressed chunks hold all their samples.
    pub(crate) fn read<R: Read + Seek>(
        decoder: &mut Decoder<R>,
        file_len: u64,
        (sample_type, compression, planes): (SampleType, u16, usize),
        width: usize,
        height: usize,
    ) -> Result<ChunkGrid, FormatError> {
        let kind = decoder.get_chunk_type();
        let (chunk_width, chunk_height) = decoder.chunk_dimensions();
        let (chunk_width, chunk_height) = (chunk_width as usize, chunk_height as usize);
        let (offsets_tag, counts_tag, name) = match kind {
            ChunkType::Strip => (Tag::StripOffsets, Tag::StripByteCounts, "strip"),
            ChunkType::Tile => (Tag::TileOffsets, Tag::TileByteCounts, "tile"),
        };
        let mut u64_values = |tag: Tag, tag_name: &'static str| -> Result<Vec<u64>, FormatError> {
            let error = tag_error(tag_name);
            let value = decoder.find_tag(tag).map_err(error)?;
            value.map_or(Ok(Vec::new()), |v| v.into_u64_vec().map_err(error))
        };
        let offsets = u64_values(offsets_tag, "chunk offsets")?;
        let counts = u64_values(counts_tag, "chunk byte counts")?;
        let size = sample_type.size() as u64;
        let grid = match kind {
            ChunkType::Strip => {
                let rows = chunk_height.min(height);
                ChunkGrid {
                    kind,
                    chunk_width: width,
                    chunk_height: rows,
                    across: 1,
                    count: height.div_ceil(rows),
                    sparse: Vec::new(),
                    offsets: Vec::new(),
                    byte_counts: Vec::new(),
                    stored_bytes: (width * rows) as u64 * size,
                    raster_height: height,
                }
            }
            ChunkType::Tile => {
                let across = width.div_ceil(chunk_width);
                ChunkGrid {
                    kind,
                    chunk_width,
                    chunk_height,
                    across,
                    count: across * height.div_ceil(chunk_height),
                    sparse: Vec::new(),
                    offsets: Vec::new(),
                    byte_counts: Vec::new(),
                    stored_bytes: (chunk_width as u64)
                        .saturating_mul(chunk_height as u64)
                        .saturating_mul(size),
                    raster_height: height,
                }
            }
        };
        let all = grid.count.saturating_mul(planes);
        if offsets.len() != all || counts.len() != all {
            return Err(FormatError::Format(format!(
                "{} offsets and {} byte counts for {} {name}s",
                offsets.len(),
                counts.len(),
                all
            )));
        }
        let mut sparse = Vec::with_capacity(grid.count);
        for (index, (&offset, &count)) in offsets.iter().zip(&counts).enumerate() {
            sparse.push(count == 0);
            if count == 0 {
                continue;
            }
            if offset.checked_add(count).is_none_or(|end| end > file_len) {
                return Err(FormatError::Format(format!(
                    "truncated: {name} {index} claims bytes {offset}..{} of a {file_len}-byte \
                         file",
                    offset.saturating_add(count)
                )));
            }
            // The decoder reads whole stored rows of an uncompressed chunk.
            let rows = grid.region(index % grid.count, width).height as u64;
            let needed = (rows * grid.chunk_width as u64).saturating_mul(size);
            if compression == 1 && count < needed {
                return Err(FormatError::Format(format!(
                    "uncompressed {name} {index} holds {count} bytes; its {} x {} samples \
                         need {needed}",
                    grid.chunk_width.min(width),
                    rows
                )));
            }
        }
        Ok(ChunkGrid { sparse, offsets, byte_counts: counts, ..grid })
    }

    /// Whether the chunks are tiles (else strips).
    pub(crate) fn tiled(&self) -> bool {
        self.kind == ChunkType::Tile
    }

    /// "strip" or "tile".
    pub(crate) fn name(&self) -> &'static str {
        match self.kind {
            ChunkType::Strip => "strip",
            ChunkType::Tile => "tile",
        }
    }

    /// The region chunk `index` (< count) covers in a `width`-sample-wide raster, edge chunks
    /// cut to the raster.
    pub(crate) fn region(&self, index: usize, width: usize) -> Region {
        let x = index % self.across * self.chunk_width;
        let y = index / self.across * self.chunk_height;
        Region {
            x,
            y,
            width: self.chunk_width.min(width - x),
            height: self.chunk_height.min(self.raster_height - y),
        }
    }
}
