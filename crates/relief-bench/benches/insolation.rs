//! How long a day's insolation takes: the sun's positions by NREL's SPA over one day at
//! 15-minute steps, then the hours of direct sun and the direct-beam energy of every sample
//! of an N x N synthetic terrain from a horizon map of D directions.
//!
//! The horizon map is made up (a smooth pattern of angles from -0.1 to 0.5 rad), not computed:
//! this times the insolation pass alone, whose work does not depend on the angles' values
//! beyond which suns clear them.
//!
//! `cargo bench -p relief-bench --bench insolation -- [N] [D] [REPEATS]`
//! (N 3601, D 32, REPEATS 3).

#[path = "common/args.rs"]
mod args;
#[path = "common/synthetic.rs"]
#[allow(dead_code)] // cpu_seconds is not used here
mod synthetic;

use rayon::prelude::*;
use relief_shade::horizon::HorizonMap;
use relief_shade::solar::{insolation, parse_date_range, sun_samples_over, Observer, UtcOffset};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = args::program_args();
    let n: usize = args.first().map_or(Ok(3601), |a| a.parse())?;
    let directions: usize = args.get(1).map_or(Ok(32), |a| a.parse())?;
    let repeats: u32 = args.get(2).map_or(Ok(3), |a| a.parse())?;
    let field = synthetic::synthetic_field(n);
    let horizons = HorizonMap {
        width: n,
        height: n,
        azimuths_deg: (0..directions).map(|k| k as f64 * 360.0 / directions as f64).collect(),
        angles: (0..directions)
            .into_par_iter()
            .map(|k| {
                (0..n * n)
                    .map(|i| {
                        let (c, r) = ((i % n) as f32, (i / n) as f32);
                        0.2 + 0.3 * (c * 0.013 + k as f32).sin() * (r * 0.007).cos()
                    })
                    .collect()
            })
            .collect(),
    };
    let day = parse_date_range("2026-06-21")?;
    let zone = UtcOffset::from_minutes(120)?;
    let observer = Observer::at(46.95, 7.45);
    println!(
        "insolation of {n} x {n} samples, {directions} horizon directions, 2026-06-21 at 15 min"
    );
    println!("| run | sun positions (96) ms | insolation s | Msample-suns/s |");
    println!("|---|---|---|---|");
    for run in 1..=repeats {
        let start = Instant::now();
        let suns = sun_samples_over(day, zone, 900.0, &observer)?;
        let suns_ms = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let result = insolation(&field, None, &horizons, &suns)?;
        let seconds = start.elapsed().as_secs_f64();
        let work = (n * n * suns.len()) as f64 / seconds / 1e6;
        println!("| {run} | {suns_ms:.2} | {seconds:.3} | {work:.0} |");
        std::hint::black_box(result);
    }
    Ok(())
}
