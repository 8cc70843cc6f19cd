//! The files beside a raster that place it: an ESRI world file (`.pgw`, ...) and a `.prj`
//! naming its CRS in ESRI WKT, as GDAL writes and reads them for ESRI grids and images.

use crate::georef::crs::prj_crs;
use crate::georef::geokeys::ModelGrid;
use crate::{Georeference, HeightUnit, IoError, LengthUnit, Raster};
use relief_core::{DVec2, GridGeometry};
use std::path::{Path, PathBuf};

/// The largest world file read: six numbers need far less.
const MAX_WORLD_FILE_BYTES: u64 = 4096;

/// `raster` (an image, row 0 south) placed by the world file beside `path`
/// ([`world_file_path`](world_file_path)), when there is one, then in the CRS of its
/// `.prj` ([`with_prj`]). Without a `.prj` the world file's coordinates are taken as metres,
/// as an ESRI grid's are. A world file that is not six numbers, or that rotates, mirrors or
/// turns the image south-up, is refused.
pub(crate) fn with_world_file(path: &Path, mut raster: Raster) -> Result<Raster, IoError> {
    let world = world_file_path(path);
    let Some(bytes) = read_sidecar(&world, MAX_WORLD_FILE_BYTES)? else { return Ok(raster) };
    let text = String::from_utf8_lossy(&bytes);
    let numbers: Vec<f64> = text.split_whitespace().map_while(|w| w.parse().ok()).collect();
    let words = text.split_whitespace().count();
    let ([dx, rotation_y, rotation_x, minus_dy, centre_x, centre_y], 6) =
        (numbers.as_slice(), words)
    else {
        return Err(IoError::format(&world, "a world file holds six numbers, one a line"));
    };
    let (dx, dy) = (*dx, -*minus_dy);
    if *rotation_x != 0.0 || *rotation_y != 0.0 {
        return Err(IoError::unsupported(&world, "a rotated image (world file rotation terms)"));
    }
    let finite = centre_x.is_finite() && centre_y.is_finite();
    if !(dx > 0.0 && dy > 0.0 && finite) {
        return Err(IoError::unsupported(
            &world,
            format!("pixel size {dx} x {} (relief reads north-up, east-right images)", -dy),
        ));
    }
    let (west, north) = (centre_x - 0.5 * dx, centre_y + 0.5 * dy);
    let south = north - dy * raster.height as f64;
    let geometry = GridGeometry { dx, dy, origin: DVec2::new(west, south), ..raster.geometry };
    geometry.validate().map_err(|e| IoError::format(&world, format!("placement: {e}")))?;
    raster.geometry = geometry;
    raster.info.georeferenced = true;
    raster.info.georeference = Some(Georeference::north_up_grid(west, north, dx, dy));
    with_prj(path, raster)
}

/// The bytes of the sidecar file `path`, or `None` when there is none; a file over
/// `max_bytes` is refused.
fn read_sidecar(path: &Path, max_bytes: u64) -> Result<Option<Vec<u8>>, IoError> {
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(IoError::io(path, e)),
    };
    if bytes.len() as u64 > max_bytes {
        return Err(IoError::format(path, format!("{} bytes, too long for its kind", bytes.len())));
    }
    Ok(Some(bytes))
}

/// The largest `.prj` read: far more than any CRS's WKT needs.
const MAX_PRJ_BYTES: u64 = 1 << 20;

/// `raster` placed in the CRS of the `.prj` beside `path`, when there is one: a geographic
/// CRS's degrees converted to metres at the grid's central latitude (as for a GeoTIFF), a
/// projected CRS's units scaled to metres, the heights taken in the projected CRS's linear
/// unit (metres, assumed, for a geographic one) unless the file named their unit. A `.prj`
/// that is not ESRI WKT is refused (the grid's coordinates could be degrees or feet): fix or
/// remove it.
pub(crate) fn with_prj(path: &Path, mut raster: Raster) -> Result<Raster, IoError> {
    let prj = prj_path(path);
    let Some(bytes) = read_sidecar(&prj, MAX_PRJ_BYTES)? else { return Ok(raster) };
    let Some(grid) = &raster.info.georeference else { return Ok(raster) };
    let [west, dx, _, north, _, minus_dy] = grid.geotransform;
    let text = String::from_utf8_lossy(&bytes);
    let crs = prj_crs(&text, (west, north, dx, -minus_dy)).map_err(|why| {
        IoError::unsupported(
            &prj,
            format!("CRS: {why}; fix or remove it to read {}", path.display()),
        )
    })?;
    let south = north + minus_dy * raster.height as f64;
    let model = ModelGrid { west, south, dx, dy: -minus_dy, metres_per_unit: crs.metres_per_unit };
    let (geometry, from_degrees) =
        model.geometry((raster.width, raster.height)).map_err(|e| e.at(path))?;
    let height_unit = match crs.metres_per_unit {
        None => {
            HeightUnit::assumed_metres("the .prj's CRS is geographic and names no vertical unit")
        }
        Some(factor) => match LengthUnit::from_metres(factor) {
            Some(unit) => HeightUnit::new(unit, "the linear unit of the .prj's CRS"),
            None => HeightUnit::assumed_metres(&format!(
                "the .prj's linear unit of {factor} m is not a height unit relief knows"
            )),
        },
    };
    // A unit the file itself names (a PNG's tEXt height_unit) stands.
    if raster.info.height_unit.is_assumed() {
        raster.info.height_unit = height_unit;
    }
    raster.geometry = GridGeometry { z_scale: raster.info.height_unit.unit.metres(), ..geometry };
    raster.info.from_degrees = from_degrees;
    raster.info.georeference = Some(crs.georeference);
    Ok(raster)
}

/// The world file beside an image, as GDAL and ESRI name it: the extension's first and last
/// letters then `w` (`shade.png` → `shade.pgw`, `a.tif` → `a.tfw`), or `.wld` when the image
/// has no extension of at least two letters.
///
/// ```
/// use std::path::Path;
/// assert_eq!(relief_io::world_file_path(Path::new("out/shade.png")), Path::new("out/shade.pgw"));
/// ```
pub fn world_file_path(path: &Path) -> PathBuf {
    let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let mut chars = extension.chars();
    match (chars.next(), chars.next_back()) {
        (Some(first), Some(last)) => path.with_extension(format!("{first}{last}w")),
        _ => path.with_extension("wld"),
    }
}

/// The `.prj` beside a file: its extension replaced.
pub fn prj_path(path: &Path) -> PathBuf {
    path.with_extension("prj")
}

/// GDAL's auxiliary file beside a file: `c.png` → `c.png.aux.xml`.
pub fn aux_xml_path(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".aux.xml");
    PathBuf::from(name)
}
