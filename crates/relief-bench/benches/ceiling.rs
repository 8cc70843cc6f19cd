//! How fast relief's primary-ray render pass could be, whatever the tracer: the measurements
//! behind "What 5x would take" in docs/performance.md.
//!
//! On `relief bench`'s three views of a terrain (an `.npy` from `relief generate fbm`) at
//! 1920x1080, this renders the G-buffer (`render_gbuffer_into`, as `relief bench` does) with
//!
//! - `nothing`: a tracer that does no work and finds no hit: camera rays and G-buffer only;
//! - `answer known`: a tracer that copies each tile's hits, found beforehand: camera rays and
//!   the G-buffer writes of the real hits, the least any tracer could cost;
//! - `mipmap`: the real tracer, in packets;
//! - `mipmap, start known`: the same packets, with every ray that hits started half a pixel's
//!   footprint before its hit, as a perfect lower bound on its distance would allow;
//!
//! and traces single rays with the mipmap tracer from the eye (`single rays`) and from that
//! same start (`single rays, start known`). A second table gives the floor of any exact
//! tracer: the hit rays alone, one at a time with the naive tracer's exact cell test, walked
//! cell by cell from that start (`cell walk, start known`, the best a continuation from a
//! neighbour's hit could do) and from just before the hit (`one cell, at the hit`: making,
//! moving and clipping the ray and one exact cell test), beside the cost of making the rays
//! alone. A third traces the shadow rays of the mipmap's hits (made beforehand as `relief
//! bench` makes them) with the mipmap's packets whole and with their first 2, 8 and 32 units
//! skipped (not exact, a diagnostic of where a shadow ray's time goes), through the sun's
//! sweep as `relief render` does, and over their first cell alone. A fourth renders the
//! whole picture in one pass (`render_to_srgb8`: trace, shade and tone-map strip by strip, as
//! `relief render` does; the PNG not written) with `nothing`, `answer known` and `mipmap`,
//! without shadows, and with `mipmap` and shadows: what shading costs beyond tracing.
//! Each figure is the fastest of five runs, in millions of rays per second (every pixel counts
//! as a ray, misses included, as in `relief bench`).
//!
//! ```sh
//! relief generate fbm --size 4096 -o fbm-4096.npy
//! cargo bench -p relief-bench --bench ceiling -- fbm-4096.npy
//! ```

use anyhow::{Context, Result};
use rayon::prelude::*;
use relief_bench::benchmark_views;
use relief_core::{Camera, DVec3, HeightField, Ray, Surface};
use relief_shade::{
    render_gbuffer_into, render_to_srgb8, sun_direction, GBuffer, KeptHits, ShadingParams, Tile,
    TILE_SIZE,
};
use relief_trace::{Hit, MipmapTracer, NaiveTracer, SunShadows, Tracer};
use std::sync::Arc;
use std::time::Instant;

#[path = "common/args.rs"]
mod args;

/// Finds nothing, at no cost.
struct Nothing;

impl Tracer for Nothing {
    fn name(&self) -> &'static str {
        "nothing"
    }
    fn surface(&self) -> Surface {
        Surface::Triangles
    }
    fn bounds(&self) -> relief_core::Aabb {
        relief_core::Aabb::new(DVec3::INFINITY, DVec3::NEG_INFINITY)
    }
    fn intersect_counted(&self, _: &Ray, _: &mut u32) -> Option<Hit> {
        None
    }
    fn intersect_batch(&self, _: &[Ray], hits: &mut [Option<Hit>], _: &mut [u32]) {
        hits.fill(None);
    }
}

/// Hands back the hits found beforehand, stored tile by tile in the order
/// `render_gbuffer_into` asks for them, so that a batch costs one copy: the cheapest a tracer
/// could possibly be.
struct AnswerKnown {
    camera: Camera,
    right: DVec3,
    true_up: DVec3,
    tan_half: f64,
    /// Every pixel's hit, row by row.
    hits: Vec<Option<Hit>>,
    /// The same hits tile by tile (tiles row by row), each tile's in the order of its pixels.
    by_tile: Vec<Option<Hit>>,
    /// Where each tile's hits start in `by_tile`.
    tile_start: Vec<usize>,
}

