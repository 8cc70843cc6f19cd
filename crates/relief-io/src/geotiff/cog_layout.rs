//! The bytes before the image data of a cloud-optimised GeoTIFF, laid out as GDAL's COG driver
//! lays them out: the TIFF (or BigTIFF) header, GDAL's ghost area of structural metadata, the
//! full-resolution directory and then the overviews' (largest first), each followed by its
//! tags' values, then every tile offset and byte count array; after them the tiles, from the
//! smallest overview to the full resolution, each level band by band, row by row, each tile
//! between GDAL's leader (its size) and trailer (its last 4 bytes again).

use crate::geotiff::cog_tiles::LevelTiles;
use crate::geotiff::gdal_metadata::{band_descriptions_xml, GDAL_METADATA_TAG};
use crate::geotiff::tiff_directory::{encode, Entry, TagValue, TiffFlavour};
use crate::geotiff::write_tags::{georeference_tags, GeoTagValues};
use crate::Georeference;
use std::io::Write;
use tiff::tags::Tag;

/// GDAL's ghost area after the header: what an optimised reader may rely on, as GDAL's COG
/// driver writes it (the final space included). With the block leader and trailer GDAL's
/// reader takes the file for a COG (IMAGE_STRUCTURE LAYOUT=COG) and reads a run of tiles in
/// one request, checking each tile's leader and trailer against its TileByteCounts.
const GHOST_ITEMS: &str = "LAYOUT=IFDS_BEFORE_DATA\nBLOCK_ORDER=ROW_MAJOR\n\
                           BLOCK_LEADER=SIZE_AS_UINT4\nBLOCK_TRAILER=LAST_4_BYTES_REPEATED\n\
                           KNOWN_INCOMPATIBLE_EDITION=NO\n ";

/// Bytes around each tile's data: its leader (4) and trailer (4).
const LEADER_AND_TRAILER: u64 = 8;

/// The ghost area: `GDAL_STRUCTURAL_METADATA_SIZE=<6 digits> bytes\n` (43 bytes), the digits
/// counting the items after that line.
fn ghost_area() -> String {
    format!("GDAL_STRUCTURAL_METADATA_SIZE={:06} bytes\n{GHOST_ITEMS}", GHOST_ITEMS.len())
}

/// What the full-resolution directory says besides the layout.
pub(crate) struct CogMetadata<'a> {
    /// The bands' descriptions (GDAL_METADATA).
    pub(crate) band_names: &'a [String],
    /// Its georeference tags, unchanged (none when `None`).
    pub(crate) georeference: Option<&'a Georeference>,
    /// The GDAL_NODATA text, on every level (none when `None`).
    pub(crate) nodata_text: Option<String>,
}

/// Where everything of a cloud-optimised GeoTIFF lies.
pub(crate) struct CogLayout {
    /// The bytes before the first tile: header, ghost area, directories and their values.
    pub(crate) header: Vec<u8>,
    /// The file's size.
    pub(crate) file_len: u64,
}

/// Whether a file of `file_len` bytes must be a BigTIFF: a classic TIFF's offsets are 32-bit.
pub(crate) fn needs_big_tiff(file_len: u64) -> bool {
    file_len > u64::from(u32::MAX)
}

/// Lays out the file of `levels` (the full resolution first, then the overviews, largest
/// first), their tiles as large as their byte counts say: a classic TIFF when it fits in
/// 4 GiB and `force_big` is false, else a BigTIFF. Fails, saying why, only on directories a
/// TIFF cannot hold (see [`encode`]).
pub(crate) fn lay_out(
    levels: &[&LevelTiles],
    metadata: &CogMetadata<'_>,
    force_big: bool,
) -> Result<CogLayout, String> {
    let data_len: u64 =
        levels.iter().flat_map(|l| l.counts()).map(|&c| u64::from(c) + LEADER_AND_TRAILER).sum();
    let classic = TiffFlavour { big: false };
    let big = force_big || {
        // Offsets are unknown yet, but the directories' size does not depend on them.
        let probe =
            encode(classic, ghost_area().as_bytes(), &directories(levels, metadata, classic, 0))
                .map(|e| e.bytes.len() as u64);
        probe.map_or(true, |header| needs_big_tiff(header + data_len))
    };
    let flavour = TiffFlavour { big };
    let ghost = ghost_area();
    let header_len = encode(flavour, ghost.as_bytes(), &directories(levels, metadata, flavour, 0))?
        .bytes
        .len() as u64;
    let header =
        encode(flavour, ghost.as_bytes(), &directories(levels, metadata, flavour, header_len))?;
    debug_assert_eq!(header.bytes.len() as u64, header_len);
    Ok(CogLayout { header: header.bytes, file_len: header_len + data_len })
}

