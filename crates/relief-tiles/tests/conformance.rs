//! The tiled terrain through relief-trace's tracer conformance suite: each of the suite's
//! terrains is written to a tile store in a temporary directory, opened, and traced as the
//! streamer's terrain at full resolution, against the suite's brute force.

use relief_core::{Camera, HeightField, Surface};
use relief_io::{Format, InMemoryRows, Raster, RasterInfo};
use relief_tiles::{build_store, BuildOptions, FrameRequest, Precision, TileStore, TileStreamer};
use relief_trace::conformance::Suite;
use relief_trace::Tracer;
use std::sync::atomic::{AtomicUsize, Ordering};

/// `field` as a raster (holes as NaN samples).
fn raster_of(field: &HeightField) -> Raster {
    let (w, h) = (field.width(), field.height());
    let samples = (0..w * h)
        .map(|i| if field.is_hole(i % w, i / w) { f32::NAN } else { field.samples()[i] })
        .collect();
    Raster {
        width: w,
        height: h,
        samples,
        geometry: *field.geometry(),
        info: RasterInfo {
            format: Format::Npy,
            sample_type: "float32".into(),
            georeferenced: false,
            from_degrees: None,
            nodata: None,
            georeference: None,
            height_unit: relief_io::HeightUnit::default(),
        },
    }
}

/// The tiled terrain of `field` in tiles of `tile` samples, all at full resolution.
fn tiled(field: &HeightField, surface: Surface, tile: u32) -> Option<Box<dyn Tracer>> {
    static STORES: AtomicUsize = AtomicUsize::new(0);
    let n = STORES.fetch_add(1, Ordering::Relaxed);
    let dir =
        std::env::temp_dir().join(format!("relief-tiles-conformance-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut rows = InMemoryRows::new(raster_of(field));
    let options = BuildOptions { tile, precision: Precision::F32, ..BuildOptions::default() };
    build_store(&mut rows, Vec::new(), &dir, &options, &|_, _| {}).expect("the store is built");
    let streamer =
        TileStreamer::new(TileStore::open(&dir).expect("the store opens"), surface, 1 << 30)
            .expect("the streamer starts");
    let bounds = field.world_bounds(Surface::Boxes);
    let camera = Camera::frame(&bounds, 64, 48).expect("a camera on the terrain");
    let request = FrameRequest { max_error_px: 0.0, cull: false, wait: true };
    let (terrain, _) = streamer.frame(&camera, request).expect("the frame's tiles load");
    let _ = std::fs::remove_dir_all(&dir);
    Some(Box::new(terrain))
}

/// The suite on the tiled terrain of `surface` only, in tiles of 8 and 16 samples.
fn check(surface: Surface) {
    for tile in [8, 16] {
        Suite::new()
            .terrains(24)
            .run(|field, s| if s == surface { tiled(field, s, tile) } else { None })
            .assert_conforms();
    }
}

#[test]
fn tiled_boxes_conform() {
    check(Surface::Boxes);
}

/// Once found by the suite: walls the whole field does not have (from the ring's repeated
/// edge samples beside holes, and over fields one sample wide), a flat terrain's top missed
/// (its tiles' boxes have no height), and batches that differed from single rays beside holes.
#[test]
fn tiled_triangles_conform() {
    check(Surface::Triangles);
}
