//! A raster as read from a file, before its voids are resolved, and the options of reading.

use crate::format_error::FormatError;
use crate::memory_budget::default_memory_limit;
use crate::void_fill::fill_voids;
use crate::{Georeference, HeightUnit, IoError, LengthUnit};
use relief_core::{GridGeometry, HeightField};
use std::fmt;
use std::path::Path;

/// The file formats relief reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// NumPy `.npy` array.
    Npy,
    /// NumPy `.npz` archive of arrays.
    Npz,
    /// GeoTIFF (`.tif`, `.tiff`).
    GeoTiff,
    /// SRTM height tile (`.hgt`).
    Hgt,
    /// ESRI ASCII grid (`.asc`).
    Asc,
    /// 16-bit greyscale PNG: the sample is the grey value.
    Png16,
    /// Mapbox terrain-RGB PNG tile: height = -10000 + (R * 65536 + G * 256 + B) / 10.
    TerrainRgb,
    /// Terrarium PNG tile: height = R * 256 + G + B / 256 - 32768.
    Terrarium,
}

impl Format {
    /// A human-readable name.
    pub fn name(self) -> &'static str {
        match self {
            Format::Npy => "NumPy .npy",
            Format::Npz => "NumPy .npz",
            Format::GeoTiff => "GeoTIFF",
            Format::Hgt => "SRTM .hgt",
            Format::Asc => "ESRI ASCII grid",
            Format::Png16 => "16-bit greyscale PNG",
            Format::TerrainRgb => "Mapbox terrain-RGB PNG",
            Format::Terrarium => "Terrarium PNG",
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

/// How a PNG's pixels encode heights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PngEncoding {
    /// 16-bit (or 8-bit) grey: the sample is the grey value.
    #[default]
    Grey,
    /// Mapbox terrain-RGB.
    TerrainRgb,
    /// Terrarium.
    Terrarium,
}

/// A georeference given in degrees, converted to metres at the raster's latitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DegreeSpacing {
    /// Pixel width in degrees of longitude.
    pub dlon: f64,
    /// Pixel height in degrees of latitude.
    pub dlat: f64,
    /// Latitude (degrees) at which the conversion to metres was made: the raster's centre.
    pub latitude: f64,
}

/// What a reader learned about a file besides its samples.
#[derive(Debug, Clone, PartialEq)]
pub struct RasterInfo {
    /// The file's format.
    pub format: Format,
    /// The stored sample type, e.g. `int16` or `float32`.
    pub sample_type: String,
    /// Whether spacing and origin came from the file (else they are 1 and 0, grid units).
    pub georeferenced: bool,
    /// Set when the georeference was in degrees and was converted to metres.
    pub from_degrees: Option<DegreeSpacing>,
    /// The value the file declares for missing samples, if any.
    pub nodata: Option<f64>,
    /// The file's placement and CRS as stored, for writing outputs aligned with it: a
    /// GeoTIFF's own georeferencing tags, an SRTM tile's WGS 84 placement from its name, an
    /// ESRI grid's corner and cell size or a PNG's world file, in the CRS of the `.prj`
    /// beside it (in no stated CRS without one); `None` for a file without one (`.npy`,
    /// `.npz`, a PNG without a world file, a TIFF without model tags).
    pub georeference: Option<Georeference>,
    /// The unit of the stored heights and why relief took it; the raster's geometry's
    /// `z_scale` is its length in metres.
    pub height_unit: HeightUnit,
}

