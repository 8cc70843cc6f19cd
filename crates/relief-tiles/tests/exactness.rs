//! A store rendered at an error tolerance of 0 equals the untiled raster rendered whole: depth
//! to 1e-5 relative and the shaded picture, shadows included, from cameras looking across tile
//! seams; and coarser tolerances leave neither cracks nor holes.

use relief_core::{Camera, DVec2, DVec3, GridGeometry, HeightField, Surface};
use relief_io::{Format, InMemoryRows, Raster, RasterInfo, VoidPolicy};
use relief_shade::{render_gbuffer, shade_to_srgb8, GBuffer, ShadingNormals, ShadingParams};
use relief_tiles::{
    build_store, BuildOptions, FrameRequest, Precision, TileStore, TileStreamer, TiledTerrain,
};
use relief_trace::{MipmapTracer, Tracer};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A rough terrain with cliffs, and voids where `voids` says.
fn terrain(width: usize, height: usize, seed: u64, voids: bool) -> Raster {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64) as f32
    };
    let bumps: Vec<(f32, f32, f32, f32)> = (0..12)
        .map(|_| {
            (
                next() * width as f32,
                next() * height as f32,
                4.0 + 20.0 * next(),
                30.0 * next() - 8.0,
            )
        })
        .collect();
    let mut samples = Vec::with_capacity(width * height);
    for r in 0..height {
        for c in 0..width {
            let (x, y) = (c as f32, r as f32);
            let mut h = 3.0 * (x * 0.21).sin() * (y * 0.17).cos() + 0.5 * next();
            for &(bx, by, radius, amp) in &bumps {
                let d2 = ((x - bx).powi(2) + (y - by).powi(2)) / (radius * radius);
                h += amp * (-d2).exp();
            }
            if (c / 7 + r / 5) % 11 == 0 {
                h += 6.0; // cliffs
            }
            let hole = voids && ((c as i64 - 40).pow(2) + (r as i64 - 30).pow(2) < 30);
            samples.push(if hole { f32::NAN } else { h });
        }
    }
    Raster {
        width,
        height,
        samples,
        geometry: GridGeometry {
            dx: 2.0,
            dy: 1.5,
            z_scale: 1.25,
            origin: DVec2::new(-100.0, 40.0),
        },
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

fn temp_store(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-tiles-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn build(raster: &Raster, dir: &Path, tile: u32, precision: Precision) {
    let mut rows = InMemoryRows::new(raster.clone());
    let options = BuildOptions { tile, precision, ..BuildOptions::default() };
    build_store(&mut rows, Vec::new(), dir, &options, &|_, _| {}).unwrap();
}

fn cameras(bounds: &relief_core::Aabb) -> Vec<Camera> {
    let c = bounds.center();
    let size = bounds.max - bounds.min;
    let mut cams = Vec::new();
    for (k, (ex, ey, ez)) in
        [(-0.3, -0.4, 1.2), (1.2, 0.5, 0.3), (0.5, -0.2, 0.08), (0.2, 0.3, 0.6)]
            .into_iter()
            .enumerate()
    {
        let eye = DVec3::new(
            bounds.min.x + ex * size.x,
            bounds.min.y + ey * size.y,
            bounds.max.z + ez * size.x * 0.3,
        );
        let target = c + DVec3::new(0.1 * k as f64 * size.x, -0.05 * size.y, 0.0);
        cams.push(Camera::look_at(eye, target, DVec3::Z, 50.0, 96, 64).unwrap());
    }
    cams
}

fn compare(surface: Surface, voids: bool, tile: u32) {
    let raster = terrain(150, 110, 7 + tile as u64, voids);
    let dir = temp_store(&format!("exact-{surface:?}-{voids}-{tile}"));
    build(&raster, &dir, tile, Precision::F32);
    let field =
        Arc::new(raster.clone().into_height_field(Path::new("t"), VoidPolicy::Hole).unwrap());
    let whole = MipmapTracer::new(field.clone(), surface);
    let bounds = field.world_bounds(surface);
    let streamer = TileStreamer::new(TileStore::open(&dir).unwrap(), surface, 1 << 30).unwrap();
    assert_eq!(streamer.store().world_bounds(surface), bounds);
    let params = ShadingParams::for_terrain(&bounds).unwrap();
    for camera in cameras(&bounds) {
        let request = FrameRequest { max_error_px: 0.0, cull: false, wait: true };
        let (tiled, stats) = streamer.frame(&camera, request).unwrap();
        assert!(stats.tiles_drawn > 4, "the view crosses seams: {stats:?}");
        let (a, _) = render_gbuffer(&whole, &camera, &bounds, &|_| {}).unwrap();
        let (b, _) = render_gbuffer(&tiled, &camera, &bounds, &|_| {}).unwrap();
        let (da, db) = (a.depth_hw(), b.depth_hw());
        let mut hits = 0;
        for (k, (x, y)) in da.iter().zip(&db).enumerate() {
            if x.is_finite() {
                hits += 1;
            }
            let same = (x.is_infinite() && y.is_infinite() && x == y)
                || (x - y).abs() <= 1e-5 * x.abs().max(1.0);
            assert!(same, "{surface:?} pixel {k}: whole {x}, tiled {y}");
        }
        assert!(hits > 500, "the camera sees the terrain");
        // One ray at a time takes another path through the tiles: the same hits.
        for (k, d) in db.iter().enumerate().step_by(7) {
            let ray = camera.ray((k % 96) as u32, (k / 96) as u32);
            let single = tiled.intersect(&ray).map_or(f32::INFINITY, |h| h.t as f32);
            assert_eq!(single, *d, "pixel {k}: one ray {single}, batch {d}");
            assert_eq!(tiled.occluded(&ray), d.is_finite());
        }
        let (ia, _) = shade_to_srgb8(&a, &whole, &camera, &params).unwrap();
        let (ib, _) = shade_to_srgb8(&b, &tiled, &camera, &params).unwrap();
        let differ = ia.iter().zip(&ib).filter(|(p, q)| p != q).count();
        for (k, (p, q)) in ia.iter().zip(&ib).enumerate().filter(|(_, (p, q))| p != q) {
            eprintln!(
                "pixel {k}: {p:?} {q:?} normals {:?} {:?} depth {} {}",
                a.pixel(k).unwrap().normal,
                b.pixel(k).unwrap().normal,
                da[k],
                db[k]
            );
        }
        assert_eq!(differ, 0, "{surface:?}: {differ} shaded pixels differ (shadows)");
        if surface == Surface::Triangles {
            compare_smooth(&field, tiled, &camera, &params, [&a, &b]);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Smooth shading normals of the tiles (each from its own samples) light the picture as the
/// whole field's do, but for the pixels beside a seam, where a tile's one-sided differences
/// stand in for the whole field's central ones.
fn compare_smooth(
    field: &Arc<HeightField>,
    tiled: TiledTerrain,
    camera: &Camera,
    params: &ShadingParams,
    [whole, tiles]: [&GBuffer; 2],
) {
    let tiled = Arc::new(tiled);
    let lit = |normals| ShadingParams { normals, ..params.clone() };
    let smooth_whole = lit(ShadingNormals::smooth(field.clone()));
    let smooth_tiled = lit(ShadingNormals::smooth(tiled.clone()));
    let (ia, _) = shade_to_srgb8(whole, &*tiled, camera, &smooth_whole).unwrap();
    let (ib, _) = shade_to_srgb8(tiles, &*tiled, camera, &smooth_tiled).unwrap();
    let (faceted, _) = shade_to_srgb8(whole, &*tiled, camera, params).unwrap();
    let steps = |x: &[[u8; 3]], y: &[[u8; 3]]| {
        x.iter()
            .zip(y)
            .filter(|(p, q)| p.iter().zip(q.iter()).any(|(u, v)| u.abs_diff(*v) > 2))
            .count()
    };
    let (seams, smoothed) = (steps(&ia, &ib), steps(&ia, &faceted));
    eprintln!("smooth: {seams} pixels differ at seams, {smoothed} from faceted");
    assert!(smoothed > 200, "smooth normals change the picture: {smoothed}");
    assert!(seams * 10 < smoothed, "{seams} pixels differ beside seams, {smoothed} smoothed");
}

#[test]
fn level_0_tiles_render_the_whole_raster_triangles() {
    compare(Surface::Triangles, false, 16);
}

#[test]
fn level_0_tiles_render_the_whole_raster_boxes() {
    compare(Surface::Boxes, false, 16);
}

#[test]
fn level_0_tiles_render_the_whole_raster_with_voids() {
    compare(Surface::Triangles, true, 32);
    compare(Surface::Boxes, true, 32);
}

/// At any tolerance, every ray that reaches the terrain's column from above hits something:
/// where tiles of different levels meet there are neither cracks nor holes.
#[test]
fn mixed_levels_leave_no_holes() {
    let raster = terrain(150, 110, 3, false);
    let dir = temp_store("mixed");
    build(&raster, &dir, 8, Precision::F16);
    let surface = Surface::Triangles;
    let streamer = TileStreamer::new(TileStore::open(&dir).unwrap(), surface, 1 << 30).unwrap();
    let bounds = streamer.store().world_bounds(surface);
    let field = Arc::new(raster.into_height_field(Path::new("t"), VoidPolicy::Hole).unwrap());
    let whole = MipmapTracer::new(field, surface);
    for camera in cameras(&bounds) {
        for tolerance in [0.5, 2.0, 8.0, 50.0] {
            let request = FrameRequest { max_error_px: tolerance, cull: true, wait: true };
            let (tiled, _) = streamer.frame(&camera, request).unwrap();
            // Straight down onto every point of the domain: always a hit.
            for k in 0..400 {
                let (u, v) = ((k % 20) as f64 / 19.0, (k / 20) as f64 / 19.0);
                let x = bounds.min.x + 1e-6 + u * (bounds.max.x - bounds.min.x - 2e-6);
                let y = bounds.min.y + 1e-6 + v * (bounds.max.y - bounds.min.y - 2e-6);
                let ray = relief_core::Ray::new(DVec3::new(x, y, bounds.max.z + 10.0), -DVec3::Z);
                let Some(truth) = whole.intersect(&ray) else { continue };
                if relief_tiles::outside_view(
                    &camera,
                    &relief_core::Aabb::new(truth.position, truth.position),
                ) {
                    continue;
                }
                assert!(
                    tiled.intersect(&ray).is_some(),
                    "hole at ({x}, {y}) at tolerance {tolerance}"
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A store built from a mosaic of four SRTM tiles, at an error tolerance of 0, equals the
/// mosaic read whole, from cameras looking across the seams between the tiles (where two
/// .hgt files share their edge samples) and across tile seams, shadows included.
#[test]
fn a_mosaic_store_renders_the_mosaic_read_whole() {
    let side = 1201;
    let big = terrain(2 * side - 1, 2 * side - 1, 11, false);
    let dir = temp_store("mosaic");
    std::fs::create_dir_all(&dir).unwrap();
    let mut paths = Vec::new();
    for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
        // Tile (i, j): i rows of tiles north of the south-west one, j columns east.
        let (r0, c0) = (i * (side - 1), j * (side - 1));
        let samples = (0..side)
            .flat_map(|r| (0..side).map(move |c| (r0 + r, c0 + c)))
            .map(|(r, c)| 60.0 * big.samples[c + r * big.width])
            .collect();
        let field =
            relief_core::HeightField::new(side, side, samples, GridGeometry::unit()).unwrap();
        let path = dir.join(format!("N{:02}E{:03}.hgt", 36 + i, 7 + j));
        relief_io::write_hgt(&path, &field).unwrap();
        paths.push(path);
    }
    let options = relief_io::ReadOptions::default();
    let mut rows = relief_io::open_mosaic(&paths, &options).unwrap();
    let (width, height) = (rows.width(), rows.height());
    assert_eq!((width, height), (2 * side - 1, 2 * side - 1), "tiles share their edges");
    let mut samples = vec![0f32; width * height];
    rows.read_rows(0, &mut samples).unwrap();
    let whole =
        Raster { width, height, samples, geometry: rows.geometry(), info: rows.info().clone() };
    let store = dir.join("store");
    let options = BuildOptions { tile: 256, ..BuildOptions::default() };
    build_store(rows.as_mut(), Vec::new(), &store, &options, &|_, _| {}).unwrap();

    let surface = Surface::Triangles;
    let field = Arc::new(whole.into_height_field(Path::new("m"), VoidPolicy::Hole).unwrap());
    let tracer = MipmapTracer::new(field.clone(), surface);
    let bounds = field.world_bounds(surface);
    let streamer = TileStreamer::new(TileStore::open(&store).unwrap(), surface, 1 << 30).unwrap();
    let params = ShadingParams::for_terrain(&bounds).unwrap();
    let (c, size) = (bounds.center(), bounds.max - bounds.min);
    // Low over the seam between the western and eastern tiles, looking along it and across.
    let views = [
        (
            DVec3::new(
                c.x - 0.02 * size.x,
                bounds.min.y + 0.2 * size.y,
                bounds.max.z + 0.1 * size.x,
            ),
            c,
        ),
        (DVec3::new(c.x - 0.2 * size.x, c.y - 0.15 * size.y, bounds.max.z + 0.05 * size.x), c),
    ];
    for (eye, target) in views {
        let camera = Camera::look_at(eye, target, DVec3::Z, 40.0, 96, 64).unwrap();
        let request = FrameRequest { max_error_px: 0.0, cull: false, wait: true };
        let (tiled, stats) = streamer.frame(&camera, request).unwrap();
        assert!(stats.tiles_drawn > 8, "the view crosses seams: {stats:?}");
        let (a, _) = render_gbuffer(&tracer, &camera, &bounds, &|_| {}).unwrap();
        let (b, _) = render_gbuffer(&tiled, &camera, &bounds, &|_| {}).unwrap();
        let (da, db) = (a.depth_hw(), b.depth_hw());
        assert!(da.iter().filter(|d| d.is_finite()).count() > 1000, "the view sees the terrain");
        for (k, (x, y)) in da.iter().zip(&db).enumerate() {
            let same = (x.is_infinite() && x == y) || (x - y).abs() <= 1e-5 * x.abs().max(1.0);
            assert!(same, "pixel {k}: whole {x}, tiled {y}");
        }
        let (ia, _) = shade_to_srgb8(&a, &tracer, &camera, &params).unwrap();
        let (ib, _) = shade_to_srgb8(&b, &tiled, &camera, &params).unwrap();
        assert!(ia == ib, "the shaded pictures differ");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
