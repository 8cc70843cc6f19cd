//! Rasters larger than memory from the command line: `relief generate fbm -o x.tif` written
//! band by band is the file the whole-raster writer made; `relief tile` reads a mosaic of
//! SRTM tiles, and refuses inputs that do not make one.

mod common;

use common::{assert_refused, relief, scratch, stdout_of};
use relief_core::{GridGeometry, HeightField};
use relief_sim::{fbm_terrain, FbmParams};
use std::path::Path;

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

#[test]
fn streamed_fbm_geotiffs_are_the_whole_raster_files_byte_for_byte() {
    // 300 wide: strips of 218 rows; bands of 300 rows do not line up with them.
    for (size, seed) in [(1, 3), (37, 5), (300, 7)] {
        let streamed = scratch(&format!("streamed-{size}.tif"));
        let seed_text = seed.to_string();
        let args = ["generate", "fbm", "--size", &size.to_string(), "--seed", &seed_text];
        let out = relief(&[&args[..], &["-o", p(&streamed)]].concat());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let field = fbm_terrain(size, size, seed, &FbmParams::for_size(size, size)).unwrap();
        let whole = scratch(&format!("whole-{size}.tif"));
        relief_io::write_geotiff(&whole, &field).unwrap();
        assert!(std::fs::read(&streamed).unwrap() == std::fs::read(&whole).unwrap(), "{size}");
    }
}

#[test]
fn a_mosaic_of_srtm_tiles_is_tiled_and_mixed_inputs_are_refused() {
    let n = 1201;
    let field = |base: f32| {
        let samples = (0..n * n).map(|i| base + (i % 997) as f32).collect();
        HeightField::new(n, n, samples, GridGeometry::unit()).unwrap()
    };
    let (west, east) = (scratch("N10E020.hgt"), scratch("N10E021.hgt"));
    relief_io::write_hgt(&west, &field(0.0)).unwrap();
    relief_io::write_hgt(&east, &field(1000.0)).unwrap();
    let store = scratch("mosaic store");
    let _ = std::fs::remove_dir_all(&store);
    let out = relief(&["tile", p(&west), p(&east), "-o", p(&store), "--tile", "512"]);
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && text.contains("2401 x 1201"), "{text}");
    let info = stdout_of(&relief(&["info", p(&store)]));
    assert!(info.contains("2401"), "{info}");

    let tif = scratch("mosaic-dem.tif");
    stdout_of(&relief(&["generate", "fbm", "--size", "20", "-o", p(&tif)]));
    let refused = scratch("refused store");
    let out = relief(&["tile", p(&west), p(&tif), "-o", p(&refused)]);
    assert_refused(&out, "one kind");
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(text.contains("N10E020.hgt") && text.contains("mosaic-dem.tif"), "{text}");
}
