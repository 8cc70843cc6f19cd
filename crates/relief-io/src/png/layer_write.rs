//! Writing one layer as a 16-bit greyscale PNG, with an ESRI world file beside it that places
//! it (QGIS and GDAL read it).

use crate::atomic_write::write_atomically;
use crate::png::write::write_png_gray16;
use crate::{world_file_path, Georeference, IoError};
use std::io::Write;
use std::path::Path;

/// Writes a `width x height` layer of `samples` (row-major, row 0 south) to `path` as a
/// 16-bit greyscale PNG, with a world file beside it when `georeference` is given.
///
/// - Values: 0..1 maps to 0..65535 (rounded; values outside are clamped); voids (NaN) are
///   written as 0, as black as a value of 0: a PNG has no nodata.
/// - Rows: north-up, the grid's last row first, unless the georeference says its file was
///   south-up.
/// - World file: the six-line ESRI world file of the georeference (see
///   [`Georeference::world_file`]) at [`world_file_path`]`(path)` (`shade.png` →
///   `shade.pgw`), written atomically after the image; with the CRS's ESRI WKT, where relief
///   can write it ([`Georeference::esri_wkt`]), in a `.prj` and a `.png.aux.xml` (where GDAL
///   reads a PNG's CRS).
///
/// Errors: [`IoError::InvalidData`] for an empty image or `samples` of the wrong length,
/// [`IoError::Unsupported`] for a side longer than 2^32 - 1, [`IoError::Io`] when writing
/// fails.
pub fn write_layer_png(
    path: &Path,
    samples: &[f32],
    width: usize,
    height: usize,
    georeference: Option<&Georeference>,
) -> Result<(), IoError> {
    let (Ok(w), Ok(h)) = (u32::try_from(width), u32::try_from(height)) else {
        return Err(IoError::unsupported(
            path,
            format!("{width} x {height} pixels in a PNG (at most 2^32 - 1 a side)"),
        ));
    };
    if width.checked_mul(height) != Some(samples.len()) || samples.is_empty() {
        return Err(IoError::invalid_data(
            path,
            format!(
                "a {width} x {height} layer needs {} samples, got {}",
                width as u128 * height as u128,
                samples.len()
            ),
        ));
    }
    let south_up = georeference.is_some_and(Georeference::is_south_up);
    let mut grey = Vec::with_capacity(samples.len());
    for file_row in 0..height {
        let row = if south_up { file_row } else { height - 1 - file_row };
        grey.extend(samples[row * width..][..width].iter().map(|&v| grey_level(v)));
    }
    write_png_gray16(path, w, h, &grey)?;
    if let Some(georeference) = georeference {
        let world = world_file_path(path);
        write_atomically(&world, |out| {
            out.write_all(georeference.world_file().as_bytes()).map_err(|e| IoError::io(&world, e))
        })?;
        crate::write::write_image_crs(path, georeference, &mut Vec::new())?;
    }
    Ok(())
}

/// The 16-bit grey level of a layer value: 0..1 to 0..65535, clamped, NaN as 0.
fn grey_level(value: f32) -> u16 {
    if value.is_nan() {
        0
    } else {
        (value.clamp(0.0, 1.0) * 65535.0).round() as u16
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;

    #[test]
    fn grey_levels_and_world_file_names() {
        assert_eq!(grey_level(0.0), 0);
        assert_eq!(grey_level(1.0), 65535);
        assert_eq!(grey_level(0.5), 32768);
        assert_eq!((grey_level(-3.0), grey_level(7.0), grey_level(f32::NAN)), (0, 65535, 0));
        assert_eq!(world_file_path(Path::new("a.tif")), Path::new("a.tfw"));
        assert_eq!(world_file_path(Path::new("a.PNG")), Path::new("a.PGw"));
        assert_eq!(world_file_path(Path::new("a")), Path::new("a.wld"));
    }

    #[test]
    fn png_rows_run_north_first_with_a_world_file() {
        let dir = TestDir::new("layer-png");
        let path = dir.path().join("shade.png");
        let georeference = Georeference::north_up_grid(100.0, 200.0, 10.0, 5.0);
        // Row 0 (south) is 0 and NaN, row 1 (north) is 1 and 0.5.
        write_layer_png(&path, &[0.0, f32::NAN, 1.0, 0.5], 2, 2, Some(&georeference)).unwrap();
        let image = crate::png::height::read_png_height(&path, &Default::default()).unwrap();
        // The PNG reader flips rows back: row 0 south.
        assert_eq!(image.samples, [0.0, 0.0, 65535.0, 32768.0]);
        let world = std::fs::read_to_string(world_file_path(&path)).unwrap();
        assert_eq!(world, "10\n0\n0\n-5\n105\n197.5\n");
        let err = write_layer_png(&path, &[0.0; 3], 2, 2, None).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    }
}
