//! Reading any supported height file: the format follows the file name's extension.

use crate::georef::sidecars::{with_prj, with_world_file};
use crate::input_file::open_input;
use crate::{Format, IoError, PngEncoding, Raster, ReadOptions};
use std::io::{BufRead, BufReader, Cursor, Seek};
use std::path::Path;

/// The format a path's extension names, with the PNG encoding from `options`.
pub fn format_of(path: &Path, options: &ReadOptions) -> Result<Format, IoError> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    Ok(match extension.as_deref() {
        Some("npy") => Format::Npy,
        Some("npz") => Format::Npz,
        Some("tif" | "tiff") => Format::GeoTiff,
        Some("hgt") => Format::Hgt,
        Some("asc") => Format::Asc,
        Some("png") => match options.png_encoding {
            PngEncoding::Grey => Format::Png16,
            PngEncoding::TerrainRgb => Format::TerrainRgb,
            PngEncoding::Terrarium => Format::Terrarium,
        },
        _ => {
            return Err(IoError::unsupported(
                path,
                "file type: expected .tif, .tiff, .hgt, .asc, .png, .npy or .npz",
            ))
        }
    })
}

/// Reads the height raster at `path`, in the format its extension names.
///
/// The raster's heights are as stored; its geometry's z scale turns them into metres, from
/// the unit the file names ([`RasterInfo::height_unit`](crate::RasterInfo::height_unit)) or
/// the one [`ReadOptions::z_unit`] gives.
pub fn read_raster(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let mut raster = read_raster_as_stored(path, options)?;
    raster.apply_z_unit(options);
    Ok(raster)
}

/// [`read_raster`] before [`ReadOptions::z_unit`] is applied: the file opened once, its bytes
/// decoded, and its error named once.
fn read_raster_as_stored(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let format = format_of(path, options)?;
    let (file, len) = open_input(path)?;
    let raster = decode(BufReader::new(file), len, format, path, options)?;
    match format {
        Format::Asc => with_prj(path, raster),
        Format::Png16 | Format::TerrainRgb | Format::Terrarium => with_world_file(path, raster),
        Format::Npy | Format::Npz | Format::GeoTiff | Format::Hgt => Ok(raster),
    }
}

/// Reads a raster of `format` from bytes in memory; `path` names it in errors (the `.hgt`
/// reader takes its georeference from the name). Used by the fuzz targets.
pub fn read_raster_from_bytes(
    bytes: &[u8],
    format: Format,
    path: &Path,
    options: &ReadOptions,
) -> Result<Raster, IoError> {
    let mut raster = decode(Cursor::new(bytes), bytes.len() as u64, format, path, options)?;
    raster.apply_z_unit(options);
    Ok(raster)
}

/// The raster of `format` in the `len` bytes of `reader`, without the files beside it; errors
/// name `path` (whose name also places an SRTM tile).
fn decode<R: BufRead + Seek>(
    reader: R,
    len: u64,
    format: Format,
    path: &Path,
    options: &ReadOptions,
) -> Result<Raster, IoError> {
    match format {
        Format::Npy => {
            crate::npy::raster::read_npy_from(reader, len, options).map_err(|e| e.at(path))
        }
        Format::Npz => crate::npy::npz::read_npz_from(reader, len, options).map_err(|e| e.at(path)),
        Format::GeoTiff => {
            crate::geotiff::read::read_geotiff_from(reader, options).map_err(|e| e.at(path))
        }
        Format::Hgt => {
            crate::hgt::tile::read_hgt_from(reader, len, path, options).map_err(|e| e.at(path))
        }
        Format::Asc => {
            crate::asc::grid::read_asc_from(reader, len, options).map_err(|e| e.at(path))
        }
        Format::Png16 | Format::TerrainRgb | Format::Terrarium => {
            let options = ReadOptions {
                png_encoding: match format {
                    Format::TerrainRgb => PngEncoding::TerrainRgb,
                    Format::Terrarium => PngEncoding::Terrarium,
                    _ => PngEncoding::Grey,
                },
                ..options.clone()
            };
            crate::png::height::read_png_height_from(reader, len, &options).map_err(|e| e.at(path))
        }
    }
}
