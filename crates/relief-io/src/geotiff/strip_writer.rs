//! Writing a float32 GeoTIFF band by band, never whole in memory: strips compressed in
//! parallel as their rows come, written by a thread of their own into a temporary file that
//! is renamed into place when the last row is in.

use crate::atomic_write::temp_path;
use crate::geotiff::float_strips::{pack_strip, rows_per_strip, FloatStrips, BIG_TIFF_FROM};
use crate::geotiff::write_tags::{encoding_error, write_geometry_tags, write_georeference};
use crate::{Georeference, IoError};
use rayon::prelude::*;
use relief_core::GridGeometry;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;
use tiff::encoder::{TiffEncoder, TiffKind, TiffKindBig, TiffKindStandard};
use tiff::tags::Tag;

/// Compressed strips waiting for the writing thread, at most.
const QUEUED_STRIPS: usize = 64;

/// A single-band float32 GeoTIFF written a band of rows at a time, first row first.
///
/// The file is the one [`write_geotiff`](crate::write_geotiff) writes for the same samples
/// and geometry, byte for byte: Deflate-compressed strips of about 256 KiB with the
/// floating-point predictor, NaN declared as nodata (GDAL_NODATA "nan"), a BigTIFF when the
/// samples reach 3 GiB (so that the file may pass 4 GiB). Strips are compressed in parallel
/// (rayon) as soon as their rows are in, and written by a thread of the writer's own, so
/// memory holds one strip, the rows of the current call and a bounded queue of compressed
/// strips, whatever the raster's size.
///
/// The file is written under a temporary name beside `path` and renamed into place by
/// [`finish`](Self::finish) once every row is in: a writer that fails, is dropped before
/// `finish` or is killed never leaves a partial file under `path` (a killed process may leave
/// the hidden temporary file `.<name>.<pid>.<n>.tmp`).
///
/// ```
/// use relief_core::GridGeometry;
/// use relief_io::geotiff::GeoTiffStripWriter;
/// let path = std::env::temp_dir().join(format!("relief-io-strips-{}.tif", std::process::id()));
/// let mut out = GeoTiffStripWriter::create(&path, 3, 2, &GridGeometry::unit())?;
/// out.write_rows(&[3.0, 4.0, 5.0])?; // the northern row
/// out.write_rows(&[0.0, 1.0, f32::NAN])?;
/// out.finish()?;
/// let raster = relief_io::geotiff::read_geotiff(&path, &relief_io::ReadOptions::default())?;
/// // Row 0 of the raster is the southern row.
/// assert_eq!(raster.samples[..2], [0.0, 1.0]);
/// assert!(raster.samples[2].is_nan());
/// assert_eq!(raster.samples[3..], [3.0, 4.0, 5.0]);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct GeoTiffStripWriter {
    path: PathBuf,
    temp: PathBuf,
    width: usize,
    height: usize,
    z_scale: f64,
    rows_per_strip: usize,
    /// Rows received so far.
    rows_written: usize,
    /// Rows of the strip being filled (fewer than a strip), scaled.
    pending: Vec<f32>,
    /// Sends compressed strips, then the order to finish, to the writing thread.
    sender: Option<SyncSender<Message>>,
    /// The writing thread: its result is the file's.
    thread: Option<JoinHandle<Result<(), IoError>>>,
}

/// What the writing thread receives.
enum Message {
    /// The stored bytes of the next strip.
    Strip(Vec<u8>),
    /// Every strip is in: write the directory and flush.
    Finish,
}

/// The tags that place the raster.
enum Placement {
    /// A north-up grid of this geometry, as [`write_geotiff`](crate::write_geotiff) places it.
    Geometry(GridGeometry),
    /// These georeferencing tags, as stored (none without one).
    Georeference(Option<Georeference>),
}

impl GeoTiffStripWriter {
    /// Starts writing the `width x height` raster of `geometry` to `path`, placed as
    /// [`write_geotiff`](crate::write_geotiff) places a height field of that geometry
    /// (north-up, a projected CRS in metres). Values written are multiplied by
    /// `geometry.z_scale`.
    ///
    /// Errors: [`IoError::InvalidData`] for an empty raster, [`IoError::Unsupported`] for a
    /// side longer than 2^32 - 1 samples, [`IoError::Io`] when the temporary file cannot be
    /// created.
    pub fn create(
        path: &Path,
        width: usize,
        height: usize,
        geometry: &GridGeometry,
    ) -> Result<Self, IoError> {
        let big = width as u64 * height as u64 * 4 >= BIG_TIFF_FROM;
        let z_scale = geometry.z_scale;
        Self::start(path, (width, height), Placement::Geometry(*geometry), z_scale, big)
    }

