//! `relief tile --texture` and `relief render STORE` of a textured store end to end: at error
//! 0 with bilinear filtering the store gives the picture of the raster rendered with the same
//! photo draped over it; a GeoTIFF photo larger than the DEM is cut to it by its
//! georeference; damaged texture tiles and photos that do not cover the DEM are refused with
//! one line, exit 2.

mod common;

use common::{assert_refused, relief, scratch, stdout_of};
use relief_io::{Georeference, ReadOptions};
use std::path::{Path, PathBuf};

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Photo pixels: checks of 3 x 3 pixels in two colours over a ramp, `border` pixels of grey
/// around them.
fn photo(width: u32, height: u32, border: u32) -> Vec<u8> {
    let (w, h) = (width + 2 * border, height + 2 * border);
    (0..w * h)
        .flat_map(|k| {
            let (c, r) = (k % w, k / w);
            if c < border || r < border || c >= width + border || r >= height + border {
                return [128, 128, 128];
            }
            let (c, r) = (c - border, r - border);
            let ramp = (r * 255 / height) as u8;
            if (c / 3 + r / 3) % 2 == 0 {
                [240, ramp, 30]
            } else {
                [10, 90, 255 - ramp]
            }
        })
        .collect()
}

/// A 100 x 100 fBm GeoTIFF, a PNG photo of 300 x 300 pixels over it, and the DEM's
/// georeference.
fn dem_and_photo(name: &str) -> (PathBuf, PathBuf, Georeference) {
    let tif = scratch(&format!("{name} dem.tif"));
    stdout_of(&relief(&["generate", "fbm", "--size", "100", "-o", p(&tif)]));
    let png = scratch(&format!("{name} photo.png"));
    relief_io::write_png_rgb8(&png, 300, 300, &photo(300, 300, 0)).unwrap();
    let raster = relief_io::read_raster(&tif, &ReadOptions::default()).unwrap();
    (tif, png, raster.info.georeference.expect("relief writes georeferenced GeoTIFFs"))
}

fn tile(dem: &Path, photo: &Path, store: &Path) {
    let _ = std::fs::remove_dir_all(store);
    let out = relief(&["tile", p(dem), "-o", p(store), "--tile", "32", "--texture", p(photo)]);
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && text.contains("the texture's"), "{text}");
}

fn render(input: &Path, name: &str, extra: &[&str]) -> Vec<u8> {
    let png = scratch(&format!("{name}.png"));
    let mut args = vec!["render", p(input), "-o", p(&png), "--size", "160x100"];
    args.extend(["--eye", "-30,-40,60", "--target", "60,70,0", "--surface", "boxes"]);
    args.extend(extra);
    stdout_of(&relief(&args));
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    buf
}

/// A georeference like `dem`'s (its CRS keys) with pixels of `size` from north-west corner
/// `(west, north)`.
fn placed_like(dem: &Georeference, west: f64, north: f64, size: f64) -> Georeference {
    let mut tags = dem.geotiff.clone();
    tags.model_pixel_scale = Some(vec![size, size, 0.0]);
    tags.model_tiepoint = Some(vec![0.0, 0.0, 0.0, west, north, 0.0]);
    tags.model_transformation = None;
    Georeference::from_geotiff_tags(tags).unwrap()
}

#[test]
fn a_textured_store_at_error_0_renders_the_draped_raster_and_a_larger_geotiff_is_cut() {
    let (dem, png, georeference) = dem_and_photo("drape");
    let store = scratch("drape store");
    tile(&dem, &png, &store);
    let info = stdout_of(&relief(&["info", p(&store)]));
    assert!(info.contains("texture:     300 x 300 texels"), "{info}");
    let plain = ["--no-shadows", "--voids", "hole"];
    let draped = render(&dem, "drape-raster", &[&plain[..], &["--texture", p(&png)]].concat());
    let bilinear = ["--no-shadows", "--max-error-px", "0", "--texture-filter", "bilinear"];
    let tiled = render(&store, "drape-store", &bilinear);
    // The raster's texture coordinates are f32; the store's placement is exact in f64.
    let differ = draped.iter().zip(&tiled).filter(|(a, b)| a != b).count();
    let worst = draped.iter().zip(&tiled).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
    assert!(worst <= 1 && differ * 200 < draped.len(), "{differ} bytes differ, by up to {worst}");
    // Anisotropic filtering (the default) changes the far checks.
    let filtered = render(&store, "drape-aniso", &["--no-shadows", "--max-error-px", "0"]);
    assert!(filtered != tiled);

    // The same photo inside a larger GeoTIFF, 7 grey pixels of a third of a texel each
    // around it: cut to the DEM by its georeference, the store renders the same picture.
    let [west, dx, _, north, _, dy] = georeference.geotransform;
    assert!(dy < 0.0 && (dx + dy).abs() < 1e-12, "square north-up texels");
    let pixel = dx * 100.0 / 300.0;
    let larger = scratch("drape larger.tif");
    let place = placed_like(&georeference, west - 7.0 * pixel, north + 7.0 * pixel, pixel);
    relief_io::write_rgb_geotiff(&larger, 314, 314, &photo(300, 300, 7), &place).unwrap();
    let cut = scratch("drape cut store");
    tile(&dem, &larger, &cut);
    assert!(render(&cut, "drape-cut", &bilinear) == tiled, "the GeoTIFF's store differs");
}

#[test]
fn damaged_texture_tiles_and_photos_off_the_dem_are_refused() {
    let (dem, png, georeference) = dem_and_photo("refused");
    let store = scratch("refused store");
    tile(&dem, &png, &store);
    let data = store.join("texture.data");
    let mut bytes = std::fs::read(&data).unwrap();
    bytes[200] ^= 0x08; // the first tile of level 0
    std::fs::write(&data, &bytes).unwrap();
    let out_png = scratch("refused.png");
    let out = relief(&["render", p(&store), "-o", p(&out_png), "--max-error-px", "0"]);
    assert_refused(&out, "tile (level 0, column 0, row 0)");
    assert_refused(&out, "texture.data");
    assert!(!out_png.exists());

    let [west, dx, _, north, _, _] = georeference.geotransform;
    let off = scratch("refused off.tif");
    let far = placed_like(&georeference, west + 1000.0 * dx, north, dx);
    relief_io::write_rgb_geotiff(&off, 50, 50, &photo(50, 50, 0), &far).unwrap();
    let elsewhere = scratch("refused elsewhere");
    let out = relief(&["tile", p(&dem), "-o", p(&elsewhere), "--texture", p(&off)]);
    assert_refused(&out, "does not overlap the DEM");
    let part = placed_like(&georeference, west + 50.0 * dx, north, dx);
    relief_io::write_rgb_geotiff(&off, 100, 100, &photo(100, 100, 0), &part).unwrap();
    let out = relief(&["tile", p(&dem), "-o", p(&elsewhere), "--texture", p(&off)]);
    assert_refused(&out, "covers only part of the DEM");

    // Texture options on a store without a texture.
    let bare = scratch("refused bare");
    let _ = std::fs::remove_dir_all(&bare);
    stdout_of(&relief(&["tile", p(&dem), "-o", p(&bare), "--tile", "32"]));
    let out = relief(&["render", p(&bare), "-o", p(&out_png), "--texture-filter", "bilinear"]);
    assert_refused(&out, "--texture-filter");
}
