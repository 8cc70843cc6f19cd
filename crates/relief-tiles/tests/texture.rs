//! A store's texture pyramid: rendered at error 0 with bilinear filtering of level 0, a
//! textured store gives the colours of the photo itself sampled at each hit; anisotropic
//! filtering averages a fine pattern seen at a grazing angle; damaged texture tiles are named;
//! a store without a texture opens as before.

use relief_core::texture::{
    pixel_ground_footprint, FootprintAlbedo, GroundFootprint, TextureFilter,
};
use relief_core::{Camera, DVec2, DVec3, GridGeometry, Projection, Surface};
use relief_io::{Format, InMemoryRows, IoError, OrthoInfo, OrthoRows, Raster, RasterInfo};
use relief_shade::{render_gbuffer, RgbTexture};
use relief_tiles::{
    build_store, build_textured_store, BuildOptions, FrameRequest, SourceFile, TextureInput,
    TexturePlacement, TextureStore, TextureStreamer, TileStore, TileStreamer,
};
use std::path::{Path, PathBuf};
use std::sync::Arc;

const DEM: (usize, usize) = (96, 64);
const PHOTO: (u32, u32) = (192, 128);

fn raster() -> Raster {
    let (w, h) = DEM;
    let samples = (0..w * h)
        .map(|k| {
            let (c, r) = ((k % w) as f32, (k / w) as f32);
            (c * 0.15).sin() * 4.0 + (r * 0.2).cos() * 3.0 + r * 0.1
        })
        .collect();
    Raster {
        width: w,
        height: h,
        samples,
        geometry: GridGeometry { dx: 10.0, dy: 10.0, z_scale: 1.0, origin: DVec2::new(0.0, 0.0) },
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

/// A photo in memory, served row by row from its top (north) row.
struct Photo {
    info: OrthoInfo,
    rgb: Vec<u8>,
    next: usize,
}

impl OrthoRows for Photo {
    fn info(&self) -> &OrthoInfo {
        &self.info
    }
    fn read_next_row(&mut self, out: &mut [[u8; 3]]) -> Result<(), IoError> {
        let w = self.info.width as usize;
        for (o, p) in out.iter_mut().zip(self.rgb[self.next * w * 3..].chunks_exact(3)) {
            *o = [p[0], p[1], p[2]];
        }
        self.next += 1;
        Ok(())
    }
}

/// Checks of 2 x 2 photo pixels in two colours, with a smooth ramp over them.
fn photo_pixels() -> Vec<u8> {
    let (w, h) = PHOTO;
    (0..w * h)
        .flat_map(|k| {
            let (c, r) = (k % w, k / w);
            let on = (c / 2 + r / 2) % 2 == 0;
            let ramp = (c * 255 / w) as u8;
            if on {
                [230, ramp, 40]
            } else {
                [20, 60, 255 - ramp]
            }
        })
        .collect()
}

fn temp(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("relief-tiles-texture-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn build(dir: &Path) {
    let (w, h) = PHOTO;
    let mut photo = Photo {
        info: OrthoInfo { path: "photo.png".into(), width: w, height: h, georeference: None },
        rgb: photo_pixels(),
        next: 0,
    };
    let raster = raster();
    let dem = relief_tiles::DemPlacement {
        width: DEM.0 as u64,
        height: DEM.1 as u64,
        geometry: raster.geometry,
        georeference: None,
    };
    let placement: TexturePlacement = relief_tiles::place_ortho(&dem, photo.info()).unwrap();
    let texture = TextureInput {
        rows: &mut photo,
        placement,
        source: SourceFile { path: "photo.png".into(), bytes: 1, modified_ns: 2 },
    };
    let mut rows = InMemoryRows::new(raster);
    let sources = vec![SourceFile { path: "dem.npy".into(), bytes: 3, modified_ns: 4 }];
    let options = BuildOptions { tile: 16, ..BuildOptions::default() };
    let report =
        build_textured_store(&mut rows, sources, Some(texture), dir, &options, &|_, _| {}).unwrap();
    assert!(report.texture_tiles > 0 && report.texture_built <= report.texture_tiles);
}

/// A view across the terrain from the south-west, low over it.
fn camera() -> Camera {
    Camera::new(
        DVec3::new(-100.0, -120.0, 90.0),
        DVec3::new(500.0, 400.0, 0.0),
        DVec3::Z,
        Projection::Perspective { fov_deg: 50.0 },
        120,
        80,
    )
    .unwrap()
}

#[test]
fn at_error_0_bilinear_level_0_is_the_photo_sampled_at_each_hit() {
    let dir = temp("exact");
    build(&dir);
    let store = TileStore::open(&dir).unwrap();
    let texture = TextureStore::open(&dir, store.header()).unwrap().expect("a texture");
    let bounds = store.world_bounds(Surface::Triangles);
    let streamer = TileStreamer::new(store, Surface::Triangles, 64 << 20).unwrap();
    let camera = camera();
    let request = FrameRequest { max_error_px: 0.0, cull: true, wait: true };
    let (terrain, _) = streamer.frame(&camera, request).unwrap();
    let (gbuffer, _) = render_gbuffer(&terrain, &camera, &bounds, &|_| {}).unwrap();
    let terrain = Arc::new(terrain);
    let textures = TextureStreamer::new(texture, 64 << 20).unwrap();
    let (frame, stats) =
        textures.frame(&gbuffer, &camera, terrain.clone(), TextureFilter::Bilinear, true).unwrap();
    assert_eq!(stats.min_level, 0);
    assert!(stats.tiles > 1, "{stats:?}");
    let (w, h) = PHOTO;
    let photo = RgbTexture::from_srgb8(w as usize, h as usize, &photo_pixels()).unwrap();
    let (extent_x, extent_y) = (DEM.0 as f64 * 10.0, DEM.1 as f64 * 10.0);
    let mut hits = 0;
    for j in 0..camera.height() {
        for i in 0..camera.width() {
            let d = gbuffer.distance[(i + j * camera.width()) as usize] as f64;
            if !d.is_finite() {
                continue;
            }
            hits += 1;
            let at = camera.ray(i, j).at(d);
            let want = photo.sample_bilinear(at.x / extent_x, at.y / extent_y);
            let got = frame.albedo(&GroundFootprint::point(at));
            assert!((got - want).abs().max_element() < 1e-6, "pixel ({i}, {j}): {got} {want}");
        }
    }
    assert!(hits > 1000, "{hits} hits");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn anisotropic_filtering_averages_the_checks_far_away() {
    let dir = temp("aniso");
    build(&dir);
    let store = TileStore::open(&dir).unwrap();
    let texture = TextureStore::open(&dir, store.header()).unwrap().expect("a texture");
    let bounds = store.world_bounds(Surface::Triangles);
    let streamer = TileStreamer::new(store, Surface::Triangles, 64 << 20).unwrap();
    let camera = camera();
    let request = FrameRequest { max_error_px: 0.0, cull: true, wait: true };
    let (terrain, _) = streamer.frame(&camera, request).unwrap();
    let (gbuffer, _) = render_gbuffer(&terrain, &camera, &bounds, &|_| {}).unwrap();
    let terrain = Arc::new(terrain);
    let textures = TextureStreamer::new(texture, 64 << 20).unwrap();
    let filters = [TextureFilter::Bilinear, TextureFilter::Anisotropic { max_anisotropy: 16 }];
    // The red channel of the far pixels (beyond 60% of the farthest hit): the checks
    // alternate 230 and 20, so bilinear samples spread, filtered ones gather near the mean.
    let far = 0.6 * gbuffer.distance.iter().filter(|d| d.is_finite()).fold(0f32, |a, &d| a.max(d));
    let spread = filters.map(|filter| {
        let (frame, _) = textures.frame(&gbuffer, &camera, terrain.clone(), filter, true).unwrap();
        let mut reds = Vec::new();
        for j in 0..camera.height() {
            for i in 0..camera.width() {
                let d = gbuffer.distance[(i + j * camera.width()) as usize];
                if d.is_nan() || d <= far {
                    continue;
                }
                let footprint =
                    pixel_ground_footprint(&gbuffer, &camera, i, j, &|p| frame.tangent_slope(p));
                if let Some(footprint) = footprint {
                    reds.push(frame.albedo(&footprint).x);
                }
            }
        }
        assert!(reds.len() > 200, "{} far pixels", reds.len());
        let mean = reds.iter().sum::<f64>() / reds.len() as f64;
        (reds.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / reds.len() as f64).sqrt()
    });
    assert!(spread[1] < 0.3 * spread[0], "standard deviations {spread:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_interrupted_texture_build_resumes_into_the_same_store() {
    let whole = temp("whole");
    build(&whole);
    let resumed = temp("resumed");
    build(&resumed);
    // What a build killed in the texture's coarse levels leaves: the index not complete, the
    // last texture records unwritten (their slots may hold anything).
    let index = resumed.join("index.json");
    let text = std::fs::read_to_string(&index).unwrap();
    std::fs::write(&index, text.replace("\"complete\": true", "\"complete\": false")).unwrap();
    let table = resumed.join("texture.table");
    let mut records = std::fs::read(&table).unwrap();
    let n = records.len();
    records[n - 16 * 6..].fill(0);
    std::fs::write(&table, &records).unwrap();
    let data = resumed.join("texture.data");
    let mut bytes = std::fs::read(&data).unwrap();
    let end = bytes.len();
    bytes[end - 500..].fill(7);
    std::fs::write(&data, &bytes).unwrap();
    assert!(matches!(TileStore::open(&resumed), Err(relief_tiles::TileError::Incomplete { .. })));
    build(&resumed);
    for name in ["index.json", "tiles.table", "tiles.data", "texture.table", "texture.data"] {
        let same =
            std::fs::read(whole.join(name)).unwrap() == std::fs::read(resumed.join(name)).unwrap();
        assert!(same, "{name} differs");
    }
    std::fs::remove_dir_all(&whole).unwrap();
    std::fs::remove_dir_all(&resumed).unwrap();
}

#[test]
fn a_damaged_texture_tile_is_named_and_a_store_without_texture_opens() {
    let dir = temp("damaged");
    build(&dir);
    let data = dir.join("texture.data");
    let mut bytes = std::fs::read(&data).unwrap();
    bytes[100] ^= 0x40; // the first tile of level 0
    std::fs::write(&data, &bytes).unwrap();
    let store = TileStore::open(&dir).unwrap();
    let texture = TextureStore::open(&dir, store.header()).unwrap().unwrap();
    let err = texture.load(relief_tiles::TileId { level: 0, col: 0, row: 0 }).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("texture.data") && text.contains("tile (level 0, column 0, row 0)"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).unwrap();

    let plain = temp("plain");
    let mut rows = InMemoryRows::new(raster());
    let sources = vec![SourceFile { path: "dem.npy".into(), bytes: 3, modified_ns: 4 }];
    let options = BuildOptions { tile: 16, ..BuildOptions::default() };
    build_store(&mut rows, sources, &plain, &options, &|_, _| {}).unwrap();
    let index = std::fs::read_to_string(plain.join("index.json")).unwrap();
    assert!(!index.contains("texture"), "{index}");
    let store = TileStore::open(&plain).unwrap();
    assert!(TextureStore::open(&plain, store.header()).unwrap().is_none());
    std::fs::remove_dir_all(&plain).unwrap();
}

/// A frame that does not wait loads no texture tile itself: coarser ones stand in, the tiles
/// arrive in the background, and later frames are the frame that waited.
#[test]
fn frames_that_do_not_wait_refine_as_texture_tiles_arrive() {
    let dir = temp("nowait");
    build(&dir);
    let store = TileStore::open(&dir).unwrap();
    let texture = || TextureStore::open(&dir, store.header()).unwrap().expect("a texture");
    let bounds = store.world_bounds(Surface::Triangles);
    let camera = camera();
    let streamer =
        TileStreamer::new(TileStore::open(&dir).unwrap(), Surface::Triangles, 64 << 20).unwrap();
    let request = FrameRequest { max_error_px: 0.0, cull: true, wait: true };
    let (terrain, _) = streamer.frame(&camera, request).unwrap();
    let (gbuffer, _) = render_gbuffer(&terrain, &camera, &bounds, &|_| {}).unwrap();
    let terrain = Arc::new(terrain);
    let filter = TextureFilter::Bilinear;
    let colours = |frame: &relief_tiles::TexturedFrame| -> Vec<DVec3> {
        let hits = gbuffer.distance.iter().enumerate().filter(|(_, d)| d.is_finite());
        let at = |k: usize| {
            let (i, j) = (k as u32 % camera.width(), k as u32 / camera.width());
            camera.ray(i, j).at(gbuffer.distance[k] as f64)
        };
        hits.map(|(k, _)| frame.albedo(&GroundFootprint::point(at(k)))).collect()
    };
    let waited = TextureStreamer::new(texture(), 64 << 20).unwrap();
    let (frame, _) = waited.frame(&gbuffer, &camera, terrain.clone(), filter, true).unwrap();
    let want = colours(&frame);

    let streamer = TextureStreamer::new(texture(), 64 << 20).unwrap();
    let (frame, stats) = streamer.frame(&gbuffer, &camera, terrain.clone(), filter, false).unwrap();
    assert_eq!(stats.tiles_loaded, 0, "{stats:?}");
    assert!(colours(&frame) != want, "the first frame is drawn from coarser tiles");
    let mut refined = false;
    for _ in 0..200 {
        let (frame, stats) =
            streamer.frame(&gbuffer, &camera, terrain.clone(), filter, false).unwrap();
        assert_eq!(stats.tiles_loaded, 0);
        if colours(&frame) == want {
            refined = true;
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(refined, "later frames draw the tiles loaded in the background");
    std::fs::remove_dir_all(&dir).unwrap();
}
