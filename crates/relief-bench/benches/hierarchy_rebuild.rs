//! Times the MLHM hierarchy's rebuild, what a simulation pays every frame: the RiversRain
//! scene at N² cells, built once, then rebuilt in place R times; prints the median and the
//! fastest rebuild, for box bounds (f32 and f16) and the smooth surface's padded bounds.
//!
//! `cargo bench -p relief-bench --bench hierarchy_rebuild -- 4096 [R] [NAME]`, NAME
//! one of `f32`, `f16`, `smooth` for that kind alone.

#[path = "common/args.rs"]
mod args;

use relief_core::Precision;
use relief_trace::MlhmHierarchy;
use std::time::Instant;

fn main() {
    let mut args = args::program_args().into_iter();
    let size: usize = args.next().map_or(4096, |s| s.parse().expect("N: cells per side"));
    let repeat: usize = args.next().map_or(9, |s| s.parse().expect("R: rebuilds"));
    let only = args.next();
    let layers = if size >= 4096 { 4 } else { 8 };
    let map = relief_sim::rivers_rain(size, layers, relief_sim::RIVERS_RAIN_SEED)
        .expect("the RiversRain scene");
    for (key, name, precision, radius) in [
        ("f32", "boxes, f32", Precision::F32, 0.0),
        ("f16", "boxes, f16", Precision::F16, 0.0),
        ("smooth", "smooth (one cell), f32", Precision::F32, map.cell_size()),
    ] {
        if only.as_deref().is_some_and(|only| only != key) {
            continue;
        }
        let start = Instant::now();
        let mut hierarchy = MlhmHierarchy::build_padded(&map, radius, precision);
        let build_ms = start.elapsed().as_secs_f64() * 1e3;
        let mut times: Vec<f64> = (0..repeat)
            .map(|_| {
                let start = Instant::now();
                hierarchy.rebuild(&map);
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        times.sort_by(f64::total_cmp);
        println!(
            "{size}² RiversRain, {name}: build {build_ms:.1} ms, rebuild median {:.1} ms, \
             fastest {:.1} ms ({} threads)",
            times[times.len() / 2],
            times[0],
            rayon::current_num_threads()
        );
    }
}
