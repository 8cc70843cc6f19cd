//! Times geometry clipmaps (n = 511, 11 levels, transition n / 10, as in the hybrid paper's
//! section 5.2) on a synthetic N x N field (default 4096): the pyramid build, then per frame
//! of a flight along the benchmark's flight view the mesh and its draw at W x H (default
//! 1920 x 1080), with back faces culled (the camera is above the terrain).
//!
//! `cargo bench -p relief-bench --bench clipmap -- [N] [W] [H]`

use relief_bench::benchmark_views;
use relief_core::{Camera, DVec3};
use relief_mesh::{Clipmap, ClipmapParams, Culling, RasterTarget, Rasterizer};
use std::time::Instant;

#[path = "common/synthetic.rs"]
mod synthetic;
use synthetic::{cpu_seconds, synthetic_field};

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let n = args.first().copied().unwrap_or(4096);
    let (w, h) = (args.get(1).copied().unwrap_or(1920), args.get(2).copied().unwrap_or(1080));
    println!("threads: {}", rayon::current_num_threads());
    let field = synthetic_field(n);
    let start = Instant::now();
    let clipmap = Clipmap::new(&field, ClipmapParams::default()).unwrap();
    println!(
        "field {n}x{n}: pyramid of 11 levels in {:.0} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    let views = benchmark_views(&field, w as u32, h as u32).unwrap();
    let flight = views.iter().find(|(name, _)| *name == "flight").unwrap().1;
    let rasterizer = Rasterizer::new().with_culling(Culling::BackFaces);
    let mut target = RasterTarget::for_camera(&flight);
    let (mut mesh_total, mut draw_total, mut cpu_total) = (0.0, 0.0, 0.0);
    let frames = 8;
    for frame in 0..frames {
        // Fly towards the target, 1% of the field per frame.
        let step =
            (flight.target() - flight.eye()) * DVec3::new(1.0, 1.0, 0.0) * (0.02 * frame as f64);
        let camera = Camera::look_at(
            flight.eye() + step,
            flight.target() + step,
            DVec3::Z,
            60.0,
            w as u32,
            h as u32,
        )
        .unwrap();
        let cpu = cpu_seconds();
        let start = Instant::now();
        let mesh = clipmap.mesh(&camera);
        let mesh_ms = start.elapsed().as_secs_f64() * 1e3;
        target.clear();
        let start = Instant::now();
        let stats = rasterizer.draw(&camera, &mesh, 0, &mut target).unwrap();
        let draw_ms = start.elapsed().as_secs_f64() * 1e3;
        cpu_total += cpu_seconds() - cpu;
        mesh_total += mesh_ms;
        draw_total += draw_ms;
        println!(
            "frame {frame}: mesh {} triangles in {mesh_ms:.1} ms, draw {draw_ms:.1} ms ({} binned, {} fragments)",
            mesh.triangle_count(),
            stats.triangles_binned,
            stats.fragments
        );
    }
    let f = frames as f64;
    println!(
        "mean: mesh {:.1} ms, draw {:.1} ms, frame {:.1} ms ({:.1} CPU ms)",
        mesh_total / f,
        draw_total / f,
        (mesh_total + draw_total) / f,
        cpu_total * 1e3 / f
    );
}