impl AnswerKnown {
    fn new(camera: &Camera, tracer: &dyn Tracer) -> Self {
        let (w, h) = (camera.width(), camera.height());
        let hits: Vec<Option<Hit>> = (0..h)
            .into_par_iter()
            .flat_map_iter(|j| (0..w).map(move |i| tracer.intersect(&camera.ray(i, j))))
            .collect();
        let (mut by_tile, mut tile_start) = (Vec::new(), Vec::new());
        for y in (0..h as usize).step_by(TILE_SIZE) {
            for x in (0..w as usize).step_by(TILE_SIZE) {
                tile_start.push(by_tile.len());
                let tile = Tile::new(x, y, w as usize, h as usize);
                by_tile.extend(tile.pixels().map(|(i, j)| hits[i + j * w as usize]));
            }
        }
        let right = camera.forward().cross(camera.up()).normalize();
        AnswerKnown {
            camera: *camera,
            right,
            true_up: right.cross(camera.forward()),
            // The benchmark views are pinholes.
            tan_half: camera.half_height(),
            hits,
            by_tile,
            tile_start,
        }
    }

    /// The pixel a camera ray goes through.
    fn pixel(&self, ray: &Ray) -> (usize, usize) {
        let (w, h) = (self.camera.width() as f64, self.camera.height() as f64);
        let depth = ray.dir.dot(self.camera.forward());
        let sx = ray.dir.dot(self.right) / depth;
        let sy = ray.dir.dot(self.true_up) / depth;
        let i = ((sx / (self.tan_half * w / h) + 1.0) * w / 2.0) as usize;
        let j = ((1.0 - sy / self.tan_half) * h / 2.0) as usize;
        (i, j)
    }
}

impl Tracer for AnswerKnown {
    fn name(&self) -> &'static str {
        "answer known"
    }
    fn surface(&self) -> Surface {
        Surface::Triangles
    }
    fn bounds(&self) -> relief_core::Aabb {
        relief_core::Aabb::new(DVec3::NEG_INFINITY, DVec3::INFINITY)
    }
    fn intersect_counted(&self, ray: &Ray, _: &mut u32) -> Option<Hit> {
        let (i, j) = self.pixel(ray);
        self.hits[i + j * self.camera.width() as usize]
    }
    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], _: &mut [u32]) {
        let Some(first) = rays.first() else { return };
        // The first ray of a tile's batch is its top left pixel.
        let (i, j) = self.pixel(first);
        let tiles_x = (self.camera.width() as usize).div_ceil(TILE_SIZE);
        let start = self.tile_start[i / TILE_SIZE + j / TILE_SIZE * tiles_x];
        hits.copy_from_slice(&self.by_tile[start..start + rays.len()]);
    }
}

/// The mipmap tracer's packets, with every ray that hits started half a pixel's footprint
/// before its hit, as a perfect lower bound on its distance would allow.
struct StartKnown<'a> {
    tracer: &'a MipmapTracer,
    answers: &'a AnswerKnown,
    footprint: f64,
}

impl Tracer for StartKnown<'_> {
    fn name(&self) -> &'static str {
        "start known"
    }
    fn surface(&self) -> Surface {
        Surface::Triangles
    }
    fn bounds(&self) -> relief_core::Aabb {
        self.tracer.bounds()
    }
    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        self.tracer.intersect_counted(ray, steps)
    }
    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], steps: &mut [u32]) {
        let starts: Vec<f64> = rays
            .iter()
            .map(|ray| {
                self.answers.intersect(ray).map_or(0.0, |h| oracle_start(&h, self.footprint))
            })
            .collect();
        let late: Vec<Ray> =
            rays.iter().zip(&starts).map(|(r, &s)| Ray::new(r.at(s), r.dir)).collect();
        self.tracer.intersect_batch(&late, hits, steps);
        for (hit, &s) in hits.iter_mut().zip(&starts) {
            if let Some(h) = hit {
                h.t += s;
            }
        }
    }
}

/// Where the oracle starts a camera ray that hits at `hit`: half a pixel's footprint (per unit
/// distance, `footprint`) before it.
fn oracle_start(hit: &Hit, footprint: f64) -> f64 {
    hit.t * (1.0 - 0.5 * footprint)
}

/// How far along its ray each shadow ray starts in the shadow table: 0 is the real thing, the
/// others skip the ray's first stretch (not exact: a diagnostic of where the time goes).
const SHADOW_SKIPS: [f64; 4] = [0.0, 2.0, 8.0, 32.0];

/// How far along its range a shadow ray of the `first cell` column may go: a thousandth of a
/// unit, which keeps it in the cell it starts in.
const FIRST_CELL: f64 = 1e-3;

