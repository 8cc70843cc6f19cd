//! Where an ortho photo lies over a DEM: which of its pixels the store keeps and where they
//! fall in the store's world, or why the photo cannot be draped over the DEM.
//!
//! A photo without a georeference (a PNG, a TIFF without model tags) is taken to span the
//! DEM's extent exactly, its first row the northern edge. A georeferenced GeoTIFF must be in
//! the DEM's CRS and cover the DEM's extent (to half a photo pixel); the store keeps the
//! window of its pixels over the DEM. Both are mapped to the world through the DEM's own
//! georeference, so that a DEM in degrees, whose world is metres at its centre's latitude,
//! places the photo exactly where its degrees say.

use crate::TileError;
use relief_core::GridGeometry;
use relief_io::{Georeference, OrthoInfo};

/// Where a photo's kept pixels lie: the window of the file and its placement in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct TexturePlacement {
    /// The pixels kept: first column, first row (counted from the file's first row), columns,
    /// rows.
    pub window: [u64; 4],
    /// World (x, y) of the window's south-west corner.
    pub origin: [f64; 2],
    /// World width and height of one pixel.
    pub texel: [f64; 2],
    /// Whether the file's first row is its northernmost.
    pub north_up: bool,
}

/// The DEM a photo is draped over: its size, world placement and georeference as read.
#[derive(Debug, Clone, Copy)]
pub struct DemPlacement<'a> {
    /// Samples per row.
    pub width: u64,
    /// Rows.
    pub height: u64,
    /// The DEM's world placement (the store's geometry).
    pub geometry: GridGeometry,
    /// The DEM file's georeference, when it has one.
    pub georeference: Option<&'a Georeference>,
}

/// GTModelTypeGeoKey.
const MODEL_TYPE: u16 = 1024;
/// GeographicTypeGeoKey.
const GEOGRAPHIC_TYPE: u16 = 2048;
/// ProjectedCSTypeGeoKey.
const PROJECTED_TYPE: u16 = 3072;
/// The GeoKey value "user-defined".
const USER_DEFINED: &str = "32767";

/// Places the photo `ortho` over `dem`.
///
/// Errors ([`TileError::Invalid`], naming the photo): a georeferenced photo over a DEM without
/// one, a CRS other than the DEM's, a photo that does not overlap the DEM or covers only part
/// of it.
pub fn place_ortho(dem: &DemPlacement, ortho: &OrthoInfo) -> Result<TexturePlacement, TileError> {
    let name = ortho.path.display();
    let (w, h) = (ortho.width as u64, ortho.height as u64);
    let g = &dem.geometry;
    let Some(photo) = &ortho.georeference else {
        return Ok(TexturePlacement {
            window: [0, 0, w, h],
            origin: [g.origin.x, g.origin.y],
            texel: [dem.width as f64 * g.dx / w as f64, dem.height as f64 * g.dy / h as f64],
            north_up: true,
        });
    };
    let Some(own) = dem.georeference else {
        return Err(TileError::Invalid(format!(
            "--texture {name}: a georeferenced GeoTIFF, but the DEM has no georeference to place \
             it by; give a PNG (taken to span the DEM exactly) or a georeferenced DEM"
        )));
    };
    if let Some(reason) = crs_difference(own, photo) {
        return Err(TileError::Invalid(format!(
            "--texture {name}: its CRS differs from the DEM's ({reason}); reproject it to the \
             DEM's CRS first"
        )));
    }
    let d = own.geotransform;
    let p = photo.geotransform;
    // The DEM's extent in model coordinates, and in the photo's pixels (column, row from the
    // file's first row).
    let (x0, x1) = (d[0], d[0] + dem.width as f64 * d[1]);
    let (ya, yb) = (d[3], d[3] + dem.height as f64 * d[5]);
    // Pixel edges a rounding error away from the DEM's edge are taken as on it.
    let snap = |v: f64| if (v - v.round()).abs() < 1e-6 { v.round() } else { v };
    let (px0, px1) = sorted(snap((x0 - p[0]) / p[1]), snap((x1 - p[0]) / p[1]));
    let (py0, py1) = sorted(snap((ya - p[3]) / p[5]), snap((yb - p[3]) / p[5]));
    let (wf, hf) = (w as f64, h as f64);
    let extent = |lo: f64, hi: f64| format!("{lo:.1} to {hi:.1}");
    if px1 <= 0.0 || px0 >= wf || py1 <= 0.0 || py0 >= hf {
        return Err(TileError::Invalid(format!(
            "--texture {name}: the photo does not overlap the DEM (the DEM spans columns {} and \
             rows {} of the photo's {w} x {h} pixels)",
            extent(px0, px1),
            extent(py0, py1)
        )));
    }
    const SLACK: f64 = 0.5;
    if px0 < -SLACK || py0 < -SLACK || px1 > wf + SLACK || py1 > hf + SLACK {
        return Err(TileError::Invalid(format!(
            "--texture {name}: the photo covers only part of the DEM (the DEM spans columns {} \
             and rows {} of the photo's {w} x {h} pixels); give a photo that covers it all",
            extent(px0, px1),
            extent(py0, py1)
        )));
    }
    let c0 = px0.max(0.0).floor() as u64;
    let c1 = (px1.min(wf).ceil() as u64).max(c0 + 1);
    let r0 = py0.max(0.0).floor() as u64;
    let r1 = (py1.min(hf).ceil() as u64).max(r0 + 1);
    let north_up = p[5] < 0.0;
    // Model to world through the DEM's own placement.
    let world_x = |mx: f64| g.origin.x + (mx - d[0]) / d[1] * g.dx;
    let world_y = |my: f64| {
        let v = (my - d[3]) / d[5];
        if d[5] < 0.0 {
            g.origin.y + (dem.height as f64 - v) * g.dy
        } else {
            g.origin.y + v * g.dy
        }
    };
    let south_row = if north_up { r1 } else { r0 };
    Ok(TexturePlacement {
        window: [c0, r0, c1 - c0, r1 - r0],
        origin: [world_x(p[0] + c0 as f64 * p[1]), world_y(p[3] + south_row as f64 * p[5])],
        texel: [(p[1] / d[1]).abs() * g.dx, (p[5] / d[5]).abs() * g.dy],
        north_up,
    })
}