    /// Starts writing a `width x height` raster to `path` placed by `georeference`'s tags,
    /// written unchanged (as [`write_layers_geotiff`](crate::write_layers_geotiff) does), or
    /// with no georeference when `None`. Rows are written in the georeference's file order:
    /// the northernmost first for the usual north-up one. Values are written as given.
    ///
    /// Errors: those of [`create`](Self::create).
    pub fn create_georeferenced(
        path: &Path,
        width: usize,
        height: usize,
        georeference: Option<&Georeference>,
    ) -> Result<Self, IoError> {
        let big = width as u64 * height as u64 * 4 >= BIG_TIFF_FROM;
        let placement = Placement::Georeference(georeference.cloned());
        Self::start(path, (width, height), placement, 1.0, big)
    }

    /// Creates the temporary file and starts the writing thread; a BigTIFF when `big`.
    fn start(
        path: &Path,
        (width, height): (usize, usize),
        placement: Placement,
        z_scale: f64,
        big: bool,
    ) -> Result<Self, IoError> {
        if width == 0 || height == 0 {
            return Err(IoError::invalid_data(
                path,
                format!("a raster of {width} x {height} samples is empty"),
            ));
        }
        // Refuses sides beyond u32 before anything is created.
        FloatStrips::new(path, width, height)?;
        let temp = temp_path(path)?;
        let file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)
            .map_err(|e| IoError::io(path, e))?;
        let (sender, receiver) = sync_channel(QUEUED_STRIPS);
        let target = path.to_path_buf();
        let thread = std::thread::Builder::new()
            .name("geotiff-writer".into())
            .spawn(move || write_file(file, &target, (width, height), placement, big, receiver))
            .map_err(|e| IoError::io(path, e));
        let thread = match thread {
            Ok(thread) => thread,
            Err(e) => {
                let _ = std::fs::remove_file(&temp);
                return Err(e);
            }
        };
        Ok(GeoTiffStripWriter {
            path: path.to_path_buf(),
            temp,
            width,
            height,
            z_scale,
            rows_per_strip: rows_per_strip(width, height),
            rows_written: 0,
            pending: Vec::new(),
            sender: Some(sender),
            thread: Some(thread),
        })
    }

    /// Rows written so far.
    pub fn rows_written(&self) -> usize {
        self.rows_written
    }

    /// Appends the next `rows.len() / width` rows, first row first (for a north-up raster,
    /// north first); NaN samples are voids. The strips they complete are compressed in
    /// parallel and queued for writing.
    ///
    /// Errors: [`IoError::InvalidData`] for rows that are not whole, rows past the raster's
    /// height, or a sample that is infinite (or overflows f32 once scaled), naming its column
    /// and grid row (row 0 south); [`IoError::Io`] when writing failed.
    pub fn write_rows(&mut self, rows: &[f32]) -> Result<(), IoError> {
        let width = self.width;
        if !rows.len().is_multiple_of(width) || rows.len() / width > self.height - self.rows_written
        {
            return Err(IoError::invalid_data(
                &self.path,
                format!(
                    "{} samples are not whole rows of {width}, or run past row {} of {} (rows \
                     written so far: {})",
                    rows.len(),
                    self.height,
                    self.height,
                    self.rows_written
                ),
            ));
        }
        let per_strip = self.rows_per_strip * width;
        let mut rest = rows;
        // First fill the strip begun by an earlier call.
        if !self.pending.is_empty() {
            let take = (per_strip - self.pending.len()).min(rest.len());
            let first_row = self.rows_written;
            self.scale_into_pending(&rest[..take], first_row)?;
            self.rows_written += take / width;
            rest = &rest[take..];
            if self.pending.len() == per_strip || self.rows_written == self.height {
                let packed = pack_strip(&self.path, &self.pending, width)?;
                self.pending.clear();
                self.send(vec![packed])?;
            }
        }
        // Whole strips (and the short last one) straight from `rest`, in parallel.
        let ends_raster = self.rows_written + rest.len() / width == self.height;
        let whole = if ends_raster { rest.len() } else { rest.len() / per_strip * per_strip };
        if whole > 0 {
            let (path, z_scale, first_row) = (&self.path, self.z_scale, self.rows_written);
            let (height, rows_per_strip) = (self.height, self.rows_per_strip);
            let packed: Vec<Result<Vec<u8>, IoError>> = rest[..whole]
                .par_chunks(per_strip)
                .enumerate()
                .map(|(k, strip)| {
                    let first = first_row + k * rows_per_strip;
                    let scaled = scaled(path, strip, (width, height), first, z_scale)?;
                    pack_strip(path, &scaled, width)
                })
                .collect();
            self.rows_written += whole / width;
            self.send(packed.into_iter().collect::<Result<Vec<_>, _>>()?)?;
        }
        let first_row = self.rows_written;
        self.scale_into_pending(&rest[whole..], first_row)?;
        self.rows_written += (rest.len() - whole) / width;
        Ok(())
    }

    /// Appends `values` (whole rows, the first the file's row `first_row`), scaled and
    /// checked, to the strip being filled.
    fn scale_into_pending(&mut self, values: &[f32], first_row: usize) -> Result<(), IoError> {
        let size = (self.width, self.height);
        let scaled = scaled(&self.path, values, size, first_row, self.z_scale)?;
        self.pending.extend_from_slice(&scaled);
        Ok(())
    }

    /// Queues compressed strips for the writing thread; when it has stopped, its error.
    fn send(&mut self, strips: Vec<Vec<u8>>) -> Result<(), IoError> {
        for strip in strips {
            let sent = self.sender.as_ref().map(|s| s.send(Message::Strip(strip)));
            if !matches!(sent, Some(Ok(()))) {
                return Err(self.stopped_thread_error());
            }
        }
        Ok(())
    }

    /// The error of a writing thread that stopped early.
    fn stopped_thread_error(&mut self) -> IoError {
        self.sender = None;
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(Err(e))) => e,
            _ => {
                IoError::io(&self.path, std::io::Error::other("the GeoTIFF writing thread stopped"))
            }
        }
    }

    /// Writes the directory after the last strip, syncs the file to disk and renames it to
    /// the path given at creation.
    ///
    /// Errors: [`IoError::InvalidData`] when fewer rows than the raster's height were
    /// written, [`IoError::Io`] when writing or renaming failed. On any error no file is left
    /// under the path.
    pub fn finish(mut self) -> Result<(), IoError> {
        if self.rows_written != self.height {
            return Err(IoError::invalid_data(
                &self.path,
                format!("finished after {} of {} rows", self.rows_written, self.height),
            ));
        }
        let sent = self.sender.take().map(|s| s.send(Message::Finish));
        let written = match (sent, self.thread.take().map(JoinHandle::join)) {
            (Some(Ok(())), Some(Ok(result))) => result,
            (_, Some(Ok(Err(e)))) => Err(e),
            _ => Err(IoError::io(
                &self.path,
                std::io::Error::other("the GeoTIFF writing thread stopped"),
            )),
        };
        written?;
        std::fs::rename(&self.temp, &self.path).map_err(|e| IoError::io(&self.path, e))
    }
}

