//! The hybrid renderer's per-cell work on a large fBm terrain seen from the benchmark's
//! grazing flight view: how many cells each choice gets, the time to evaluate the heuristic
//! and to update every cell's min/max (a simulation rewriting the whole field), and the
//! dynamic updates of the exact tracer's pyramid (a 64 x 64 brush against a rebuild).
//!
//! `cargo bench -p relief-bench --bench hybrid_cells -- [N] [CELL] [WIDTH] [HEIGHT]
//! [T] [--image]` (defaults 4096, 64, 1920, 1080, 70). Timings are medians of 9 runs.
//!
//! With `--image`, it also renders the view's depth the hybrid way with this module's parts,
//! the near field's mesh cells standing in for a rasterizer by the exact tracer inside their
//! boxes, and compares it with the exact tracer: the levels of precision's PSNR (R the
//! terrain's diagonal, over the pixels both see terrain) and wrong pixels (terrain against
//! sky), and the exact far field's agreement, which must be complete. A check of the parts at
//! scale, not the renderer (its times say nothing of one). `LOP_STEPS=L/B` in the environment
//! casts every ray-cast cell with L linear and B binary steps instead of its level's.

#[path = "common/args.rs"]
mod args;

use rayon::prelude::*;
use relief_bench::benchmark_views;
use relief_core::{Camera, HeightField, SampleRegion, Surface};
use relief_shade::hybrid::{project_box, CellChoice, HybridHeuristic, HybridParams, PixelRect};
use relief_sim::{fbm_terrain, FbmParams};
use relief_trace::hybrid::{
    box_entry, exact_far_hit, exact_far_hits, lop_cast, HybridCells, LopSteps,
};
use relief_trace::{MipmapTracer, Tracer};
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
    let image = args::program_args().iter().any(|a| a == "--image");
    let mut args = args::program_args().into_iter().filter(|a| a != "--image");
    let mut next = |default: usize| args.next().map_or(default, |s| s.parse().expect("a number"));
    let (size, cell, width, height) = (next(4096), next(64), next(1920), next(1080));
    let threshold = args.next().map_or(70.0, |s| s.parse().expect("T: a number"));
    let runs = 9;
    let start = Instant::now();
    let field = fbm_terrain(size, size, 7, &FbmParams::for_size(size, size)).expect("fBm terrain");
    println!("fBm terrain {size}^2 generated in {:.0} ms", start.elapsed().as_secs_f64() * 1e3);
    let views = benchmark_views(&field, width as u32, height as u32).expect("views");
    let (_, camera) = views.into_iter().find(|(name, _)| *name == "flight").expect("flight view");
    let params = HybridParams { cell, threshold, ..HybridParams::default() };
    let heuristic = HybridHeuristic::new(params).expect("parameters");
    let threads = rayon::current_num_threads();
    println!(
        "cells of {cell}^2, T = {}, k = {}, {} levels {:?}; flight view {width}x{height}; \
         {threads} threads",
        params.threshold,
        params.k,
        params.levels,
        heuristic.steps().iter().map(|s| format!("{}/{}", s.linear, s.binary)).collect::<Vec<_>>()
    );

    let mut chosen = Vec::new();
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
        chosen.push((surface, cells, choices));
    }
    if image {
        let field = Arc::new(field.clone());
        for (surface, cells, choices) in &chosen {
            compare_depths(&field, *surface, cells, choices, &heuristic, &camera);
        }
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
        // A brush that lifts a peak above the highest sample: the range changes every time.
        let peak_ms = median_ms(runs, |k| {
            tracer
                .edit(|f| {
                    let (region, top) = (brush(f, k), f.max_sample() + 1.0);
                    let (c, r) = (region.col0 + 32, region.row0 + 32);
                    f.edit_region(region, |col, row, v| if (col, row) == (c, r) { top } else { v })
                })
                .expect("peak");
        });
        println!(
            "{surface:<9}: mipmap pyramid: rebuild {rebuild_ms:.1} ms, update above a 64x64 \
             brush {pyramid_ms:.4} ms; brush edits with the field's own update: within the \
             range {brush_ms:.2} ms, past its top {peak_ms:.2} ms"
        );
    }
}

/// Side of the screen tiles the cells are binned into.
const TILE: u32 = 16;

