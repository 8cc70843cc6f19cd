//! Several height files read as one raster: SRTM tiles placed by their names, GeoTIFFs by
//! their georeference, each read as rows only where a request overlaps it.

use crate::georef::geokeys::ModelGrid;
use crate::geotiff::rows::GeoTiffRows;
use crate::hgt::rows::HgtRows;
use crate::hgt::tile::hgt_mosaic_placement;
use crate::rows::open_rows::in_unit;
use crate::rows::row_source::check_request;
use crate::{
    format_of, open_rows, Format, GeoTiffTags, Georeference, IoError, RasterInfo, ReadOptions,
    RowSource,
};
use relief_core::GridGeometry;
use std::path::PathBuf;

/// Opens `paths` as one raster: a mosaic of SRTM `.hgt` tiles or of GeoTIFFs, read as rows on
/// request (see [`open_rows`] for how each input is read).
///
/// - `.hgt` tiles are placed by their names (`N37W119.hgt`, see
///   [`hgt_tile_corner`](crate::hgt::hgt_tile_corner)) and must all be of one size (1201 or 3601
///   samples a side). Neighbouring tiles share their edge rows and columns, so `a x b` tiles
///   of 3601 samples make `3600 a + 1` columns by `3600 b + 1` rows. The geometry is that
///   [`read_hgt`](crate::hgt::read_hgt) gives a tile, over the whole mosaic: degrees converted to
///   metres at the mosaic's central latitude, so that a mosaic of one tile is that tile.
/// - GeoTIFFs are placed by their georeference. They must share the pixel size (to a
///   relative 1e-9), the model (projected or geographic) and the coordinate reference system
///   (the GeoKeys, apart from citations and the raster type), and their samples must lie on
///   one grid (to 1e-3 pixel). The geometry is that [`read_geotiff`](crate::geotiff::read_geotiff)
///   would give one file covering the mosaic (geographic rasters converted at the mosaic's
///   central latitude).
///
/// The mosaic covers the rectangle around every input; samples no input covers are voids
/// (NaN). Where inputs overlap, the first input in `paths` with a valid (non-void) sample
/// there gives it. [`RowSource::info`] is the first input's, with the placement of the whole
/// mosaic. A single input of any other format is opened with [`open_rows`].
///
/// Streaming: [`RowSource::read_rows`] reads from each input only the rows the request
/// overlaps, and frees the decoding buffers of the inputs it does not touch. Every input
/// stays open (one file handle each) while the mosaic lives.
///
/// Errors: [`IoError::Mosaic`], naming the files and saying why, for no input, a mix of
/// `.hgt` tiles and GeoTIFFs, several inputs of another format, a `.hgt` whose name gives no
/// place, tiles of different sizes, GeoTIFFs without a georeference or of different pixel
/// sizes, models, coordinate reference systems or sample grids; any input's own error when
/// it cannot be opened.
pub fn open_mosaic(
    paths: &[PathBuf],
    options: &ReadOptions,
) -> Result<Box<dyn RowSource>, IoError> {
    let Some(first) = paths.first() else {
        return Err(IoError::mosaic(&[], "no input files"));
    };
    let first_format = format_of(first, options)?;
    for path in &paths[1..] {
        let format = format_of(path, options)?;
        if format != first_format {
            return Err(IoError::mosaic(
                &[first, path],
                format!(
                    "{} is {}, {} is {}: a mosaic is of one kind",
                    first.display(),
                    kind_name(first_format),
                    path.display(),
                    kind_name(format)
                ),
            ));
        }
    }
    match first_format {
        Format::Hgt => Ok(in_unit(Box::new(hgt_mosaic(paths)?), options)),
        Format::GeoTiff => Ok(in_unit(Box::new(geotiff_mosaic(paths, options)?), options)),
        _ if paths.len() == 1 => open_rows(first, options),
        other => Err(IoError::mosaic(
            &[first],
            format!(
                "{} is {}: a mosaic is made of SRTM .hgt tiles (placed by their names) or \
                 GeoTIFFs (placed by their georeference)",
                first.display(),
                kind_name(other)
            ),
        )),
    }
}