/// Where the `at the hit` column starts a camera ray: this relative distance before its hit,
/// inside the hit's cell.
const AT_HIT: f64 = 1e-9;

/// The shadow table's row of a view, in millions of rays per second.
struct ShadowRates {
    /// The mipmap's packets, the rays started [`SHADOW_SKIPS`] along.
    skipped: [f64; 4],
    /// `relief render`'s shadow rays: the sun's sweep over the mipmap tracer.
    swept: f64,
    /// The naive tracer, one ray at a time, over the first [`FIRST_CELL`] of each ray: the
    /// exact test of the cell it starts in and nothing else.
    first_cell: f64,
}

/// The shadow rays from every hit of `gbuffer` towards the benchmark's sun, made beforehand
/// as `relief bench` makes them and traced a tile at a time: [`ShadowRates`].
fn shadow_rates(
    field: &Arc<HeightField>,
    tracer: &MipmapTracer,
    naive: &NaiveTracer,
    camera: &Camera,
    gbuffer: &GBuffer,
) -> Result<ShadowRates> {
    let sun = sun_direction(315.0, 35.0);
    let (w, h) = (gbuffer.width, gbuffer.height);
    let mut tiles = Vec::new();
    for y in (0..h).step_by(TILE_SIZE) {
        for x in (0..w).step_by(TILE_SIZE) {
            let mut rays = Vec::new();
            Tile::new(x, y, w, h).shadow_rays(camera, gbuffer, sun, &mut rays);
            tiles.push(rays);
        }
    }
    let count = tiles.iter().map(Vec::len).sum::<usize>() as f64;
    let batches = |tracer: &dyn Tracer, tiles: &[Vec<Ray>]| {
        count
            / fastest(|| {
                tiles.par_iter().for_each(|rays| {
                    let (mut occluded, mut steps) = (vec![false; rays.len()], vec![0; rays.len()]);
                    tracer.occluded_batch(rays, &mut occluded, &mut steps);
                    std::hint::black_box(occluded);
                })
            })
            / 1e6
    };
    let skipped = SHADOW_SKIPS.map(|skip| {
        let skipped: Vec<Vec<Ray>> = tiles
            .iter()
            .map(|rays| rays.iter().map(|r| Ray { origin: r.at(skip), ..*r }).collect())
            .collect();
        batches(tracer, &skipped)
    });
    let swept = batches(&SunShadows::new(tracer, field.clone(), sun)?, &tiles);
    let first: Vec<Ray> =
        tiles.iter().flatten().map(|r| r.with_range(r.t_min, r.t_min + FIRST_CELL)).collect();
    let first_cell = count
        / fastest(|| {
            first.par_iter().for_each(|r| {
                std::hint::black_box(naive.occluded(r));
            })
        })
        / 1e6;
    Ok(ShadowRates { skipped, swept, first_cell })
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
    let path = args::program_args().into_iter().next().context("usage: ceiling TERRAIN.npy")?;
    let field = Arc::new(relief_io::read_npy_height_field(path.as_ref())?);
    let tracer = MipmapTracer::new(field.clone(), Surface::Triangles);
    let naive = NaiveTracer::new(field.clone(), Surface::Triangles);
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
        "{:<14} {:>8} {:>13} {:>8} {:>21} {:>12} {:>25}",
        "view",
        "nothing",
        "answer known",
        "mipmap",
        "mipmap, start known",
        "single rays",
        "single rays, start known"
    );
    let mut shadows = Vec::new();
    let mut pictures = Vec::new();
    let mut floors = Vec::new();
    for (view, camera) in benchmark_views(&field, w, h)?.into_iter().take(3) {
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
        let footprint = camera.pixel_footprint(1.0);
        let packets_late = render(&StartKnown { tracer: &tracer, answers: &answers, footprint });
        let pixels: Vec<(u32, u32)> = (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).collect();
        let single =
            rays / fastest(|| {
                pixels.par_iter().for_each(|&(i, j)| {
                    std::hint::black_box(tracer.intersect(&camera.ray(i, j)));
                })
            }) / 1e6;
        let started_late =
            rays / fastest(|| {
                pixels.par_iter().for_each(|&(i, j)| {
                    let ray = camera.ray(i, j);
                    if let Some(hit) = answers.hits[(i + j * w) as usize] {
                        let late = Ray::new(ray.at(oracle_start(&hit, footprint)), ray.dir);
                        std::hint::black_box(tracer.intersect(&late));
                    }
                })
            }) / 1e6;
        // The floor of any continuation: each hit ray started at a known point before its hit
        // and walked cell by cell with the exact test, its misses skipped.
        let hits = answers.hits.iter().flatten().count() as f64;
        let late = |start: &dyn Fn(&Hit) -> f64, i: u32, j: u32| {
            let ray = camera.ray(i, j);
            answers.hits[(i + j * w) as usize].map(|hit| Ray::new(ray.at(start(&hit)), ray.dir))
        };
        // Mrays/s of making every hit ray from `start` and, if `trace`, tracing it.
        let from_known = |start: &(dyn Fn(&Hit) -> f64 + Sync), trace: bool| {
            rays / fastest(|| {
                pixels.par_iter().for_each(|&(i, j)| {
                    if let Some(ray) = late(start, i, j) {
                        std::hint::black_box(if trace { naive.intersect(&ray) } else { None });
                        std::hint::black_box(ray);
                    }
                })
            }) / 1e6
        };
        let cells_per_hit = |start: &dyn Fn(&Hit) -> f64| {
            let mut cells = 0u64;
            for ray in pixels.iter().filter_map(|&(i, j)| late(start, i, j)) {
                let mut steps = 0;
                naive.intersect_counted(&ray, &mut steps);
                cells += steps as u64;
            }
            cells as f64 / hits
        };
        let before = |hit: &Hit| oracle_start(hit, footprint);
        let at = |hit: &Hit| hit.t * (1.0 - AT_HIT);
        let made = from_known(&before, false);
        let walked = (from_known(&before, true), cells_per_hit(&before));
        let at_hit = (from_known(&at, true), cells_per_hit(&at));
        floors.push((view, made, walked, at_hit));
        println!(
            "{view:<14} {nothing:>8.1} {known:>13.1} {mipmap:>8.1} {packets_late:>21.1} {single:>12.1} {started_late:>25.1}"
        );
        shadows.push((view, shadow_rates(&field, &tracer, &naive, &camera, &gbuffer)?));
        let mut params = ShadingParams::for_terrain(&bounds)?;
        params.shadows = false;
        let picture = |tracer: &dyn Tracer, params: &ShadingParams| {
            rays / fastest(|| {
                std::hint::black_box(
                    render_to_srgb8(
                        tracer,
                        tracer,
                        &camera,
                        &bounds,
                        params,
                        KeptHits::default(),
                        &|_| {},
                    )
                    .expect("valid parameters"),
                );
            }) / 1e6
        };
        let unshadowed = [&Nothing as &dyn Tracer, &answers, &tracer].map(|t| picture(t, &params));
        params.shadows = true;
        let shadowed = picture(&tracer, &params);
        pictures.push((view, unshadowed, shadowed));
    }
    println!(
        "\nhit rays one at a time from a known start, misses skipped, no G-buffer; Mrays/s of all pixels"
    );
    println!(
        "{:<14} {:>11} {:>24} {:>14} {:>20} {:>14}",
        "view",
        "rays made",
        "cell walk, start known",
        "cells per hit",
        "one cell, at the hit",
        "cells per hit"
    );
    for (view, made, (walked, walk_cells), (at_hit, hit_cells)) in floors {
        println!(
            "{view:<14} {made:>11.1} {walked:>24.1} {walk_cells:>14.2} {at_hit:>20.1} {hit_cells:>14.3}"
        );
    }
    println!(
        "\nshadow rays made beforehand: mipmap packets started this far along their ray, the \
         sweep, the first cell alone; Mrays/s"
    );
    print!("{:<14}", "view");
    SHADOW_SKIPS.iter().for_each(|skip| print!(" {skip:>8}"));
    println!(" {:>8} {:>10}", "sweep", "first cell");
    for (view, rates) in shadows {
        print!("{view:<14}");
        rates.skipped.iter().for_each(|rate| print!(" {rate:>8.1}"));
        println!(" {:>8.1} {:>10.1}", rates.swept, rates.first_cell);
    }
    println!("\nthe whole picture in one pass (render_to_srgb8), no shadows unless said; Mrays/s");
    println!(
        "{:<14} {:>8} {:>13} {:>8} {:>17}",
        "view", "nothing", "answer known", "mipmap", "mipmap, shadows"
    );
    for (view, [nothing, known, mipmap], shadowed) in &pictures {
        println!("{view:<14} {nothing:>8.1} {known:>13.1} {mipmap:>8.1} {shadowed:>17.1}");
    }
    Ok(())
}