fn sorted(a: f64, b: f64) -> (f64, f64) {
    (a.min(b), a.max(b))
}

/// How two files' CRSs differ, `None` when they are the same: the same model type and EPSG
/// code when both name one, else the same CRS GeoKeys ([`Georeference::crs_keys`]).
fn crs_difference(dem: &Georeference, photo: &Georeference) -> Option<String> {
    let (a, b) = (dem.crs_keys(), photo.crs_keys());
    let key =
        |keys: &[(u16, String)], id: u16| keys.iter().find(|k| k.0 == id).map(|k| k.1.clone());
    let epsg = |keys: &[(u16, String)]| {
        let code = key(keys, PROJECTED_TYPE).or_else(|| key(keys, GEOGRAPHIC_TYPE));
        code.filter(|c| c != USER_DEFINED)
    };
    let describe = |keys: &[(u16, String)]| match (epsg(keys), key(keys, MODEL_TYPE).as_deref()) {
        (Some(code), _) => format!("EPSG:{code}"),
        (None, Some("2")) => "a user-defined geographic CRS".to_string(),
        (None, Some(_)) => "a user-defined projected CRS".to_string(),
        (None, None) if keys.is_empty() => "no CRS keys".to_string(),
        (None, None) => "a CRS without a model type".to_string(),
    };
    let same = match (epsg(&a), epsg(&b)) {
        (Some(x), Some(y)) => x == y && key(&a, MODEL_TYPE) == key(&b, MODEL_TYPE),
        _ => a == b,
    };
    (!same).then(|| format!("{} against the DEM's {}", describe(&b), describe(&a)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::DVec2;
    use std::path::PathBuf;

    fn dem_georeference() -> Georeference {
        // 100 x 50 samples of 2 m, north-west corner at (1000, 5100).
        Georeference::north_up_grid(1000.0, 5100.0, 2.0, 2.0)
    }

    fn dem(georeference: Option<&Georeference>) -> DemPlacement<'_> {
        DemPlacement {
            width: 100,
            height: 50,
            geometry: GridGeometry {
                dx: 2.0,
                dy: 2.0,
                z_scale: 1.0,
                origin: DVec2::new(1000.0, 5000.0),
            },
            georeference,
        }
    }

    fn photo(width: u32, height: u32, georeference: Option<Georeference>) -> OrthoInfo {
        OrthoInfo { path: PathBuf::from("photo.tif"), width, height, georeference }
    }

    #[test]
    fn a_photo_without_georeference_spans_the_dem() {
        let g = dem_georeference();
        let placed = place_ortho(&dem(Some(&g)), &photo(400, 100, None)).unwrap();
        assert_eq!(placed.window, [0, 0, 400, 100]);
        assert_eq!((placed.origin, placed.texel), ([1000.0, 5000.0], [0.5, 1.0]));
    }

    #[test]
    fn a_larger_photo_is_cut_to_the_dem() {
        let g = dem_georeference();
        // Half-metre pixels from (990, 5110): the DEM is columns 20..420, rows 20..220.
        let p = Georeference::north_up_grid(990.0, 5110.0, 0.5, 0.5);
        let placed = place_ortho(&dem(Some(&g)), &photo(500, 300, Some(p))).unwrap();
        assert_eq!(placed.window, [20, 20, 400, 200]);
        assert_eq!((placed.origin, placed.texel), ([1000.0, 5000.0], [0.5, 0.5]));
        assert!(placed.north_up);
    }

    #[test]
    fn photos_that_miss_the_dem_or_another_crs_are_refused() {
        let g = dem_georeference();
        let far = Georeference::north_up_grid(9000.0, 5110.0, 0.5, 0.5);
        let err = place_ortho(&dem(Some(&g)), &photo(500, 300, Some(far))).unwrap_err();
        assert!(err.to_string().contains("does not overlap"), "{err}");
        let part = Georeference::north_up_grid(1050.0, 5110.0, 0.5, 0.5);
        let err = place_ortho(&dem(Some(&g)), &photo(500, 300, Some(part))).unwrap_err();
        assert!(err.to_string().contains("covers only part"), "{err}");
        let mut wgs = Georeference::srtm_tile(45, 7, 1201);
        wgs.geotransform = [990.0, 0.5, 0.0, 5110.0, 0.0, -0.5];
        let err = place_ortho(&dem(Some(&g)), &photo(500, 300, Some(wgs))).unwrap_err();
        assert!(err.to_string().contains("EPSG:4326"), "{err}");
        let p = Georeference::north_up_grid(990.0, 5110.0, 0.5, 0.5);
        let err = place_ortho(&dem(None), &photo(500, 300, Some(p))).unwrap_err();
        assert!(err.to_string().contains("DEM has no georeference"), "{err}");
    }
}