/// The directories of `levels`, their tiles' data starting at `data_start` in the order of
/// [`data_order`].
fn directories(
    levels: &[&LevelTiles],
    metadata: &CogMetadata<'_>,
    flavour: TiffFlavour,
    data_start: u64,
) -> Vec<Vec<Entry>> {
    // Tile offsets: the smallest level's tiles first.
    let mut starts = vec![0u64; levels.len()];
    let mut at = data_start;
    for (k, level) in levels.iter().enumerate().rev() {
        starts[k] = at;
        at += level.counts().iter().map(|&c| u64::from(c) + LEADER_AND_TRAILER).sum::<u64>();
    }
    levels
        .iter()
        .zip(starts)
        .enumerate()
        .map(|(k, (level, start))| directory(level, k > 0, metadata, flavour, start))
        .collect()
}

/// The directory of one level whose tiles lie one after the other from `start`, in index
/// order, each between its leader and trailer; an overview (NewSubfileType 1) when `overview`, else the full resolution with the
/// band descriptions and georeference.
fn directory(
    level: &LevelTiles,
    overview: bool,
    metadata: &CogMetadata<'_>,
    flavour: TiffFlavour,
    start: u64,
) -> Vec<Entry> {
    let bands = level.bands;
    // Bands are at most u16::MAX (CogWriter::create checks), sides and tiles at most u32::MAX.
    let per_band = |value: u16| TagValue::Short(vec![value; bands]);
    let short = |value: u16| TagValue::Short(vec![value]);
    let long = |value: usize| TagValue::Long(vec![value as u32]);
    let counts = level.counts();
    let mut offsets = Vec::with_capacity(counts.len());
    let mut at = start;
    for &count in counts {
        // The data starts after the 4-byte leader.
        offsets.push(at + 4);
        at += u64::from(count) + LEADER_AND_TRAILER;
    }
    let (offsets, counts) = if flavour.big {
        (TagValue::Long8(offsets), TagValue::Long8(counts.iter().map(|&c| u64::from(c)).collect()))
    } else {
        // lay_out chose a BigTIFF for offsets past u32.
        (
            TagValue::Long(offsets.into_iter().map(|o| o as u32).collect()),
            TagValue::Long(counts.to_vec()),
        )
    };
    let mut entries = vec![
        Entry::new(Tag::ImageWidth.to_u16(), long(level.grid.width)),
        Entry::new(Tag::ImageLength.to_u16(), long(level.grid.height)),
        Entry::new(Tag::BitsPerSample.to_u16(), per_band(32)),
        // Adobe Deflate.
        Entry::new(Tag::Compression.to_u16(), short(8)),
        // BlackIsZero.
        Entry::new(Tag::PhotometricInterpretation.to_u16(), short(1)),
        Entry::new(Tag::SamplesPerPixel.to_u16(), short(bands as u16)),
        Entry::new(Tag::PlanarConfiguration.to_u16(), short(if bands > 1 { 2 } else { 1 })),
        // The floating-point predictor.
        Entry::new(Tag::Predictor.to_u16(), short(3)),
        Entry::new(Tag::TileWidth.to_u16(), long(level.grid.tile)),
        Entry::new(Tag::TileLength.to_u16(), long(level.grid.tile)),
        Entry::deferred(Tag::TileOffsets.to_u16(), offsets),
        Entry::deferred(Tag::TileByteCounts.to_u16(), counts),
        // IEEE floating point.
        Entry::new(Tag::SampleFormat.to_u16(), per_band(3)),
    ];
    if bands > 1 {
        // The bands after the first as unspecified extra samples, as GDAL writes them.
        entries.push(Entry::new(Tag::ExtraSamples.to_u16(), TagValue::Short(vec![0; bands - 1])));
    }
    if overview {
        // A reduced-resolution version of the image.
        entries.push(Entry::new(Tag::NewSubfileType.to_u16(), TagValue::Long(vec![1])));
    } else {
        if let Some(georeference) = metadata.georeference {
            for (tag, values) in georeference_tags(&georeference.geotiff) {
                let value = match values {
                    GeoTagValues::Doubles(v) => TagValue::Double(v.to_vec()),
                    GeoTagValues::Shorts(v) => TagValue::Short(v.to_vec()),
                    GeoTagValues::Ascii(v) => TagValue::ascii(v),
                };
                entries.push(Entry::new(tag.to_u16(), value));
            }
        }
        let xml = band_descriptions_xml(metadata.band_names);
        entries.push(Entry::new(GDAL_METADATA_TAG, TagValue::ascii(xml.as_bytes())));
    }
    if let Some(text) = &metadata.nodata_text {
        entries.push(Entry::new(Tag::GdalNodata.to_u16(), TagValue::ascii(text.as_bytes())));
    }
    entries
}

