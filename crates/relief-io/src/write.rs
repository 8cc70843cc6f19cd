//! Writing a height field in the format its file name's extension names, placed in its
//! input's CRS where the format can say so.

use crate::{aux_xml_path, prj_path, world_file_path};
use crate::{Georeference, IoError, LengthUnit};
use relief_core::{DVec2, GridGeometry, HeightField};
use std::path::{Path, PathBuf};

/// Writes `field` to `path` as `.tif`/`.tiff` (float32 GeoTIFF), `.hgt`, `.asc`, `.png`
/// (16-bit grey) or `.npy` (float32), by extension. GeoTIFF, .hgt, .asc and PNG store heights
/// in world units (sample value times z scale; a PNG with the scale and offset that use its
/// 16 bits); .npy stores the samples themselves. Holes become the format's nodata.
///
/// The GeoTIFF is placed by the field's geometry in a user-defined CRS in metres; to keep an
/// input's CRS, see [`write_height_field_georeferenced`].
pub fn write_height_field(path: &Path, field: &HeightField) -> Result<(), IoError> {
    write_height_field_georeferenced(path, field, None, LengthUnit::Metre).map(|_| ())
}

/// What [`write_height_field_georeferenced`] wrote beside the file and what it changed or
/// could not keep, one sentence each, for the user.
pub type WriteNotes = Vec<String>;

/// Writes `field` to `path` as [`write_height_field`] does, its world heights
/// (`sample * z_scale`) being in `height_unit`, and placed by `georeference` (the input's,
/// on a grid of the field's size) in every format that can hold one:
///
/// - `.tif`: the georeference's GeoTIFF tags written back (the same CRS, EPSG-coded or
///   user-defined, and placement), with a VerticalUnitsGeoKey when the heights' unit is not
///   the one the CRS implies;
/// - `.asc`: the corner and cell size in the CRS's own units (degrees for a geographic CRS),
///   and a `.prj` beside it with the CRS's ESRI WKT ([`Georeference::esri_wkt`]); the heights
///   in the CRS's linear unit (metres for a geographic CRS), converted if need be;
/// - `.png`: the heights' scale, offset and unit in tEXt chunks, a world file (`.pgw`), a
///   `.prj` and, for GDAL (which reads a PNG's CRS there), a `.png.aux.xml` with the same WKT;
/// - `.hgt`, `.npy`: no georeference beyond an SRTM tile's name; heights in metres.
///
/// A sidecar an earlier file of the same name left beside an `.asc` or `.png` that this write
/// does not replace (a world file, `.prj` or `.png.aux.xml` that would place the new file
/// wrongly) is removed. Each sidecar written or removed, each conversion of the heights and
/// each piece of georeference that could not be written is said in the notes returned.
/// Errors: as the format's writer.
pub fn write_height_field_georeferenced(
    path: &Path,
    field: &HeightField,
    georeference: Option<&Georeference>,
    height_unit: LengthUnit,
) -> Result<WriteNotes, IoError> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let mut notes = WriteNotes::new();
    match extension.as_deref() {
        Some("tif" | "tiff") => match georeference {
            Some(georeference) => {
                let implied = georeference.height_unit();
                let placed = if implied.unit == height_unit {
                    georeference.clone()
                } else {
                    notes.push(format!(
                        "VerticalUnitsGeoKey says the heights are in {height_unit} (the CRS \
                         alone implies {})",
                        implied.unit
                    ));
                    georeference.with_vertical_unit(height_unit)
                };
                crate::geotiff::write::write_geotiff_placed(path, field, Some(&placed))?;
            }
            None => {
                let field = in_unit(field, height_unit, LengthUnit::Metre, path, &mut notes)?;
                crate::geotiff::write::write_geotiff(path, &field)?;
            }
        },
        Some("hgt") => {
            let field = in_unit(field, height_unit, LengthUnit::Metre, path, &mut notes)?;
            let rounding = largest_rounding(&field);
            if rounding > 0.0 {
                notes.push(format!(
                    "a .hgt stores whole metres: heights rounded, by up to {rounding:.3} m (write \
                     .tif, .asc or .png to keep them)"
                ));
            }
            crate::hgt::tile::write_hgt(path, &field)?;
        }
        Some("asc") => write_asc_georeferenced(path, field, georeference, height_unit, &mut notes)?,
        Some("png") => {
            let scale = crate::png::height::write_png16_height_in(path, field, height_unit)?;
            notes.push(format!(
                "heights stored in steps of {} {height_unit} (grey * {} + {}, in the PNG's \
                 tEXt height_scale and height_offset)",
                scale.scale, scale.scale, scale.offset
            ));
            if let Some(georeference) = georeference {
                let world = world_file_path(path);
                let north_up = Georeference {
                    geotransform: georeference.north_up_geotransform(field.height()),
                    ..georeference.clone()
                };
                write_text(&world, &north_up.world_file())?;
                notes.push(format!("wrote {} (the placement)", world.display()));
                write_image_crs(path, georeference, &mut notes)?;
            }
        }
        Some("npy") => {
            if field.holes().is_some() {
                return Err(IoError::unsupported(
                    path,
                    "voids in .npy, which has no nodata value: fill them (--voids fill) or write .tif, .asc or .hgt",
                ));
            }
            if let Some(georeference) = georeference {
                notes.push(format!(
                    "a .npy holds no georeference: {} and the placement are not kept (write \
                     .tif, .asc or .png to keep them)",
                    georeference.crs_name()
                ));
            }
            let field = in_unit(field, height_unit, LengthUnit::Metre, path, &mut notes)?;
            let field = if field.geometry().z_scale != 1.0 {
                // A .npy stores samples: give it the heights themselves.
                let z = field.geometry().z_scale;
                let samples = field.samples().iter().map(|&v| (f64::from(v) * z) as f32).collect();
                let geometry = GridGeometry { z_scale: 1.0, ..*field.geometry() };
                HeightField::new(field.width(), field.height(), samples, geometry)
                    .map_err(|e| IoError::invalid_data(path, e.to_string()))?
            } else {
                field
            };
            crate::write_height_field_npy(path, &field)?;
        }
        _ => {
            return Err(IoError::unsupported(
                path,
                "output type: expected .tif, .tiff, .hgt, .asc, .png or .npy",
            ))
        }
    }
    for stale in stale_sidecars(path, extension.as_deref(), georeference) {
        remove_stale_sidecar(&stale, path, &mut notes)?;
    }
    Ok(notes)
}

