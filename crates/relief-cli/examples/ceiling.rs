//! How fast relief's primary-ray pipeline could be, whatever the tracer: the measurements
//! behind "Why not 5x" in docs/performance.md.
//!
//! On `relief bench`'s three views of a terrain (an `.npy` from `relief generate fbm`) at
//! 1920x1080, this renders the G-buffer (`render_gbuffer_into`, as `relief bench` does) with
//!
//! - `nothing`: a tracer that does no work and finds no hit: camera rays and G-buffer only;
//! - `answer known`: a tracer that looks up each ray's hit, computed beforehand: camera rays,
//!   one lookup and the G-buffer writes of the real hits;
//! - `mipmap`: the real tracer, in packets;
//!
//! and traces single rays with the mipmap tracer from the eye (`single rays`) and, for rays
//! that hit, from a start given by an oracle half a pixel's footprint before the hit
//! (`single rays, start known`): what a perfect lower bound on every ray's distance would buy.
//! Each figure is the fastest of five runs, in millions of rays per second (every pixel counts
//! as a ray, misses included, as in `relief bench`).
//!
//! ```sh
//! relief generate fbm --size 4096 -o fbm-4096.npy
//! cargo run --release -p relief-cli --example ceiling -- fbm-4096.npy
//! ```

use anyhow::{Context, Result};
use rayon::prelude::*;
use relief_core::{Camera, DVec3, HeightField, Ray, Surface};
use relief_shade::{render_gbuffer_into, GBuffer};
use relief_trace::{Hit, MipmapTracer, Tracer};
use std::sync::Arc;
use std::time::Instant;

/// Finds nothing, at no cost.
struct Nothing;

impl Tracer for Nothing {
    fn name(&self) -> &'static str {
        "nothing"
    }
    fn surface(&self) -> Surface {
        Surface::Triangles
    }
    fn intersect_counted(&self, _: &Ray, _: &mut u32) -> Option<Hit> {
        None
    }
    fn intersect_batch(&self, _: &[Ray], hits: &mut [Option<Hit>], _: &mut [u32]) {
        hits.fill(None);
    }
}

/// Returns the hit found beforehand for the pixel a camera ray goes through.
struct AnswerKnown {
    camera: Camera,
    right: DVec3,
    true_up: DVec3,
    tan_half: f64,
    hits: Vec<Option<Hit>>,
}

impl AnswerKnown {
    fn new(camera: &Camera, tracer: &dyn Tracer) -> Self {
        let (w, h) = (camera.width(), camera.height());
        let hits = (0..h)
            .into_par_iter()
            .flat_map_iter(|j| (0..w).map(move |i| tracer.intersect(&camera.ray(i, j))))
            .collect();
        let right = camera.forward().cross(camera.up()).normalize();
        AnswerKnown {
            camera: *camera,
            right,
            true_up: right.cross(camera.forward()),
            tan_half: (camera.fov_deg().to_radians() / 2.0).tan(),
            hits,
        }
    }
}

impl Tracer for AnswerKnown {
    fn name(&self) -> &'static str {
        "answer known"
    }
    fn surface(&self) -> Surface {
        Surface::Triangles
    }
    fn intersect_counted(&self, ray: &Ray, _: &mut u32) -> Option<Hit> {
        let (w, h) = (self.camera.width() as f64, self.camera.height() as f64);
        let depth = ray.dir.dot(self.camera.forward());
        let sx = ray.dir.dot(self.right) / depth;
        let sy = ray.dir.dot(self.true_up) / depth;
        let i = ((sx / (self.tan_half * w / h) + 1.0) * w / 2.0) as usize;
        let j = ((1.0 - sy / self.tan_half) * h / 2.0) as usize;
        self.hits[i + j * self.camera.width() as usize]
    }
}

