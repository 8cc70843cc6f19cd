//! SRTM `.hgt` height tiles: big-endian int16 squares named after their south-west corner.
//!
//! A tile holds 1201 x 1201 (3 arc-seconds) or 3601 x 3601 (1 arc-second) samples, rows from
//! north to south, -32768 for a void. Its name, such as `N36W085.hgt`, gives the latitude and
//! longitude of its south-west sample. Samples are pixel-is-point: the south-west sample sits
//! exactly on the whole degree, so the texel grid starts half a pixel south-west of it.

use crate::atomic_write::write_atomically;
use crate::format_error::FormatError;
use crate::georef::geodesy::metres_per_degree;
use crate::input_file::open_input;
use crate::raster::{mark_voids, DegreeSpacing, Format, Raster, RasterInfo, ReadOptions};
use crate::{Georeference, HeightUnit, IoError, LengthUnit};
use relief_core::{DVec2, GridGeometry, HeightField};
use std::io::{BufReader, ErrorKind, Read, Write};
use std::path::Path;

/// The value of a void sample.
pub const HGT_VOID: i16 = -32768;

/// Samples per side of the tile sizes relief reads and writes: 3" and 1" tiles.
const SIDES: [usize; 2] = [1201, 3601];

/// The south-west corner `(latitude, longitude)` in whole degrees named by an SRTM tile's file
/// name, such as `N36W085.hgt` (36° N, 85° W → `(36, -85)`) or `s12e045.hgt` (`(-12, 45)`).
///
/// The name must start with `N` or `S` and two digits, then `E` or `W` and three digits
/// (either case), followed by nothing or a `.` (`N36W085.SRTMGL1.hgt` is fine). The corner
/// must lie within -90..=89 latitude and -180..=179 longitude. `None` for any other name.
///
/// ```
/// use std::path::Path;
/// assert_eq!(relief_io::hgt::hgt_tile_corner(Path::new("data/N36W085.hgt")), Some((36, -85)));
/// assert_eq!(relief_io::hgt::hgt_tile_corner(Path::new("tile.hgt")), None);
/// ```
pub fn hgt_tile_corner(path: &Path) -> Option<(i32, i32)> {
    let name = path.file_name()?.as_encoded_bytes();
    if name.len() < 7 || !(name.len() == 7 || name[7] == b'.') {
        return None;
    }
    let number = |digits: &[u8]| {
        digits
            .iter()
            .try_fold(0i32, |n, &d| d.is_ascii_digit().then(|| n * 10 + i32::from(d - b'0')))
    };
    let (lat, lon) = (number(&name[1..3])?, number(&name[4..7])?);
    let lat = match name[0].to_ascii_uppercase() {
        b'N' => lat,
        b'S' => -lat,
        _ => return None,
    };
    let lon = match name[3].to_ascii_uppercase() {
        b'E' => lon,
        b'W' => -lon,
        _ => return None,
    };
    ((-90..=89).contains(&lat) && (-180..=179).contains(&lon)).then_some((lat, lon))
}

/// Reads the SRTM tile at `path` as a raster, row 0 south.
///
/// The size comes from the file length: 2 * 1201² bytes for a 3" tile, 2 * 3601² for a 1"
/// tile. When the file name gives the tile's corner (see [`hgt_tile_corner`]), the raster is
/// georeferenced: spacing and origin in metres, converted from degrees at the tile's central
/// latitude with [`metres_per_degree`](crate::metres_per_degree), the origin (the texel grid's
/// south-west corner) half a pixel south-west of the corner sample. Otherwise the geometry is
/// [`GridGeometry::unit`] and `info.georeferenced` is false. Voids (-32768) become NaN.
///
/// Errors: [`IoError::Io`] when the file cannot be read (or is a directory),
/// [`IoError::Format`] for a file of any other length, [`IoError::Limits`] for a tile over the
/// memory budget.
pub fn read_hgt(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let (file, len) = open_input(path)?;
    read_hgt_from(BufReader::new(file), len, path, options).map_err(|e| e.at(path))
}