/// Renders the depth the hybrid way (levels of precision, and the exact far field) and
/// compares both with the exact tracer's (see the module's documentation).
fn compare_depths(
    field: &Arc<HeightField>,
    surface: Surface,
    cells: &HybridCells,
    choices: &[CellChoice],
    heuristic: &HybridHeuristic,
    camera: &Camera,
) {
    let exact = MipmapTracer::new(field.clone(), surface);
    let (w, h) = (camera.width(), camera.height());
    let start = Instant::now();
    let reference: Vec<Option<f64>> = (0..w * h)
        .into_par_iter()
        .map(|p| exact.intersect(&camera.ray(p % w, p / w)).map(|hit| hit.t))
        .collect();
    let exact_ms = start.elapsed().as_secs_f64() * 1e3;
    // Bin every drawn cell into the screen tiles its projected box covers.
    let (tiles_x, tiles_y) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let mut bins: Vec<Vec<(usize, PixelRect)>> = vec![Vec::new(); (tiles_x * tiles_y) as usize];
    for (k, choice) in choices.iter().enumerate() {
        if *choice == CellChoice::Culled {
            continue;
        }
        let Some(b) = cells.proxy_box(k) else { continue };
        let Some(rect) = project_box(camera, &b).pixels(w, h) else { continue };
        for ty in rect.j0 / TILE..=rect.j1 / TILE {
            for tx in rect.i0 / TILE..=rect.i1 / TILE {
                bins[(tx + ty * tiles_x) as usize].push((k, rect));
            }
        }
    }
    let forced = std::env::var("LOP_STEPS").ok().map(|v| {
        let (a, b) = v.split_once('/').expect("LOP_STEPS=L/B");
        LopSteps { linear: a.parse().expect("linear steps"), binary: b.parse().expect("binary") }
    });
    let start = Instant::now();
    // Per pixel: the mesh stand-in's depth, the levels of precision's, the nearest ray-cast
    // box's entry and the number of casts.
    let cells_pass: Vec<(f64, f64, f64, usize)> = (0..w * h)
        .into_par_iter()
        .map(|p| {
            let (i, j) = (p % w, p / w);
            let ray = camera.ray(i, j);
            let (mut mesh, mut lop, mut t0, mut casts) =
                (f64::INFINITY, f64::INFINITY, f64::INFINITY, 0);
            for &(k, r) in &bins[(i / TILE + (j / TILE) * tiles_x) as usize] {
                if !((r.i0..=r.i1).contains(&i) && (r.j0..=r.j1).contains(&j)) {
                    continue;
                }
                let Some((enter, exit)) = box_entry(cells, field, k, &ray) else { continue };
                match choices[k] {
                    CellChoice::Mesh => {
                        // The rasterizer's stand-in: the exact surface inside the mesh cell.
                        if let Some(hit) = exact.intersect(&ray.with_range(enter, exit)) {
                            mesh = mesh.min(hit.t);
                        }
                    }
                    CellChoice::RayCast { level } => {
                        t0 = t0.min(enter);
                        casts += 1;
                        let steps = forced.unwrap_or(heuristic.steps()[level as usize]);
                        if let Some(hit) = lop_cast(field, cells, k, &ray, steps) {
                            lop = lop.min(hit.t);
                        }
                    }
                    CellChoice::Culled => {}
                }
            }
            (mesh, lop, t0, casts)
        })
        .collect();
    let cells_ms = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    let far_pass: Vec<f64> = (0..w * h)
        .into_par_iter()
        .map(|p| {
            let (mesh, _, t0, _) = cells_pass[p as usize];
            let ray = camera.ray(p % w, p / w);
            exact_far_hit(&exact, &ray, t0, mesh).map_or(f64::INFINITY, |hit| hit.t)
        })
        .collect();
    let far_ms = start.elapsed().as_secs_f64() * 1e3;
    // The same in packets of 8 x 8 pixels, against the exact tracer's packets over the image.
    let packets = |far: bool| -> Vec<Option<f64>> {
        let (px, py) = (w.div_ceil(8), h.div_ceil(8));
        let tiles: Vec<Vec<(u32, Option<f64>)>> = (0..px * py)
            .into_par_iter()
            .map(|tile| {
                let (tx, ty) = (tile % px * 8, tile / px * 8);
                let pixels: Vec<u32> = (ty..(ty + 8).min(h))
                    .flat_map(|j| (tx..(tx + 8).min(w)).map(move |i| i + j * w))
                    .collect();
                let rays: Vec<_> = pixels.iter().map(|&p| camera.ray(p % w, p / w)).collect();
                let mut hits = vec![None; rays.len()];
                if far {
                    let t0: Vec<f64> = pixels.iter().map(|&p| cells_pass[p as usize].2).collect();
                    let t1: Vec<f64> = pixels.iter().map(|&p| cells_pass[p as usize].0).collect();
                    exact_far_hits(&exact, &rays, &t0, &t1, &mut hits);
                } else {
                    exact.intersect_batch(&rays, &mut hits, &mut vec![0; rays.len()]);
                }
                pixels.into_iter().zip(hits).map(|(p, hit)| (p, hit.map(|h| h.t))).collect()
            })
            .collect();
        let mut depth = vec![None; (w * h) as usize];
        for (p, t) in tiles.into_iter().flatten() {
            depth[p as usize] = t;
        }
        depth
    };
    let start = Instant::now();
    let exact_packets = packets(false);
    let exact_packets_ms = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    let far_packets = packets(true);
    let far_packets_ms = start.elapsed().as_secs_f64() * 1e3;
    let packets_differ = (0..(w * h) as usize)
        .filter(|&p| {
            let mesh = cells_pass[p].0;
            let far = far_packets[p].map_or(mesh, |t| t.min(mesh));
            let want = exact_packets[p].unwrap_or(f64::INFINITY);
            !(far == want || (far - want).abs() <= 1e-9 * want)
        })
        .count();
    let casts: usize = cells_pass.iter().map(|c| c.3).sum();
    let finite = |t: f64| t.is_finite().then_some(t);
    let hybrid: Vec<(Option<f64>, Option<f64>)> = cells_pass
        .iter()
        .zip(&far_pass)
        .map(|(&(mesh, lop, _, _), &far)| (finite(mesh.min(lop)), finite(mesh.min(far))))
        .collect();
    let diagonal = cells.world_bounds().diagonal();
    let (mut sum, mut both, mut wrong, mut far_wrong, mut far_differ) = (0.0, 0usize, 0, 0, 0);
    let (mut hist, mut emax) = ([0usize; 5], 0.0f64);
    for (reference, (lop, far)) in reference.iter().zip(&hybrid) {
        match (reference, lop) {
            (Some(a), Some(b)) => {
                sum += (a - b) * (a - b);
                both += 1;
                let e = (a - b).abs();
                for (count, limit) in hist.iter_mut().zip([0.01, 0.1, 1.0, 10.0, 100.0]) {
                    *count += (e > limit) as usize;
                }
                emax = emax.max(e);
            }
            (None, None) => {}
            _ => wrong += 1,
        }
        match (reference, far) {
            (Some(a), Some(b)) => far_differ += ((a - b).abs() > 1e-9 * a) as usize,
            (None, None) => {}
            _ => far_wrong += 1,
        }
    }
    let psnr = 10.0 * (diagonal * diagonal / (sum / both.max(1) as f64)).log10();
    let pixels = (w * h) as f64;
    println!(
        "{surface:<9}: exact tracer {exact_ms:.0} ms; cells' pass {cells_ms:.0} ms ({casts} \
         casts in boxes, {:.2} per pixel), exact far field {far_ms:.0} ms; in packets of 8x8: \
         exact tracer {exact_packets_ms:.0} ms, exact far field {far_packets_ms:.0} ms \
         ({packets_differ} depths differ)",
        casts as f64 / pixels
    );
    println!(
        "{surface:<9}: levels of precision: PSNR {psnr:.1} dB, wrong pixels {:.4} %; exact far \
         field: {far_wrong} wrong pixels, {far_differ} depths off by more than 1e-9 relative",
        100.0 * wrong as f64 / pixels
    );
    println!(
        "{surface:<9}: levels of precision: of {both} pixels both see terrain, {} off by more \
         than 0.01, 0.1, 1, 10, 100 world units; at most {emax:.1} (the diagonal is {diagonal:.0})",
        hist.map(|n| n.to_string()).join(", ")
    );
}
