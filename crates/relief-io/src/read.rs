//! Reading any supported height file: the format follows the file name's extension.

use crate::{Format, IoError, PngEncoding, Raster, ReadOptions};
use std::io::Cursor;
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

/// [`read_raster`] before [`ReadOptions::z_unit`] is applied.
fn read_raster_as_stored(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    match format_of(path, options)? {
        Format::Npy => crate::npy::raster::read_npy(path, options),
        Format::Npz => crate::npy::npz::read_npz(path, options),
        Format::GeoTiff => crate::geotiff::read::read_geotiff(path, options),
        Format::Hgt => crate::hgt::tile::read_hgt(path, options),
        Format::Asc => crate::asc::grid::read_asc(path, options),
        Format::Png16 | Format::TerrainRgb | Format::Terrarium => {
            crate::png::height::read_png_height(path, options)
        }
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
    let mut raster = read_from_bytes(bytes, format, path, options)?;
    raster.apply_z_unit(options);
    Ok(raster)
}

/// [`read_raster_from_bytes`] before [`ReadOptions::z_unit`] is applied.
fn read_from_bytes(
    bytes: &[u8],
    format: Format,
    path: &Path,
    options: &ReadOptions,
) -> Result<Raster, IoError> {
    let len = bytes.len() as u64;
    let reader = Cursor::new(bytes);
    match format {
        Format::Npy => crate::npy::raster::read_npy_from(reader, len, path, options),
        Format::Npz => crate::npy::npz::read_npz_from(reader, len, path, options),
        Format::GeoTiff => crate::geotiff::read::read_geotiff_from(reader, path, options),
        Format::Hgt => crate::hgt::tile::read_hgt_from(reader, len, path, options),
        Format::Asc => crate::asc::grid::read_asc_from(reader, len, path, options),
        Format::Png16 | Format::TerrainRgb | Format::Terrarium => {
            let options = ReadOptions {
                png_encoding: match format {
                    Format::TerrainRgb => PngEncoding::TerrainRgb,
                    Format::Terrarium => PngEncoding::Terrarium,
                    _ => PngEncoding::Grey,
                },
                ..options.clone()
            };
            crate::png::height::read_png_height_from(reader, len, path, &options)
        }
    }
}