/// [`read_hgt`] from `reader` holding the `len` bytes of a tile, before the file is named;
/// `name`, the file's, places the tile.
pub(crate) fn read_hgt_from<R: Read>(
    mut reader: R,
    len: u64,
    name: &Path,
    options: &ReadOptions,
) -> Result<Raster, FormatError> {
    let n = tile_side(len)?;
    options.check_samples(n as u64, n as u64)?;
    let mut samples = vec![0f32; n * n];
    let mut row_bytes = vec![0u8; 2 * n];
    // The file's first row is the northernmost: it becomes the raster's last row.
    for row in samples.chunks_exact_mut(n).rev() {
        reader.read_exact(&mut row_bytes).map_err(|e| match e.kind() {
            ErrorKind::UnexpectedEof => FormatError::Format("truncated".into()),
            _ => FormatError::Io(e),
        })?;
        for (v, b) in row.iter_mut().zip(row_bytes.chunks_exact(2)) {
            *v = f32::from(i16::from_be_bytes([b[0], b[1]]));
        }
    }
    mark_voids(&mut samples, n, Some(f64::from(HGT_VOID)), true)?;
    let (geometry, info) = hgt_placement(hgt_tile_corner(name), n);
    Ok(Raster { width: n, height: n, samples, geometry, info })
}

/// The side of the SRTM tile `path` of `len` bytes: 1201 or 3601 samples; any other length
/// is an [`IoError::Format`].
pub(crate) fn hgt_side(path: &Path, len: u64) -> Result<usize, IoError> {
    tile_side(len).map_err(|e| e.at(path))
}

/// [`hgt_side`] before the file is named.
fn tile_side(len: u64) -> Result<usize, FormatError> {
    SIDES.into_iter().find(|&n| (2 * n * n) as u64 == len).ok_or_else(|| {
        FormatError::Format(format!(
            "an SRTM tile has 2884802 bytes (1201 x 1201, 3\") or 25934402 bytes \
             (3601 x 3601, 1\"); this file has {len}"
        ))
    })
}

/// The geometry and info of an SRTM tile of `side x side` samples whose south-west sample is
/// at `corner` (latitude, longitude), or of an unplaced one without a corner.
pub(crate) fn hgt_placement(corner: Option<(i32, i32)>, side: usize) -> (GridGeometry, RasterInfo) {
    match corner {
        Some(corner) => hgt_mosaic_placement(corner, 1, side),
        None => (GridGeometry::unit(), hgt_info(None, None)),
    }
}

/// The info of SRTM data: placed by `georeference` with `from_degrees`, or unplaced.
fn hgt_info(georeference: Option<Georeference>, from_degrees: Option<DegreeSpacing>) -> RasterInfo {
    RasterInfo {
        format: Format::Hgt,
        sample_type: "int16".into(),
        georeferenced: from_degrees.is_some(),
        from_degrees,
        nodata: Some(f64::from(HGT_VOID)),
        georeference,
        height_unit: HeightUnit::new(LengthUnit::Metre, "SRTM tiles hold metres"),
    }
}

/// The geometry and info of SRTM tiles of `side x side` samples laid edge to edge (sharing
/// their edge samples), `tiles_high` tiles from south to north, the south-west tile's
/// south-west sample at `south_west` (whole degrees of latitude and longitude).
///
/// Spacing and origin are in metres, converted from degrees at the central latitude of the
/// tiles with [`metres_per_degree`]; the origin (the texel grid's south-west corner) lies half
/// a pixel south-west of the corner sample. The georeference places the north-west sample as
/// GDAL does a `.hgt`. For one tile, the placement [`read_hgt`] gives.
pub(crate) fn hgt_mosaic_placement(
    (lat, lon): (i32, i32),
    tiles_high: u32,
    side: usize,
) -> (GridGeometry, RasterInfo) {
    let step = 1.0 / (side - 1) as f64;
    let latitude = f64::from(lat) + 0.5 * f64::from(tiles_high);
    let (per_lon, per_lat) = metres_per_degree(latitude);
    let (dx, dy) = (step * per_lon, step * per_lat);
    let origin =
        DVec2::new(f64::from(lon) * per_lon - 0.5 * dx, f64::from(lat) * per_lat - 0.5 * dy);
    let geometry = GridGeometry { dx, dy, z_scale: 1.0, origin };
    let north_tile = lat.saturating_add_unsigned(tiles_high.saturating_sub(1));
    let georeference = Georeference::srtm_tile(north_tile, lon, side);
    let degrees = DegreeSpacing { dlon: step, dlat: step, latitude };
    (geometry, hgt_info(Some(georeference), Some(degrees)))
}