/// "an SRTM .hgt tile", "a GeoTIFF", ...
fn kind_name(format: Format) -> String {
    match format {
        Format::Hgt => "an SRTM .hgt tile".into(),
        Format::Asc => "an ESRI ASCII grid".into(),
        other => format!("a {other}"),
    }
}

/// An input of a mosaic and where it lies: its south-west sample at (`col`, `row`).
struct Placed {
    source: Box<dyn RowSource>,
    col: usize,
    row: usize,
}

/// Several inputs read as one raster.
struct Mosaic {
    width: usize,
    height: usize,
    geometry: GridGeometry,
    info: RasterInfo,
    inputs: Vec<Placed>,
    /// Names the mosaic in errors: its first input.
    path: PathBuf,
    /// Rows of one input, read before they are copied into the request.
    scratch: Vec<f32>,
}

impl Mosaic {
    /// A mosaic of `inputs` placed in a `width x height` grid.
    fn new(
        (width, height): (usize, usize),
        geometry: GridGeometry,
        info: RasterInfo,
        inputs: Vec<Placed>,
        paths: &[PathBuf],
    ) -> Result<Self, IoError> {
        let path = paths[0].clone();
        if width.checked_mul(height).is_none() {
            return Err(IoError::mosaic(
                &paths.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
                format!("{width} x {height} samples are more than this machine can count"),
            ));
        }
        Ok(Mosaic { width, height, geometry, info, inputs, path, scratch: Vec::new() })
    }
}

impl RowSource for Mosaic {
    fn width(&self) -> usize {
        self.width
    }
    fn height(&self) -> usize {
        self.height
    }
    fn geometry(&self) -> GridGeometry {
        self.geometry
    }
    fn info(&self) -> &RasterInfo {
        &self.info
    }
    fn read_rows(&mut self, first_row: usize, out: &mut [f32]) -> Result<(), IoError> {
        let width = self.width;
        let rows = check_request(&self.path, (width, self.height), first_row, out.len())?;
        out.fill(f32::NAN);
        let end_row = first_row + rows;
        for input in &mut self.inputs {
            let (w, h) = (input.source.width(), input.source.height());
            let from = first_row.max(input.row);
            let to = end_row.min(input.row + h);
            if from >= to {
                input.source.release_cache();
                continue;
            }
            self.scratch.resize((to - from) * w, 0.0);
            input.source.read_rows(from - input.row, &mut self.scratch)?;
            for (row, values) in (from..to).zip(self.scratch.chunks_exact(w)) {
                let start = (row - first_row) * width + input.col;
                for (o, &v) in out[start..start + w].iter_mut().zip(values) {
                    if o.is_nan() {
                        *o = v;
                    }
                }
            }
        }
        Ok(())
    }
    fn release_cache(&mut self) {
        for input in &mut self.inputs {
            input.source.release_cache();
        }
        self.scratch = Vec::new();
    }
}