/// `relief bench`'s views (see `commands/bench.rs`).
fn views(field: &HeightField, w: u32, h: u32) -> Result<Vec<(&'static str, Camera)>> {
    let bounds = field.world_bounds(Surface::Boxes);
    let size = bounds.max - bounds.min;
    let overview = Camera::frame_from(&bounds, 225.0, 30.0, 45.0, w, h)?;
    let (col, row) = (field.width() / 5, field.height() / 5);
    let ground = field.sample(col, row) as f64 * field.geometry().z_scale;
    let eye = DVec3::new(
        bounds.min.x + 0.2 * size.x,
        bounds.min.y + 0.2 * size.y,
        ground + 0.03 * size.x.max(size.y),
    );
    let target = DVec3::new(bounds.min.x + 0.8 * size.x, bounds.min.y + 0.8 * size.y, ground);
    let flight = Camera::look_at(eye, target, DVec3::Z, 60.0, w, h)?;
    let centre = bounds.center();
    let above = DVec3::new(centre.x, centre.y, bounds.max.z + 1.2 * size.x.max(size.y));
    let below = DVec3::new(centre.x, centre.y, bounds.min.z);
    let top_down = Camera::look_at(above, below, DVec3::Y, 45.0, w, h)?;
    Ok(vec![("three-quarter", overview), ("flight", flight), ("top-down", top_down)])
}

/// The shortest of five runs of `f`, in seconds.
fn fastest(mut f: impl FnMut()) -> f64 {
    (0..5)
        .map(|_| {
            let started = Instant::now();
            f();
            started.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() -> Result<()> {
    let path = std::env::args().nth(1).context("usage: ceiling TERRAIN.npy")?;
    let field = Arc::new(relief_io::read_npy_height_field(path.as_ref())?);
    let tracer = MipmapTracer::new(field.clone(), Surface::Triangles);
    let bounds = field.world_bounds(Surface::Triangles);
    let (w, h) = (1920, 1080);
    let rays = (w * h) as f64;
    println!(
        "{}x{} terrain, {w}x{h}, {} threads; Mrays/s",
        field.width(),
        field.height(),
        rayon::current_num_threads()
    );
    println!(
        "{:<14} {:>8} {:>13} {:>8} {:>12} {:>25}",
        "view", "nothing", "answer known", "mipmap", "single rays", "single rays, start known"
    );
    for (view, camera) in views(&field, w, h)? {
        let mut gbuffer = GBuffer::new(w as usize, h as usize)?;
        let mut render = |tracer: &dyn Tracer| {
            let s = fastest(|| {
                render_gbuffer_into(tracer, &camera, &bounds, &mut gbuffer, &|_| {})
                    .expect("the G-buffer has the camera's size");
            });
            rays / s / 1e6
        };
        let nothing = render(&Nothing);
        let answers = AnswerKnown::new(&camera, &tracer);
        let known = render(&answers);
        let mipmap = render(&tracer);
        let pixels: Vec<(u32, u32)> = (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).collect();
        let single = rays
            / fastest(|| {
                pixels.par_iter().for_each(|&(i, j)| {
                    std::hint::black_box(tracer.intersect(&camera.ray(i, j)));
                })
            })
            / 1e6;
        let footprint = 2.0 * (camera.fov_deg().to_radians() / 2.0).tan() / h as f64;
        let started_late = rays
            / fastest(|| {
                pixels.par_iter().for_each(|&(i, j)| {
                    let ray = camera.ray(i, j);
                    if let Some(hit) = answers.hits[(i + j * w) as usize] {
                        let start = hit.t * (1.0 - 0.5 * footprint);
                        let late = Ray::new(ray.at(start), ray.dir);
                        std::hint::black_box(tracer.intersect(&late));
                    }
                })
            })
            / 1e6;
        println!(
            "{view:<14} {nothing:>8.1} {known:>13.1} {mipmap:>8.1} {single:>12.1} {started_late:>25.1}"
        );
    }
    Ok(())
}
