//! Times the hybrid renderer against the mipmap tracer on the flight view of `relief bench`
//! (seeded fBm terrain): `cargo run --release -p relief-shade --example hybrid_flight -- 4096
//! 1920x1080 [far] [T] [cell]`.

use relief_core::{benchmark_views, Surface};
use relief_shade::{render_gbuffer_into, FarField, GBuffer, HybridRenderer};
use relief_trace::hybrid::HybridParams;
use relief_trace::MipmapTracer;
use std::sync::Arc;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
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
        let stats = hybrid.render_into(&camera, &bounds, &mut g2, None).unwrap();
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
    }
}