/// A mosaic of SRTM tiles placed by their names.
fn hgt_mosaic(paths: &[PathBuf]) -> Result<Mosaic, IoError> {
    let tiles = paths.iter().map(|p| HgtRows::open(p)).collect::<Result<Vec<_>, _>>()?;
    let mut corners = Vec::with_capacity(tiles.len());
    for tile in &tiles {
        let corner = tile.corner().ok_or_else(|| {
            IoError::mosaic(
                &[tile.path()],
                format!(
                    "the name of {} does not say where the tile lies: a mosaic places SRTM \
                     tiles by names such as N36W085.hgt",
                    tile.path().display()
                ),
            )
        })?;
        corners.push(corner);
    }
    let side = tiles[0].width();
    if let Some(other) = tiles.iter().find(|t| t.width() != side) {
        let arc = |n: usize| if n == 1201 { 3 } else { 1 };
        return Err(IoError::mosaic(
            &[tiles[0].path(), other.path()],
            format!(
                "{} has {side} x {side} samples ({}\"), {} has {n} x {n} ({}\"): a mosaic \
                 needs one spacing",
                tiles[0].path().display(),
                arc(side),
                other.path().display(),
                arc(other.width()),
                n = other.width()
            ),
        ));
    }
    let lat_min = corners.iter().map(|c| c.0).min().unwrap_or(0);
    let lat_max = corners.iter().map(|c| c.0).max().unwrap_or(0);
    let lon_min = corners.iter().map(|c| c.1).min().unwrap_or(0);
    let lon_max = corners.iter().map(|c| c.1).max().unwrap_or(0);
    // Corners lie within -90..=89 and -180..=179: the differences are small and positive.
    let step = side - 1;
    let tiles_high = (lat_max - lat_min + 1) as usize;
    let tiles_wide = (lon_max - lon_min + 1) as usize;
    let (geometry, info) = hgt_mosaic_placement((lat_min, lon_min), tiles_high as u32, side);
    let inputs = tiles
        .into_iter()
        .zip(corners)
        .map(|(tile, (lat, lon))| Placed {
            source: Box::new(tile),
            col: (lon - lon_min) as usize * step,
            row: (lat - lat_min) as usize * step,
        })
        .collect();
    let size = (tiles_wide * step + 1, tiles_high * step + 1);
    Mosaic::new(size, geometry, info, inputs, paths)
}

/// Relative difference of pixel sizes below which two files share one.
const SAME_PIXEL_SIZE: f64 = 1e-9;

/// Largest distance, in pixels, of a file's samples from the mosaic's grid.
const ON_GRID: f64 = 1e-3;

/// A mosaic of GeoTIFFs placed by their georeference.
fn geotiff_mosaic(paths: &[PathBuf], options: &ReadOptions) -> Result<Mosaic, IoError> {
    let files =
        paths.iter().map(|p| GeoTiffRows::open(p, options)).collect::<Result<Vec<_>, _>>()?;
    let mut grids = Vec::with_capacity(files.len());
    for file in &files {
        let grid = file.model().ok_or_else(|| {
            IoError::mosaic(
                &[file.path()],
                format!(
                    "{} has no georeference: a mosaic places GeoTIFFs by their georeference",
                    file.path().display()
                ),
            )
        })?;
        grids.push(grid);
    }
    let (first, base) = (&files[0], grids[0]);
    let first_keys = crs_keys(first.info());
    let mut offsets = Vec::with_capacity(files.len());
    for (file, grid) in files.iter().zip(&grids) {
        let both = [first.path(), file.path()];
        let (a, b) = (first.path().display(), file.path().display());
        if grid.metres_per_unit != base.metres_per_unit {
            return Err(IoError::mosaic(
                &both,
                format!(
                    "{a} is {}, {b} is {}: a mosaic needs one projection",
                    units_name(&base),
                    units_name(grid)
                ),
            ));
        }
        if crs_keys(file.info()) != first_keys {
            return Err(IoError::mosaic(
                &both,
                format!(
                    "{a} and {b} are in different coordinate reference systems (their GeoKeys \
                     differ): a mosaic needs one projection"
                ),
            ));
        }
        let differs = |p: f64, q: f64| (p - q).abs() > SAME_PIXEL_SIZE * p.abs().max(q.abs());
        if differs(grid.dx, base.dx) || differs(grid.dy, base.dy) {
            return Err(IoError::mosaic(
                &both,
                format!(
                    "{a} has pixels of {} x {}, {b} of {} x {}: a mosaic needs one pixel size",
                    base.dx, base.dy, grid.dx, grid.dy
                ),
            ));
        }
        let col = (grid.west - base.west) / base.dx;
        let row = (grid.south - base.south) / base.dy;
        let off = (col - col.round()).abs().max((row - row.round()).abs());
        if off > ON_GRID || !col.is_finite() || !row.is_finite() {
            return Err(IoError::mosaic(
                &both,
                format!(
                    "{b}'s samples lie {off:.3} pixels off {a}'s sample grid: a mosaic needs \
                     its inputs on one grid"
                ),
            ));
        }
        offsets.push((col.round() as i64, row.round() as i64));
    }
    let min_col = offsets.iter().map(|o| o.0).min().unwrap_or(0);
    let min_row = offsets.iter().map(|o| o.1).min().unwrap_or(0);
    let end = |i: usize, (col, row): (i64, i64)| {
        (col - min_col + files[i].width() as i64, row - min_row + files[i].height() as i64)
    };
    let width = (0..files.len()).map(|i| end(i, offsets[i]).0).max().unwrap_or(0) as usize;
    let height = (0..files.len()).map(|i| end(i, offsets[i]).1).max().unwrap_or(0) as usize;
    // The grid's south-west corner, taken from the files that lie on it (not recomputed).
    let west = offsets.iter().zip(&grids).find(|(o, _)| o.0 == min_col).map(|(_, g)| g.west);
    let south = offsets.iter().zip(&grids).find(|(o, _)| o.1 == min_row).map(|(_, g)| g.south);
    let model =
        ModelGrid { west: west.unwrap_or(base.west), south: south.unwrap_or(base.south), ..base };
    let (geometry, from_degrees) =
        model.geometry((width, height)).map_err(|e| e.at(first.path()))?;
    // Every input is in the same CRS, so its heights are in the same unit as the first's.
    let geometry = GridGeometry { z_scale: first.geometry().z_scale, ..geometry };
    let mut info = first.info().clone();
    if files.len() > 1 {
        info.from_degrees = from_degrees;
        info.georeference = mosaic_georeference(first.info(), &model, height);
    }
    let inputs = files
        .into_iter()
        .zip(offsets)
        .map(|(file, (col, row))| Placed {
            source: Box::new(file),
            col: (col - min_col) as usize,
            row: (row - min_row) as usize,
        })
        .collect();
    Mosaic::new((width, height), geometry, info, inputs, paths)
}

