//! Times the ocean wave simulation on the seeded fBm terrain: `cargo bench -p relief-bench
//! --bench waves -- SIZE STEPS [SEA]` prints the median milliseconds per
//! step (integration and the field's `replace_samples` together) on the current thread count
//! (`RAYON_NUM_THREADS`), with the sea level at SEA of the height range (default 0.35; 1
//! floods everything, the worst case), and a hash of the final field's bytes to compare runs.

use relief_sim::{fbm_terrain, FbmParams, WaveParams, WaveSimulation};
use std::time::Instant;

#[path = "common/args.rs"]
mod args;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = args::program_args().into_iter();
    let size: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(4096);
    let steps: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(50);
    let level: f64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(0.35);
    let mut field = fbm_terrain(size, size, 1, &FbmParams::for_size(size, size))?;
    let z = field.geometry().z_scale;
    let (lo, hi) = (f64::from(field.min_sample()) * z, f64::from(field.max_sample()) * z);
    let sea_level = lo + level * (hi - lo) + if level >= 1.0 { 1.0 } else { 0.0 };
    let params = WaveParams { sea_level, ..WaveParams::for_field(&field) };
    let wet = field.samples().iter().filter(|&&v| f64::from(v) * z < sea_level).count();
    println!(
        "sea at {sea_level:.2}: {:.1} % of the samples under it",
        100.0 * wet as f64 / (size * size) as f64
    );
    let mut sea = WaveSimulation::new(&field, params)?;
    let mut times = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t = Instant::now();
        sea.step(&mut field)?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{size}^2, {steps} steps on {} threads: median {:.2} ms/step (min {:.2}, max {:.2})",
        rayon::current_num_threads(),
        times[times.len() / 2],
        times[0],
        times[times.len() - 1]
    );
    // The field's own share: replace_samples checks and ranges every sample.
    let mut buffer = field.samples().to_vec();
    let mut replace = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t = Instant::now();
        buffer = field.replace_samples(buffer)?;
        replace.push(t.elapsed().as_secs_f64() * 1e3);
    }
    replace.sort_by(f64::total_cmp);
    println!("of which HeightField::replace_samples alone: median {:.2} ms", replace[steps / 2]);
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for v in field.samples() {
        for b in v.to_bits().to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    }
    println!("field hash {h:016x}");
    Ok(())
}