/// The files beside `path` that GDAL and relief would read as its placement or CRS but that
/// this write does not make (no georeference, or a CRS no `.prj` can name): left there by an
/// earlier file of the same name, they would place this one wrongly.
fn stale_sidecars(
    path: &Path,
    extension: Option<&str>,
    georeference: Option<&Georeference>,
) -> Vec<PathBuf> {
    let crs_written = georeference.is_some_and(|g| g.esri_wkt().is_ok());
    let mut stale = Vec::new();
    match extension {
        Some("asc") if !crs_written => stale.push(prj_path(path)),
        Some("png") => {
            if georeference.is_none() {
                stale.push(world_file_path(path));
            }
            if !crs_written {
                stale.extend([prj_path(path), aux_xml_path(path)]);
            }
        }
        _ => {}
    }
    stale
}

/// Removes `sidecar`, left beside `path` by an earlier file, and says so.
fn remove_stale_sidecar(
    sidecar: &Path,
    path: &Path,
    notes: &mut WriteNotes,
) -> Result<(), IoError> {
    match std::fs::remove_file(sidecar) {
        Ok(()) => {
            notes.push(format!(
                "removed {}: left by an earlier file, it would have placed {} wrongly",
                sidecar.display(),
                path.display()
            ));
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(IoError::io(sidecar, e)),
    }
}

/// The largest change rounding `field`'s world heights to whole metres makes (0 when they
/// are whole already), voids left out.
fn largest_rounding(field: &HeightField) -> f64 {
    let z_scale = field.geometry().z_scale;
    let mut largest = 0.0f64;
    for row in 0..field.height() {
        for col in 0..field.width() {
            if field.is_hole(col, row) {
                continue;
            }
            let world = f64::from(field.sample(col, row)) * z_scale;
            largest = largest.max((world - world.round()).abs());
        }
    }
    largest
}

/// `field` with its world heights in `to` rather than `from` (its z scale changed), and a
/// note when they were converted.
fn in_unit(
    field: &HeightField,
    from: LengthUnit,
    to: LengthUnit,
    path: &Path,
    notes: &mut WriteNotes,
) -> Result<HeightField, IoError> {
    if from == to {
        return Ok(field.clone());
    }
    notes.push(format!(
        "heights converted from {from} to {to}: {} does not record a height unit",
        path.display()
    ));
    let geometry = GridGeometry {
        z_scale: field.geometry().z_scale * from.metres() / to.metres(),
        ..*field.geometry()
    };
    field.clone().with_geometry(geometry).map_err(|e| IoError::invalid_data(path, e.to_string()))
}

/// Writes an ESRI grid placed by `georeference` in its own units, with its `.prj`.
fn write_asc_georeferenced(
    path: &Path,
    field: &HeightField,
    georeference: Option<&Georeference>,
    height_unit: LengthUnit,
    notes: &mut WriteNotes,
) -> Result<(), IoError> {
    let Some(georeference) = georeference else {
        let field = in_unit(field, height_unit, LengthUnit::Metre, path, notes)?;
        return crate::asc::grid::write_asc(path, &field);
    };
    let [west, dx, rotation_x, north, rotation_y, minus_dy] =
        georeference.north_up_geotransform(field.height());
    if rotation_x != 0.0 || rotation_y != 0.0 {
        return Err(IoError::unsupported(path, "a rotated grid in an ESRI ASCII grid"));
    }
    let dy = -minus_dy;
    let south = north - dy * field.height() as f64;
    // The .prj's linear unit is the heights' unit to a reader of the grid.
    let unit = georeference.linear_unit().map_or(LengthUnit::Metre, |(unit, _)| unit);
    let field = in_unit(field, height_unit, unit, path, notes)?;
    let geometry = GridGeometry { dx, dy, origin: DVec2::new(west, south), ..*field.geometry() };
    let field =
        field.with_geometry(geometry).map_err(|e| IoError::invalid_data(path, e.to_string()))?;
    crate::asc::grid::write_asc(path, &field)?;
    write_prj(path, georeference, notes)
}

/// Writes the `.prj` beside `path` with the ESRI WKT of `georeference`'s CRS, or notes why
/// it cannot.
fn write_prj(
    path: &Path,
    georeference: &Georeference,
    notes: &mut WriteNotes,
) -> Result<(), IoError> {
    let prj = prj_path(path);
    match georeference.esri_wkt() {
        Ok(wkt) => {
            write_text(&prj, &wkt)?;
            notes.push(format!("wrote {} ({})", prj.display(), georeference.crs_name()));
        }
        Err(why) => notes.push(format!(
            "no {} written: {why}; the file is placed but names no CRS",
            prj.display()
        )),
    }
    Ok(())
}

/// Writes the CRS of an image placed by a world file: a `.prj` and, as GDAL reads an image's
/// CRS from its `.aux.xml` rather than a `.prj`, a `.aux.xml` with the same WKT; or notes why
/// it cannot.
pub(crate) fn write_image_crs(
    path: &Path,
    georeference: &Georeference,
    notes: &mut WriteNotes,
) -> Result<(), IoError> {
    write_prj(path, georeference, notes)?;
    if let Ok(wkt) = georeference.esri_wkt() {
        let aux = aux_xml_path(path);
        let xml = format!("<PAMDataset>\n  <SRS>{}</SRS>\n</PAMDataset>\n", xml_text(&wkt));
        write_text(&aux, &xml)?;
        notes.push(format!("wrote {} (the CRS, for GDAL)", aux.display()));
    }
    Ok(())
}

/// `text` with the characters XML reserves escaped.
fn xml_text(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// Writes `text` to `path` atomically.
fn write_text(path: &Path, text: &str) -> Result<(), IoError> {
    crate::atomic_write::write_atomically(path, |out| {
        std::io::Write::write_all(out, text.as_bytes()).map_err(|e| IoError::io(path, e))
    })
}