/// The tiles of `levels` in the order they are written: the smallest level first, each in
/// index order (band by band, row by row), as (level, index).
pub(crate) fn data_order<'a>(
    levels: &'a [&LevelTiles],
) -> impl Iterator<Item = (usize, usize)> + 'a {
    levels.iter().enumerate().rev().flat_map(|(k, level)| (0..level.len()).map(move |i| (k, i)))
}

/// Writes a tile's `stored` bytes (at least 4) as the file holds them: the leader (their
/// count, a little-endian u32), the bytes, the trailer (their last 4 bytes again).
pub(crate) fn write_tile(out: &mut impl Write, stored: &[u8]) -> std::io::Result<()> {
    let count = u32::try_from(stored.len()).map_err(std::io::Error::other)?;
    let last = stored
        .len()
        .checked_sub(4)
        .ok_or_else(|| std::io::Error::other(format!("a stored tile of {} bytes", stored.len())))?;
    out.write_all(&count.to_le_bytes())?;
    out.write_all(stored)?;
    out.write_all(&stored[last..])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geotiff::cog_tiles::TileGrid;

    /// A level whose every tile is `count` bytes.
    fn level(width: usize, height: usize, bands: usize, count: u32) -> LevelTiles {
        let mut level = LevelTiles::new(TileGrid::new(width, height, 128), bands);
        for i in 0..level.len() {
            level.set(i, 0, count);
        }
        level
    }

    #[test]
    fn the_ghost_area_says_its_size_and_puts_the_first_directory_where_gdal_expects_it() {
        let ghost = ghost_area();
        assert_eq!(ghost.find('\n'), Some(42));
        let size: usize = ghost[30..36].parse().unwrap();
        assert_eq!(ghost.len(), 43 + size);
        // The size GDAL's COG driver writes for an image without a mask.
        assert_eq!(size, 140);
        let full = level(300, 200, 2, 10);
        let names = ["a".to_string(), "b".to_string()];
        let metadata =
            CogMetadata { band_names: &names, georeference: None, nodata_text: Some("nan".into()) };
        let layout = lay_out(&[&full], &metadata, false).unwrap();
        // GDAL's validator: 8 + 43 + size, rounded up to even.
        let expected = (8 + 43 + size as u32).next_multiple_of(2);
        assert_eq!(u32::from_le_bytes(layout.header[4..8].try_into().unwrap()), expected);
        assert_eq!(&layout.header[8..8 + ghost.len()], ghost.as_bytes());
        // 12 tiles of 10 bytes, each with its leader and trailer.
        assert_eq!(layout.file_len, layout.header.len() as u64 + 12 * 18);
        assert_eq!(&layout.header[..4], b"II*\0");
    }

    #[test]
    fn a_file_past_4_gib_is_a_big_tiff() {
        let names = ["a".to_string()];
        let metadata = CogMetadata { band_names: &names, georeference: None, nodata_text: None };
        // 6 tiles: 715 827 882 bytes each just fit 2^32 with the header; one more byte does not.
        let fits = u32::MAX / 6 - 200;
        let full = level(300, 200, 1, fits);
        let layout = lay_out(&[&full], &metadata, false).unwrap();
        assert_eq!(&layout.header[..4], b"II*\0");
        assert!(layout.file_len <= u64::from(u32::MAX), "{}", layout.file_len);
        let full = level(300, 200, 1, u32::MAX / 6 - 8 + 1);
        let layout = lay_out(&[&full], &metadata, false).unwrap();
        assert_eq!(&layout.header[..4], b"II+\0");
        assert!(needs_big_tiff(layout.file_len));
        // Forced, a small file too.
        let small = level(300, 200, 1, 10);
        assert_eq!(&lay_out(&[&small], &metadata, true).unwrap().header[..4], b"II+\0");
        assert!(!needs_big_tiff(u64::from(u32::MAX)));
    }

    #[test]
    fn a_tile_is_written_between_its_size_and_its_last_4_bytes() {
        let mut out = Vec::new();
        write_tile(&mut out, b"abcdef").unwrap();
        assert_eq!(out, b"\x06\0\0\0abcdefcdef");
        assert!(write_tile(&mut out, b"abc").is_err());
    }

    #[test]
    fn data_runs_from_the_smallest_level_to_the_full_resolution() {
        let (full, half) = (level(300, 200, 2, 1), level(150, 100, 2, 1));
        let order: Vec<_> = data_order(&[&full, &half]).collect();
        assert_eq!(order[..3], [(1, 0), (1, 1), (1, 2)]);
        assert_eq!(order[4], (0, 0));
        assert_eq!(order.len(), 4 + 12);
    }
}
