//! Measures the rasterizer: a synthetic N x N height field (default 2048) meshed whole as the
//! `triangles` solid, drawn at W x H (default 1920 x 1080) from relief's benchmark views;
//! prints mesh time, draw time, triangles/s and pixels (fragments)/s.
//!
//! `cargo bench -p relief-bench --bench raster -- [N] [W] [H]`

use relief_bench::benchmark_views;
use relief_core::{SampleRegion, Surface};
use relief_mesh::{height_field_mesh, Culling, IndexedMesh, RasterTarget, Rasterizer};
use std::time::Instant;

#[path = "common/synthetic.rs"]
mod synthetic;
use synthetic::{cpu_seconds, synthetic_field};

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let n = args.first().copied().unwrap_or(2048);
    let (w, h) = (args.get(1).copied().unwrap_or(1920), args.get(2).copied().unwrap_or(1080));
    println!("threads: {}", rayon::current_num_threads());
    let field = synthetic_field(n);

    let start = Instant::now();
    let whole = height_field_mesh(&field, Surface::Triangles, SampleRegion::whole(n, n)).unwrap();
    let mesh_ms = start.elapsed().as_secs_f64() * 1e3;
    println!(
        "field {n}x{n}: whole triangles mesh {} triangles, {} vertices in {mesh_ms:.0} ms",
        whole.triangle_count(),
        whole.vertex_count()
    );
    // The same field meshed as the hybrid renderer's cells of 64 squares (65 samples), appended.
    let start = Instant::now();
    let mut cells = IndexedMesh::default();
    for row in (0..n - 1).step_by(64) {
        for col in (0..n - 1).step_by(64) {
            let region = SampleRegion::new(col, row, (col + 65).min(n), (row + 65).min(n));
            cells.append(&height_field_mesh(&field, Surface::Triangles, region).unwrap()).unwrap();
        }
    }
    let cells_ms = start.elapsed().as_secs_f64() * 1e3;
    println!("  as 64x64-square cells: {} triangles in {cells_ms:.0} ms", cells.triangle_count());

    let rasterizer = Rasterizer::new();
    let views = benchmark_views(&field, w as u32, h as u32).unwrap();
    let runs = views.iter().flat_map(|v| {
        [(v, Culling::None, "whole", &whole), (v, Culling::BackFaces, "whole", &whole)]
            .into_iter()
            .chain([(v, Culling::BackFaces, "cells", &cells)])
    });
    for ((name, camera), culling, mesh_name, mesh) in runs {
        let whole = mesh;
        let rasterizer = rasterizer.with_culling(culling);
        let mut target = RasterTarget::for_camera(camera);
        let mut times = Vec::new();
        let mut stats = Default::default();
        let cpu_start = cpu_seconds();
        for _ in 0..5 {
            target.clear();
            let start = Instant::now();
            stats = rasterizer.draw(camera, whole, 0, &mut target).unwrap();
            times.push(start.elapsed().as_secs_f64());
        }
        let cpu = (cpu_seconds() - cpu_start) / 5.0;
        times.sort_by(f64::total_cmp);
        let t = times[times.len() / 2];
        let drawn = target.triangle.iter().filter(|&&k| k != RasterTarget::NO_TRIANGLE).count();
        println!(
            "{name:>13} {w}x{h} {mesh_name} {culling:?}: {:7.1} ms ({:7.1} CPU ms)  {:6.1} M triangles/s  \
             {:6.1} M fragments/s  (binned {} of {} triangles, {} bin entries, {} fragments, {drawn} pixels drawn)",
            t * 1e3,
            cpu * 1e3,
            whole.triangle_count() as f64 / t / 1e6,
            stats.fragments as f64 / t / 1e6,
            stats.triangles_binned,
            whole.triangle_count(),
            stats.bin_entries,
            stats.fragments,
        );
    }
}
