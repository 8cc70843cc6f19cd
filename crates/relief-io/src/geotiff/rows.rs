//! A GeoTIFF read as rows: only the strips or tiles that cover the rows asked for are decoded,
//! one row of them at a time, the last kept for the next request.

use crate::format_error::FormatError;
use crate::georef::geokeys::ModelGrid;
use crate::geotiff::read::{Decoding, GeoTiffImage};
use crate::input_file::open_input;
use crate::raster::mark_row_voids;
use crate::rows::row_source::check_request;
use crate::{IoError, RasterInfo, ReadOptions, RowSource};
use rayon::prelude::*;
use relief_core::GridGeometry;
use std::fs::File;
use std::io::BufReader;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

/// The rows of a single-band GeoTIFF, decoded a row of strips or tiles at a time.
///
/// Holds one decoded row of chunks (a strip, or a row of tiles: `chunk height x width` f32
/// samples) and one stored chunk, whatever the raster's size. Deflate and ZSTD chunks are
/// decoded in parallel (rayon), every chunk a request needs at once: such a request holds
/// about twice its own size while it is read. Samples, geometry, info and
/// voids are those [`read_geotiff`](crate::read_geotiff) gives.
pub(crate) struct GeoTiffRows {
    image: GeoTiffImage<BufReader<File>>,
    /// The file, which errors name.
    path: PathBuf,
    /// Which row of chunks `decoded` holds.
    cached: Option<usize>,
    /// The decoded row of chunks, file rows in file order.
    decoded: Vec<f32>,
}

impl GeoTiffRows {
    /// Opens the GeoTIFF at `path`: reads and checks its tags, decodes nothing.
    ///
    /// Errors: those of [`read_geotiff`](crate::read_geotiff), except that the memory budget
    /// needs to hold only one row of chunks and one stored chunk.
    pub(crate) fn open(path: &Path, options: &ReadOptions) -> Result<Self, IoError> {
        let (file, _) = open_input(path)?;
        let reader = BufReader::new(file);
        let image = GeoTiffImage::open_for(reader, options, false, Decoding::ChunkRows)
            .map_err(|e| e.at(path))?;
        Ok(GeoTiffRows { image, path: path.to_path_buf(), cached: None, decoded: Vec::new() })
    }

    /// The grid in the file's model coordinates; `None` without a georeference.
    pub(crate) fn model(&self) -> Option<ModelGrid> {
        self.image.placement.model
    }

    /// The file's path.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }
}

impl GeoTiffRows {
    /// Decodes the rows of chunks `chunk_rows` but the one cached, their chunks in parallel
    /// (their stored bytes read one after the other first); returns each row of chunks, in
    /// file order, with its index.
    fn decode_in_parallel(
        &mut self,
        chunk_rows: RangeInclusive<usize>,
    ) -> Result<Vec<(usize, Vec<f32>)>, FormatError> {
        let across = self.image.chunks.across;
        let wanted: Vec<usize> = chunk_rows.filter(|&k| Some(k) != self.cached).collect();
        let mut stored = Vec::with_capacity(wanted.len() * across);
        for &chunk_row in &wanted {
            for index in chunk_row * across..(chunk_row + 1) * across {
                let mut bytes = Vec::new();
                self.image.read_stored(index, &mut bytes)?;
                stored.push((index, bytes));
            }
        }
        let image = &self.image;
        let chunks: Vec<Result<Vec<f32>, FormatError>> = stored
            .par_iter()
            .map_init(
                || (image.stored_decoder(), Vec::new()),
                |(decoder, buffer), (index, bytes)| match decoder {
                    Some(decoder) => image.unpack_stored(*index, bytes, decoder, buffer),
                    None => Err(FormatError::Unsupported("chunks decoded in parallel".into())),
                },
            )
            .collect();
        let (width, chunk_height) = (image.width, image.chunks.chunk_height);
        let mut chunks = chunks.into_iter();
        let mut bands = Vec::with_capacity(wanted.len());
        for chunk_row in wanted {
            let rows = chunk_height.min(image.height - chunk_row * chunk_height);
            let mut band = vec![0f32; rows * width];
            for index in chunk_row * across..(chunk_row + 1) * across {
                let samples = chunks.next().expect("one result per chunk")?;
                let region = image.chunks.region(index, width);
                for (row, values) in samples.chunks_exact(region.width).enumerate() {
                    band[row * width + region.x..][..region.width].copy_from_slice(values);
                }
            }
            bands.push((chunk_row, band));
        }
        Ok(bands)
    }

    /// [`RowSource::read_rows`] of the `rows` rows from `first_row` on, once checked, before
    /// the file is named.
    fn decode_rows(
        &mut self,
        first_row: usize,
        rows: usize,
        out: &mut [f32],
    ) -> Result<(), FormatError> {
        let (width, height) = (self.image.width, self.image.height);
        let chunk_height = self.image.chunks.chunk_height;
        let north_up = self.image.placement.north_up;
        let file_row = |row: usize| if north_up { height - 1 - row } else { row };
        let mut decoded = if self.image.decodes_stored() {
            let (a, b) = (file_row(first_row), file_row(first_row + rows - 1));
            self.decode_in_parallel(a.min(b) / chunk_height..=a.max(b) / chunk_height)?
        } else {
            Vec::new()
        };
        for (row, values) in (first_row..).zip(out.chunks_exact_mut(width)) {
            let file_row = file_row(row);
            let chunk_row = file_row / chunk_height;
            if self.cached != Some(chunk_row) {
                self.cached = None;
                match decoded.iter().position(|(k, _)| *k == chunk_row) {
                    Some(at) => self.decoded = decoded.swap_remove(at).1,
                    None => {
                        self.image.decode_chunk_row(chunk_row, &mut self.decoded)?;
                    }
                }
                self.cached = Some(chunk_row);
            }
            let at = (file_row - chunk_row * chunk_height) * width;
            values.copy_from_slice(&self.decoded[at..at + width]);
            mark_row_voids(values, file_row, self.image.info.nodata)?;
        }
        Ok(())
    }
}

impl RowSource for GeoTiffRows {
    fn width(&self) -> usize {
        self.image.width
    }
    fn height(&self) -> usize {
        self.image.height
    }
    fn geometry(&self) -> GridGeometry {
        self.image.placement.geometry
    }
    fn info(&self) -> &RasterInfo {
        &self.image.info
    }
    fn read_rows(&mut self, first_row: usize, out: &mut [f32]) -> Result<(), IoError> {
        let (width, height) = (self.image.width, self.image.height);
        let rows = check_request(&self.path, (width, height), first_row, out.len())?;
        if rows == 0 {
            return Ok(());
        }
        self.decode_rows(first_row, rows, out).map_err(|e| e.at(&self.path))
    }
    fn release_cache(&mut self) {
        self.cached = None;
        self.decoded = Vec::new();
    }
}