impl Drop for GeoTiffStripWriter {
    /// An unfinished writer stops its thread and removes its temporary file.
    fn drop(&mut self) {
        self.sender = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
        // After a successful finish the temporary file was renamed: nothing to remove.
        let _ = std::fs::remove_file(&self.temp);
    }
}

/// `values` (whole rows of a `width x height` raster, the first its file row `first_row`)
/// times `z_scale`, voids as NaN; an infinite result is [`IoError::InvalidData`] naming its
/// column and grid row (row 0 south).
fn scaled(
    path: &Path,
    values: &[f32],
    (width, height): (usize, usize),
    first_row: usize,
    z_scale: f64,
) -> Result<Vec<f32>, IoError> {
    let mut out = Vec::with_capacity(values.len());
    for (i, &v) in values.iter().enumerate() {
        let value = if v.is_nan() {
            f32::NAN
        } else if z_scale == 1.0 {
            v
        } else {
            (f64::from(v) * z_scale) as f32
        };
        if value.is_infinite() {
            let (col, file_row) = (i % width, first_row + i / width);
            return Err(IoError::invalid_data(
                path,
                format!(
                    "sample at column {col}, row {} times z scale {z_scale} is not finite in \
                     f32",
                    height - 1 - file_row
                ),
            ));
        }
        out.push(value);
    }
    Ok(out)
}

/// The writing thread: writes each strip received to `file`, then, on [`Message::Finish`],
/// the directory; flushes and syncs. Ends with an error, writing no directory, when the
/// channel closes without the order to finish. `path` names the file in errors.
fn write_file(
    file: File,
    path: &Path,
    size: (usize, usize),
    placement: Placement,
    big: bool,
    strips: Receiver<Message>,
) -> Result<(), IoError> {
    let error = |e| encoding_error(path, e);
    let mut out = BufWriter::with_capacity(1 << 20, &file);
    if big {
        let tiff = TiffEncoder::<_, TiffKindBig>::new_big(&mut out).map_err(error)?;
        encode(tiff, path, size, &placement, &strips)?;
    } else {
        let tiff = TiffEncoder::<_, TiffKindStandard>::new(&mut out).map_err(error)?;
        encode(tiff, path, size, &placement, &strips)?;
    }
    out.flush().map_err(|e| IoError::io(path, e))?;
    drop(out);
    file.sync_all().map_err(|e| IoError::io(path, e))
}