/// "in degrees (geographic)" or "projected, in metres" (or another unit).
fn units_name(grid: &ModelGrid) -> String {
    match grid.metres_per_unit {
        None => "in degrees (geographic)".into(),
        Some(1.0) => "projected, in metres".into(),
        Some(unit) => format!("projected, in units of {unit} m"),
    }
}

/// The north-up placement of a mosaic on `model`'s grid, `height` rows high, in the first
/// file's CRS (its GeoKeys and their parameters, kept as stored).
fn mosaic_georeference(
    first: &RasterInfo,
    model: &ModelGrid,
    height: usize,
) -> Option<Georeference> {
    let stored = first.georeference.as_ref()?;
    // A PixelIsPoint tie point is the first sample's centre.
    let half = if stored.is_pixel_is_point() { 0.5 } else { 0.0 };
    let north = model.south + height as f64 * model.dy;
    let tags = GeoTiffTags {
        model_pixel_scale: Some(vec![model.dx, model.dy, 0.0]),
        model_tiepoint: Some(vec![
            0.0,
            0.0,
            0.0,
            model.west + half * model.dx,
            north - half * model.dy,
            0.0,
        ]),
        model_transformation: None,
        ..stored.geotiff.clone()
    };
    Georeference::from_geotiff_tags(tags)
}

/// The CRS GeoKeys of a file (see [`Georeference::crs_keys`]); none without a georeference.
fn crs_keys(info: &RasterInfo) -> Vec<(u16, String)> {
    info.georeference.as_ref().map_or_else(Vec::new, Georeference::crs_keys)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn path_lists_name_every_file() {
        let err = IoError::mosaic(
            &[Path::new("a.tif"), Path::new("b.tif"), Path::new("c.tif")],
            "reasons",
        );
        assert_eq!(err.to_string(), "a.tif, b.tif and c.tif: cannot be one mosaic: reasons");
    }
}
