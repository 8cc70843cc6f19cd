//! A tiled terrain nests whatever tracer its store's factory makes for each tile: the tracer
//! given is the one traced (one ray at a time and in batches), and the hits are those of the
//! default max-mipmap leaves, or of the untiled raster for leaves of another exact tracer.

use relief_core::{Camera, DVec2, GridGeometry, Ray, Surface};
use relief_io::{Format, InMemoryRows, Raster, RasterInfo, VoidPolicy};
use relief_tiles::{
    build_store, BuildOptions, FrameRequest, TileStore, TileStreamer, TileTracerFactory,
    TiledTerrain,
};
use relief_trace::{Hit, MipmapTracer, Tracer, TracerKind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Hills and a ridge over 90 x 70 samples.
fn hills() -> Raster {
    let (width, height) = (90, 70);
    let samples = (0..width * height)
        .map(|k| {
            let (x, y) = ((k % width) as f32, (k / width) as f32);
            8.0 * (x * 0.13).sin() * (y * 0.11).cos()
                + 0.2 * y
                + 5.0 * (-(x - 45.0).abs() / 4.0).exp()
        })
        .collect();
    let info = RasterInfo {
        format: Format::Npy,
        sample_type: "float32".into(),
        georeferenced: false,
        from_degrees: None,
        nodata: None,
        georeference: None,
        height_unit: relief_io::HeightUnit::default(),
    };
    let geometry = GridGeometry { dx: 1.0, dy: 1.25, z_scale: 1.5, origin: DVec2::new(10.0, -5.0) };
    Raster { width, height, samples, geometry, info }
}

/// A store of `raster` in 16-sample tiles, in a fresh directory named `name`.
fn store_of(raster: &Raster, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-tiles-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let options = BuildOptions { tile: 16, ..BuildOptions::default() };
    build_store(&mut InMemoryRows::new(raster.clone()), Vec::new(), &dir, &options, &|_, _| {})
        .unwrap();
    dir
}

/// A frame's terrain at level 0 everywhere, its tiles traced by `tile_tracers`.
fn terrain(dir: &Path, tile_tracers: TileTracerFactory, camera: &Camera) -> TiledTerrain {
    let store = TileStore::open(dir).unwrap().with_tile_tracers(tile_tracers);
    let streamer = TileStreamer::new(store, Surface::Triangles, 1 << 30).unwrap();
    let request = FrameRequest { max_error_px: 0.0, cull: false, wait: true };
    let (terrain, stats) = streamer.frame(camera, request).unwrap();
    assert!(stats.tiles_drawn > 4, "the view crosses seams: {stats:?}");
    terrain
}

/// Counts the rays its max-mipmap tracer is asked about, keeping only the one-ray methods (so
/// batches reach it through the trait's default, ray by ray).
struct Counting {
    inner: MipmapTracer,
    rays: Arc<AtomicU64>,
}

impl Tracer for Counting {
    fn name(&self) -> &'static str {
        "counting"
    }

    fn surface(&self) -> Surface {
        self.inner.surface()
    }

    fn bounds(&self) -> relief_core::Aabb {
        self.inner.bounds()
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        self.rays.fetch_add(1, Ordering::Relaxed);
        self.inner.intersect_counted(ray, steps)
    }

    fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
        self.rays.fetch_add(1, Ordering::Relaxed);
        self.inner.occluded_counted(ray, steps)
    }
}

/// Every pixel's ray of `camera`.
fn rays(camera: &Camera) -> Vec<Ray> {
    (0..camera.height()).flat_map(|j| (0..camera.width()).map(move |i| camera.ray(i, j))).collect()
}

/// The first hits of `rays` through `tracer`'s batches.
fn batch_hits(tracer: &dyn Tracer, rays: &[Ray]) -> Vec<Option<Hit>> {
    let mut hits = vec![None; rays.len()];
    tracer.intersect_batch(rays, &mut hits, &mut vec![0; rays.len()]);
    hits
}

#[test]
fn the_factorys_tracer_is_traced_and_gives_the_default_leaves_hits() {
    let raster = hills();
    let dir = store_of(&raster, "nesting-counting");
    let field = raster.into_height_field(Path::new("hills"), VoidPolicy::Hole).unwrap();
    let camera = Camera::frame(&field.world_bounds(Surface::Triangles), 80, 60).unwrap();
    let rays = rays(&camera);
    let default = terrain(&dir, TileTracerFactory::default(), &camera);
    let count = Arc::new(AtomicU64::new(0));
    let counter = count.clone();
    let counting = TileTracerFactory::new("counting", move |field, surface| {
        let rays = counter.clone();
        Box::new(Counting { inner: MipmapTracer::new(field, surface), rays }) as Box<dyn Tracer>
    });
    assert_eq!(counting.description(), "counting");
    let nested = terrain(&dir, counting, &camera);
    let one_by_one: Vec<Option<Hit>> = rays.iter().map(|r| nested.intersect(r)).collect();
    let per_ray = count.swap(0, Ordering::Relaxed);
    let batched = batch_hits(&nested, &rays);
    let in_batches = count.swap(0, Ordering::Relaxed);
    assert!(per_ray >= rays.len() as u64 / 2, "{per_ray} leaf rays for {} rays", rays.len());
    assert!(in_batches >= rays.len() as u64 / 2, "{in_batches} leaf rays in batches");
    let expected: Vec<Option<Hit>> = rays.iter().map(|r| default.intersect(r)).collect();
    assert!(expected.iter().filter(|h| h.is_some()).count() > rays.len() / 4);
    assert_eq!(one_by_one, expected);
    assert_eq!(batched, expected);
    assert_eq!(batch_hits(&default, &rays), expected);
    let blocked: Vec<bool> = rays.iter().map(|r| nested.occluded(r)).collect();
    assert!(count.load(Ordering::Relaxed) > 0);
    assert_eq!(blocked, expected.iter().map(Option::is_some).collect::<Vec<_>>());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn naive_leaves_agree_with_the_untiled_raster() {
    let raster = hills();
    let dir = store_of(&raster, "nesting-naive");
    let field = Arc::new(raster.into_height_field(Path::new("hills"), VoidPolicy::Hole).unwrap());
    let camera = Camera::frame(&field.world_bounds(Surface::Triangles), 64, 48).unwrap();
    let naive = terrain(&dir, TileTracerFactory::of_kind(TracerKind::Naive), &camera);
    let whole = MipmapTracer::new(field, Surface::Triangles);
    let rays = rays(&camera);
    let mut hits = 0;
    for (ray, tiled) in rays.iter().zip(batch_hits(&naive, &rays)) {
        let want = whole.intersect(ray);
        assert_eq!(tiled.is_some(), want.is_some(), "{ray:?}: tiled {tiled:?}, whole {want:?}");
        if let (Some(a), Some(b)) = (tiled, want) {
            assert!((a.t - b.t).abs() <= 1e-5 * b.t, "{ray:?}: tiled {a:?}, whole {b:?}");
            hits += 1;
        }
    }
    assert!(hits > rays.len() / 4, "{hits} hits of {} rays", rays.len());
    std::fs::remove_dir_all(&dir).unwrap();
}
