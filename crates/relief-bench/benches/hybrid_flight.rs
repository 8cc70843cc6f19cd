//! Times the hybrid renderer against the mipmap tracer on the flight view of `relief bench`
//! (seeded fBm terrain): `cargo bench -p relief-bench --bench hybrid_flight -- 4096
//! 1920x1080 [far] [T] [cell]`. Then times the mipmap tracer's packets on the pixels of each
//! kind the hybrid drew (exact far field, mesh, sky) alone, the other rays of each tile left
//! empty: what each kind costs the mipmap tracer.

#[path = "common/args.rs"]
mod args;

use rayon::prelude::*;
use relief_bench::benchmark_views;
use relief_core::Camera;
use relief_core::Surface;
use relief_shade::hybrid::HybridParams;
use relief_shade::{
    render_gbuffer_into, FarField, GBuffer, HybridRenderer, PixelSource, Tile, TILE_SIZE,
};
use relief_trace::MipmapTracer;
use relief_trace::Tracer;
use std::sync::Arc;
use std::time::Instant;

fn main() {
    let mut args = args::program_args().into_iter();
    let n: usize = args.next().map_or(4096, |s| s.parse().unwrap());
    let res = args.next().unwrap_or_else(|| "1920x1080".into());
    let (w, h) =
        res.split_once('x').map(|(a, b)| (a.parse().unwrap(), b.parse().unwrap())).unwrap();
    let far: FarField = args.next().map_or(FarField::Exact, |s| s.parse().unwrap());
    let threshold: f64 = args.next().map_or(70.0, |s| s.parse().unwrap());
    let cell: usize = args.next().map_or(64, |s| s.parse().unwrap());
    let field =
        Arc::new(relief_sim::fbm_terrain(n, n, 1, &relief_sim::FbmParams::for_size(n, n)).unwrap());
    let surface = Surface::Triangles;
    let views = benchmark_views(&field, w, h).unwrap();
    let camera = views.iter().find(|(name, _)| *name == "flight").unwrap().1;
    let bounds = field.world_bounds(surface);
    let mipmap = MipmapTracer::new(field.clone(), surface);
    let params = HybridParams { cell, threshold, ..HybridParams::default() };
    let mut hybrid = HybridRenderer::new(field.clone(), surface, params, far).unwrap();
    let mut g1 = GBuffer::new(w as usize, h as usize).unwrap();
    let mut g2 = GBuffer::new(w as usize, h as usize).unwrap();
    for round in 0..3 {
        let start = Instant::now();
        render_gbuffer_into(&mipmap, &camera, &bounds, &mut g1, &|_| {}).unwrap();
        let mip_ms = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let mut sources = Vec::new();
        let stats = hybrid.render_into(&camera, &bounds, &mut g2, Some(&mut sources)).unwrap();
        let hyb_ms = start.elapsed().as_secs_f64() * 1e3;
        let differ = g1
            .distance
            .iter()
            .zip(&g2.distance)
            .filter(|(a, b)| {
                a.is_finite() != b.is_finite()
                    || (a.is_finite() && (*a - *b).abs() > 1e-4 * a.abs())
            })
            .count();
        println!("round {round}: mipmap {mip_ms:.1} ms, hybrid ({far}) {hyb_ms:.1} ms; {differ} pixels differ; {stats:?}");
        for (name, kind) in [
            ("exact far field", PixelSource::Exact),
            ("mesh", PixelSource::Mesh),
            ("sky", PixelSource::Nothing),
        ] {
            let start = Instant::now();
            let rays = trace_kind(&mipmap, &camera, &sources, kind);
            let ms = start.elapsed().as_secs_f64() * 1e3;
            println!("  the mipmap tracer on the {name} pixels alone ({rays} rays): {ms:.1} ms");
        }
    }
}

/// Traces, with `tracer`'s batches tile by tile, the camera rays of the pixels `sources` says
/// `kind` drew (the others' rays empty); returns how many rays were traced.
fn trace_kind(
    tracer: &dyn Tracer,
    camera: &Camera,
    sources: &[PixelSource],
    kind: PixelSource,
) -> usize {
    let (w, h) = (camera.width() as usize, camera.height() as usize);
    (0..h.div_ceil(TILE_SIZE))
        .into_par_iter()
        .map(|strip| {
            let mut traced = 0;
            for x in (0..w).step_by(TILE_SIZE) {
                let tile = Tile::new(x, strip * TILE_SIZE, w, h);
                let rays: Vec<_> = tile
                    .pixels()
                    .map(|(i, j)| {
                        let ray = camera.ray(i as u32, j as u32);
                        if sources[i + j * w] == kind {
                            traced += 1;
                            ray
                        } else {
                            ray.with_range(1.0, 0.0)
                        }
                    })
                    .collect();
                let (mut hits, mut steps) = (vec![None; rays.len()], vec![0; rays.len()]);
                tracer.intersect_batch(&rays, &mut hits, &mut steps);
            }
            traced
        })
        .sum()
}
