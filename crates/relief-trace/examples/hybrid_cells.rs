//! The hybrid renderer's per-cell work on a large fBm terrain seen from the benchmark's
//! grazing flight view: how many cells each choice gets, the time to evaluate the heuristic
//! and to update every cell's min/max (a simulation rewriting the whole field), and the
//! dynamic updates of the exact tracer's pyramid (a 64 x 64 brush against a rebuild).
//!
//! `cargo run --release -p relief-trace --example hybrid_cells -- [N] [CELL] [WIDTH] [HEIGHT]`
//! (defaults 4096, 64, 1920, 1080). Timings are medians of 9 runs.

use relief_core::{benchmark_views, HeightField, SampleRegion, Surface};
use relief_sim::{fbm_terrain, FbmParams};
use relief_trace::hybrid::{CellChoice, HybridCells, HybridHeuristic, HybridParams};
use relief_trace::MipmapTracer;
use std::sync::Arc;
use std::time::Instant;

/// Median milliseconds of `runs` calls of `f` (given the run's index).
fn median_ms(runs: usize, mut f: impl FnMut(usize)) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|k| {
            let start = Instant::now();
            f(k);
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[runs / 2]
}

/// A 64 x 64 brush region, a different one for each run, inside the grid.
fn brush(field: &HeightField, k: usize) -> SampleRegion {
    let (w, h) = (field.width(), field.height());
    let (c, r) = ((w / 3 + 97 * k) % (w - 64), (h / 3 + 61 * k) % (h - 64));
    SampleRegion::new(c, r, c + 64, r + 64)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let mut next = |default: usize| args.next().map_or(default, |s| s.parse().expect("a number"));
    let (size, cell, width, height) = (next(4096), next(64), next(1920), next(1080));
    let runs = 9;
    let start = Instant::now();
    let field = fbm_terrain(size, size, 7, &FbmParams::for_size(size, size)).expect("fBm terrain");
    println!("fBm terrain {size}^2 generated in {:.0} ms", start.elapsed().as_secs_f64() * 1e3);
    let views = benchmark_views(&field, width as u32, height as u32).expect("views");
    let (_, camera) = views.into_iter().find(|(name, _)| *name == "flight").expect("flight view");
    let params = HybridParams { cell, ..HybridParams::default() };
    let heuristic = HybridHeuristic::new(params).expect("parameters");
    let threads = rayon::current_num_threads();
    println!(
        "cells of {cell}^2, T = {}, k = {}, {} levels {:?}; flight view {width}x{height}; {threads} threads",
        params.threshold,
        params.k,
        params.levels,
        heuristic.steps().iter().map(|s| format!("{}/{}", s.linear, s.binary)).collect::<Vec<_>>()
    );

    for surface in Surface::ALL {
        let start = Instant::now();
        let mut cells = HybridCells::new(&field, surface, cell).expect("cells");
        let build_ms = start.elapsed().as_secs_f64() * 1e3;
        let mut choices = Vec::new();
        let choose_ms = median_ms(runs, |_| choices = heuristic.choose(&cells, &camera));
        let count = |c: CellChoice| choices.iter().filter(|&&x| x == c).count();
        let levels: Vec<String> = (0..heuristic.steps().len())
            .map(|l| format!("L{l} {}", count(CellChoice::RayCast { level: l as u8 })))
            .collect();
        let whole = SampleRegion::whole(field.width(), field.height());
        let update_all_ms = median_ms(runs, |_| cells.update(&field, whole));
        let update_brush_ms = median_ms(runs, |k| cells.update(&field, brush(&field, k)));
        println!(
            "{surface:<9}: {} cells ({}x{}): culled {}, mesh {}, ray cast {} [{}]",
            cells.len(),
            cells.cells().0,
            cells.cells().1,
            count(CellChoice::Culled),
            count(CellChoice::Mesh),
            choices.iter().filter(|c| matches!(c, CellChoice::RayCast { .. })).count(),
            levels.join(", ")
        );
        println!(
            "{surface:<9}: heuristic {choose_ms:.3} ms; cells' min/max: build {build_ms:.1} ms, \
             update all {update_all_ms:.1} ms, update a 64x64 brush {update_brush_ms:.4} ms"
        );
    }

    // The exact tracer under edits: the pyramid above a 64 x 64 brush against a rebuild.
    let field = Arc::new(field);
    for surface in Surface::ALL {
        let mut tracer = MipmapTracer::new(field.clone(), surface);
        let rebuild_ms = median_ms(runs, |_| tracer = MipmapTracer::new(field.clone(), surface));
        // The pyramid's update alone: an edit that claims the brush's region.
        let pyramid_ms = median_ms(runs, |k| {
            tracer.edit(|f| Ok(brush(f, k))).expect("no edit");
        });
        // A real brush (a convex blend towards the middle of the range, so the range stays):
        // the field's own edit included, which rescans the field for its range.
        let (lo, hi) = (field.min_sample(), field.max_sample());
        let middle = 0.5 * (lo + hi);
        let brush_ms = median_ms(runs, |k| {
            tracer
                .edit(|f| f.edit_region(brush(f, k), |_, _, v| 0.9 * v + 0.1 * middle))
                .expect("brush");
        });
        println!(
            "{surface:<9}: mipmap pyramid: rebuild {rebuild_ms:.1} ms, update above a 64x64 \
             brush {pyramid_ms:.4} ms, brush edit with the field's own update {brush_ms:.2} ms"
        );
    }
}