/// Writes the strips received, then the directory: the same tags, in the same order, as
/// [`write_geotiff`](crate::write_geotiff) or [`write_layers_geotiff`](crate::write_layers_geotiff).
fn encode<W: Write + Seek, K: TiffKind>(
    mut tiff: TiffEncoder<W, K>,
    path: &Path,
    (width, height): (usize, usize),
    placement: &Placement,
    received: &Receiver<Message>,
) -> Result<(), IoError> {
    let error = |e| encoding_error(path, e);
    let mut strips = FloatStrips::new(path, width, height)?;
    let mut directory = tiff.image_directory().map_err(error)?;
    loop {
        match received.recv() {
            Ok(Message::Strip(packed)) => strips.push_packed(&mut directory, &packed)?,
            Ok(Message::Finish) => break,
            Err(_) => {
                return Err(IoError::invalid_data(path, "the writer stopped before the last row"))
            }
        }
    }
    if strips.strips_written() != strips.strips_per_band() {
        return Err(IoError::invalid_data(
            path,
            format!("{} of {} strips written", strips.strips_written(), strips.strips_per_band()),
        ));
    }
    strips.write_layout_tags(&mut directory, 1)?;
    match placement {
        Placement::Geometry(geometry) => {
            write_geometry_tags(&mut directory, path, geometry, height)?;
        }
        Placement::Georeference(georeference) => {
            if let Some(georeference) = georeference {
                write_georeference(&mut directory, path, &georeference.geotiff)?;
            }
            directory.write_tag(Tag::GdalNodata, "nan").map_err(error)?;
        }
    }
    directory.finish().map_err(error)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geotiff::{read_geotiff, write_geotiff};
    use crate::test_dir::TestDir;
    use crate::ReadOptions;
    use relief_core::{DVec2, HeightField};

    /// A `w x h` field with holes, z scale 2, placed in metres.
    fn field(w: usize, h: usize) -> HeightField {
        let samples = (0..w * h).map(|i| ((i * 7919) % 1000) as f32 * 0.25 - 100.0).collect();
        let geometry =
            GridGeometry { dx: 30.0, dy: 20.0, z_scale: 2.0, origin: DVec2::new(-500.0, 7.5) };
        let holes = (0..w * h).map(|i| i % 17 == 3).collect();
        HeightField::new(w, h, samples, geometry).unwrap().with_holes(holes).unwrap()
    }

    /// The field's rows north first, holes as NaN, unscaled.
    fn north_first(field: &HeightField) -> Vec<f32> {
        let (w, h) = (field.width(), field.height());
        let mut rows = Vec::with_capacity(w * h);
        for row in (0..h).rev() {
            for col in 0..w {
                rows.push(if field.is_hole(col, row) { f32::NAN } else { field.sample(col, row) });
            }
        }
        rows
    }

    /// Writes `rows` through a writer in calls of `bands` rows (the rest in the last call).
    fn write_in_bands(out: &mut GeoTiffStripWriter, rows: &[f32], width: usize, bands: &[usize]) {
        let mut at = 0;
        for &band in bands {
            let end = (at + band * width).min(rows.len());
            out.write_rows(&rows[at..end]).unwrap();
            at = end;
        }
        out.write_rows(&rows[at..]).unwrap();
    }

    #[test]
    fn the_file_is_write_geotiffs_byte_for_byte_whatever_the_bands() {
        let dir = TestDir::new("strip-writer-same");
        // 300 wide: 218 rows a strip, so 5 strips, the last short.
        let field = field(300, 1000);
        let whole = dir.path().join("whole.tif");
        write_geotiff(&whole, &field).unwrap();
        let expected = std::fs::read(&whole).unwrap();
        let rows = north_first(&field);
        for bands in [&[][..], &[1, 7, 250, 436], &[218, 218], &[999]] {
            let path = dir.path().join("strips.tif");
            let mut out = GeoTiffStripWriter::create(&path, 300, 1000, field.geometry()).unwrap();
            write_in_bands(&mut out, &rows, 300, bands);
            assert_eq!(out.rows_written(), 1000);
            out.finish().unwrap();
            assert!(std::fs::read(&path).unwrap() == expected, "bands {bands:?}");
        }
    }

    #[test]
    fn big_tiff_reads_back() {
        let dir = TestDir::new("strip-writer-big");
        let field = field(37, 23);
        let path = dir.path().join("big.tif");
        let placement = Placement::Geometry(*field.geometry());
        let mut out = GeoTiffStripWriter::start(&path, (37, 23), placement, 2.0, true).unwrap();
        write_in_bands(&mut out, &north_first(&field), 37, &[5]);
        out.finish().unwrap();
        assert_eq!(&std::fs::read(&path).unwrap()[..4], b"II+\0");
        let raster = read_geotiff(&path, &ReadOptions::default()).unwrap();
        let g = raster.geometry;
        assert_eq!((g.dx, g.dy, g.origin), (30.0, 20.0, DVec2::new(-500.0, 7.5)));
        for (k, &v) in raster.samples.iter().enumerate() {
            let (col, row) = (k % 37, k / 37);
            if field.is_hole(col, row) {
                assert!(v.is_nan());
            } else {
                assert_eq!(v, field.sample(col, row) * 2.0);
            }
        }
    }

    #[test]
    fn an_unfinished_or_failed_write_leaves_no_file() {
        let dir = TestDir::new("strip-writer-atomic");
        let path = dir.path().join("out.tif");
        std::fs::write(&path, b"old").unwrap();
        let rows = vec![1.0f32; 10 * 4];
        let unit = GridGeometry::unit();
        let listing = || {
            let mut names: Vec<String> = std::fs::read_dir(dir.path())
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            names.sort();
            names
        };
        // Dropped halfway.
        let mut out = GeoTiffStripWriter::create(&path, 10, 8, &unit).unwrap();
        out.write_rows(&rows).unwrap();
        assert_eq!(listing().len(), 2, "the temporary file is beside the target");
        drop(out);
        assert_eq!(listing(), ["out.tif"]);
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        // Finished too early.
        let mut out = GeoTiffStripWriter::create(&path, 10, 8, &unit).unwrap();
        out.write_rows(&rows).unwrap();
        let err = out.finish().unwrap_err();
        assert!(err.to_string().contains("finished after 4 of 8 rows"), "{err}");
        assert_eq!(listing(), ["out.tif"]);
        // Bad calls are errors, and the writer goes on.
        let mut out = GeoTiffStripWriter::create(&path, 10, 8, &unit).unwrap();
        for bad in [&rows[..15], &[0.0; 90][..]] {
            let err = out.write_rows(bad).unwrap_err();
            assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        }
        let mut infinite = rows.clone();
        infinite[13] = f32::INFINITY;
        let err = out.write_rows(&infinite).unwrap_err();
        assert!(err.to_string().contains("column 3, row 6"), "{err}");
        out.write_rows(&rows).unwrap();
        out.write_rows(&rows).unwrap();
        out.finish().unwrap();
        assert_eq!(listing(), ["out.tif"]);
        let raster = read_geotiff(&path, &ReadOptions::default()).unwrap();
        assert_eq!(raster.samples, vec![1.0; 80]);
        // Empty rasters and unwritable places are refused at once.
        assert!(GeoTiffStripWriter::create(&path, 0, 8, &unit).is_err());
        let missing = dir.path().join("no/such/dir/x.tif");
        assert!(matches!(
            GeoTiffStripWriter::create(&missing, 2, 2, &unit),
            Err(IoError::Io { .. })
        ));
    }

    #[test]
    fn a_georeference_is_written_unchanged() {
        let dir = TestDir::new("strip-writer-georeference");
        let fixture =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/jacksboro_fault_dem.tif");
        let input = read_geotiff(&fixture, &ReadOptions::default()).unwrap();
        let (w, h) = (input.width, input.height);
        let path = dir.path().join("copy.tif");
        let georeference = input.info.georeference.as_ref();
        let mut out = GeoTiffStripWriter::create_georeferenced(&path, w, h, georeference).unwrap();
        let north_first: Vec<f32> =
            input.samples.chunks_exact(w).rev().flatten().copied().collect();
        write_in_bands(&mut out, &north_first, w, &[100, 100]);
        out.finish().unwrap();
        let copy = read_geotiff(&path, &ReadOptions::default()).unwrap();
        assert_eq!(copy.geometry, input.geometry);
        assert_eq!(copy.info.georeference, input.info.georeference);
        assert_eq!(copy.info.from_degrees, input.info.from_degrees);
        let bits = |s: &[f32]| s.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&copy.samples), bits(&input.samples));
    }
}