/// A grid of samples as a reader found it: row 0 southernmost (north-up files are flipped),
/// voids (the file's nodata) as NaN, every other sample finite.
#[derive(Debug, Clone, PartialEq)]
pub struct Raster {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` samples, row-major, row 0 south, NaN for a void.
    pub samples: Vec<f32>,
    /// Spacing and origin (metres when georeferenced); z scale the metres in one unit of the
    /// stored heights ([`RasterInfo::height_unit`]): 1 for metres, 0.3048 for feet.
    pub geometry: GridGeometry,
    /// What the file said about itself.
    pub info: RasterInfo,
}

/// What to do with voids (nodata samples) when a raster becomes a height field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VoidPolicy {
    /// Fill each void from the nearest valid sample, then smooth the filled area.
    #[default]
    Fill,
    /// Keep voids as holes: empty texels that the tracers see through.
    Hole,
}

/// Options of every reader.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadOptions {
    /// Largest number of bytes a raster may need in memory; larger ones are refused before
    /// anything is allocated.
    pub max_memory: u64,
    /// The array to read from an `.npz` archive (default: the first).
    pub array: Option<String>,
    /// How PNG pixels encode heights.
    pub png_encoding: PngEncoding,
    /// The unit of the stored heights, when the caller knows it better than the file (the
    /// command line's `--z-unit`): it replaces the unit the file names or implies.
    pub z_unit: Option<LengthUnit>,
}

impl Default for ReadOptions {
    /// The [`default_memory_limit`] (half the machine's memory or of its cgroup's limit,
    /// whichever is smaller), first array, grey PNG.
    fn default() -> Self {
        ReadOptions {
            max_memory: default_memory_limit(),
            array: None,
            png_encoding: PngEncoding::Grey,
            z_unit: None,
        }
    }
}

/// Bytes per sample a raster needs while being read: the f32 samples plus a margin for the
/// reader's decoding buffers and the void mask.
pub const BYTES_PER_SAMPLE: u64 = 5;

impl ReadOptions {
    /// The unit of a raster's heights: [`ReadOptions::z_unit`] when given, else `found`, the
    /// unit the file names or implies.
    pub fn height_unit(&self, found: HeightUnit) -> HeightUnit {
        match self.z_unit {
            Some(unit) => HeightUnit::new(
                unit,
                format!("given by the caller (--z-unit); the file says {found}"),
            ),
            None => found,
        }
    }

    /// Refuses a `width x height` raster whose samples would exceed the memory budget, and a
    /// raster with no samples.
    pub fn check_size(&self, path: &Path, width: u64, height: u64) -> Result<(), IoError> {
        self.check_samples(width, height).map_err(|e| e.at(path))
    }

    /// [`ReadOptions::check_size`] before the file is named.
    pub(crate) fn check_samples(&self, width: u64, height: u64) -> Result<(), FormatError> {
        if width == 0 || height == 0 {
            return Err(FormatError::Format(format!(
                "raster of {width} x {height} samples is empty"
            )));
        }
        let needed = width.saturating_mul(height).saturating_mul(BYTES_PER_SAMPLE);
        if needed > self.max_memory || usize::try_from(width.saturating_mul(height)).is_err() {
            return Err(FormatError::Limits { width, height, needed, limit: self.max_memory });
        }
        Ok(())
    }
}

impl Raster {
    /// Applies [`ReadOptions::z_unit`]: the heights' unit becomes the caller's, and the z scale
    /// its length in metres. Every reader of [`read_raster`](crate::read_raster) does this.
    pub fn apply_z_unit(&mut self, options: &ReadOptions) {
        if options.z_unit.is_some() {
            let found = std::mem::take(&mut self.info.height_unit);
            self.info.height_unit = options.height_unit(found);
            self.geometry.z_scale = self.info.height_unit.unit.metres();
        }
    }

    /// Number of voids.
    pub fn void_count(&self) -> usize {
        self.samples.iter().filter(|v| v.is_nan()).count()
    }

    /// Smallest and largest valid sample; `None` when every sample is a void.
    pub fn value_range(&self) -> Option<(f32, f32)> {
        let valid = self.samples.iter().copied().filter(|v| !v.is_nan());
        valid.fold(None, |r, v| {
            Some(r.map_or((v, v), |(lo, hi): (f32, f32)| (lo.min(v), hi.max(v))))
        })
    }

    /// The height field of this raster, with its voids resolved by `voids`. `path` names the
    /// file in errors (a raster of nothing but voids, for one).
    pub fn into_height_field(self, path: &Path, voids: VoidPolicy) -> Result<HeightField, IoError> {
        let Raster { width, height, samples, geometry, .. } = self;
        height_field_of_samples(width, height, samples, geometry, path, voids)
    }
}

/// The height field of `width x height` row-major `samples` (row 0 south; voids NaN) placed
/// by `geometry`, with its voids resolved by `voids`: filled (nearest valid sample, then
/// smoothed) or kept as holes. `path` names the samples' file in errors (samples of nothing
/// but voids, for one).
pub fn height_field_of_samples(
    width: usize,
    height: usize,
    mut samples: Vec<f32>,
    geometry: GridGeometry,
    path: &Path,
    voids: VoidPolicy,
) -> Result<HeightField, IoError> {
    let has_voids = samples.iter().any(|v| v.is_nan());
    if has_voids && samples.iter().all(|v| v.is_nan()) {
        return Err(IoError::invalid_data(path, "every sample is a void (nodata)"));
    }
    let invalid = |e: relief_core::CoreError| IoError::invalid_data(path, e.to_string());
    match voids {
        VoidPolicy::Fill => {
            if has_voids {
                fill_voids(width, height, &mut samples);
            }
            HeightField::new(width, height, samples, geometry).map_err(invalid)
        }
        VoidPolicy::Hole if has_voids => {
            let holes: Vec<bool> = samples.iter().map(|v| v.is_nan()).collect();
            for v in samples.iter_mut().filter(|v| v.is_nan()) {
                *v = 0.0;
            }
            let field = HeightField::new(width, height, samples, geometry).map_err(invalid)?;
            field.with_holes(holes).map_err(invalid)
        }
        VoidPolicy::Hole => HeightField::new(width, height, samples, geometry).map_err(invalid),
    }
}

/// Marks samples equal to `nodata` as voids (NaN) and refuses any other non-finite sample,
/// naming its column and row in the file's own order (`row_from_top` tells that order).
pub(crate) fn mark_voids(
    samples: &mut [f32],
    width: usize,
    nodata: Option<f64>,
    row_from_top: bool,
) -> Result<(), FormatError> {
    let height = samples.len() / width.max(1);
    for (row, values) in samples.chunks_mut(width.max(1)).enumerate() {
        let file_row = if row_from_top { height - 1 - row } else { row };
        mark_row_voids(values, file_row, nodata)?;
    }
    Ok(())
}

/// [`mark_voids`] of one row, `file_row` its row in the file's own order (named in errors).
pub(crate) fn mark_row_voids(
    values: &mut [f32],
    file_row: usize,
    nodata: Option<f64>,
) -> Result<(), FormatError> {
    let nodata_f32 = nodata.map(|v| v as f32);
    for (col, v) in values.iter_mut().enumerate() {
        let is_void = match nodata_f32 {
            Some(nd) if nd.is_nan() => v.is_nan(),
            Some(nd) => *v == nd,
            None => false,
        };
        if is_void {
            *v = f32::NAN;
        } else if !v.is_finite() {
            return Err(FormatError::InvalidData(format!(
                "sample at column {col}, row {file_row} is {v}{}",
                if nodata.is_none() { " and the file declares no nodata value" } else { "" }
            )));
        }
    }
    Ok(())
}