/// Writes `field` as an SRTM tile: big-endian int16, rows from north to south, holes as
/// -32768.
///
/// The heights written are world heights in metres, `sample * z_scale`, rounded to the
/// nearest integer. Only the samples are written: a tile's position is its file name (see
/// [`hgt_tile_corner`]), its spacing implied by its size. The file is written atomically.
///
/// Errors: [`IoError::Unsupported`] for a field that is not 1201 x 1201 or 3601 x 3601,
/// [`IoError::InvalidData`] naming the first height that rounds outside -32767..=32767,
/// [`IoError::Io`] when the file cannot be written.
pub fn write_hgt(path: &Path, field: &HeightField) -> Result<(), IoError> {
    let n = field.width();
    if field.height() != n || !SIDES.contains(&n) {
        return Err(IoError::unsupported(
            path,
            format!(
                "SRTM tile of {} x {} samples (only 1201 x 1201 and 3601 x 3601)",
                field.width(),
                field.height()
            ),
        ));
    }
    let z_scale = field.geometry().z_scale;
    write_atomically(path, |w| {
        let mut bytes = Vec::with_capacity(2 * n);
        for row in (0..n).rev() {
            bytes.clear();
            for col in 0..n {
                let value = if field.is_hole(col, row) {
                    HGT_VOID
                } else {
                    let world = (f64::from(field.sample(col, row)) * z_scale).round();
                    if !(-32767.0..=32767.0).contains(&world) {
                        return Err(IoError::invalid_data(
                            path,
                            format!(
                                "height {world} m at column {col}, row {row} is outside the \
                                 -32767..=32767 range of an SRTM tile"
                            ),
                        ));
                    }
                    world as i16
                };
                bytes.extend_from_slice(&value.to_be_bytes());
            }
            w.write_all(&bytes).map_err(|e| IoError::io(path, e))?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_give_the_south_west_corner() {
        let corner = |name: &str| hgt_tile_corner(Path::new(name));
        assert_eq!(corner("N36W085.hgt"), Some((36, -85)));
        assert_eq!(corner("s12e045.hgt"), Some((-12, 45)));
        assert_eq!(corner("/some/dir/S90W180.HGT"), Some((-90, -180)));
        assert_eq!(corner("N00E000"), Some((0, 0)));
        assert_eq!(corner("N36W085.SRTMGL1.hgt"), Some((36, -85)));
        for bad in ["N90E000.hgt", "N00E180.hgt", "X36W085.hgt", "N36X085.hgt", "N3aW085.hgt"] {
            assert_eq!(corner(bad), None, "{bad}");
        }
        for bad in ["N36W08.hgt", "N36W0850.hgt", "N36W085hgt", "", "N36", "é36W085.hgt"] {
            assert_eq!(corner(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_wrong_length_is_refused_before_reading() {
        let path = Path::new("N36W085.hgt");
        for len in [0, 1, 2 * 1201 * 1201 - 2, 2 * 1201 * 1201 + 2, 2 * 3600 * 3600, u64::MAX] {
            let err =
                read_hgt_from(&[][..], len, path, &ReadOptions::default()).unwrap_err().at(path);
            assert!(matches!(err, IoError::Format { .. }), "{err}");
            assert!(err.to_string().contains(&format!("this file has {len}")), "{err}");
        }
    }
}
