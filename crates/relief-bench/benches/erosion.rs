//! Times erosion steps on the RiversRain scene: `cargo bench -p relief-bench --bench erosion --
//! SIZE STEPS` prints the median milliseconds per step and the volumes, and
//! checks the final terrain's invariants, with a hash of the final state's bytes (layer counts,
//! columns, fluxes, stability, sediment, damage) to compare runs. It also times the check of the
//! invariants each step runs (`ErosionState::validate`) once more after every step.

use relief_sim::erosion::{ErosionParams, ErosionState, StepVolumes};
use std::time::Instant;

#[path = "common/args.rs"]
mod args;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = args::program_args().into_iter();
    let size: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(256);
    let steps: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(50);
    let map = relief_sim::rivers_rain(size, 8, relief_sim::RIVERS_RAIN_SEED)?;
    let mut state = ErosionState::from_mlhm(&map, None, 8, 0)?;
    let params = ErosionParams::default();
    let mut times = Vec::with_capacity(steps);
    let mut checks = Vec::with_capacity(steps);
    let mut volumes = StepVolumes::default();
    for _ in 0..steps {
        let t = Instant::now();
        volumes.add(&state.step(&params, 1)?);
        times.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        state.validate()?;
        checks.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    checks.sort_by(f64::total_cmp);
    let layered = state.layer_counts().iter().filter(|&&n| n > 1).count();
    println!(
        "{size}^2, {steps} steps on {} threads: median {:.2} ms/step (of which the invariants' \
         check {:.3} ms); cells with overhangs {layered}",
        rayon::current_num_threads(),
        times[times.len() / 2],
        checks[checks.len() / 2]
    );
    println!("{volumes:?}");
    state.to_mlhm()?.validate()?;
    println!("{:?}", state.totals());
    println!("state hash {:016x}", state_hash(&state));
    Ok(())
}

/// FNV-1a over the bytes of the final state: layer counts, then every slot's column, fluxes,
/// stability, sediment and damage.
fn state_hash(state: &ErosionState) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h = (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    };
    eat(state.layer_counts());
    for (s, c) in state.columns().iter().enumerate() {
        for v in [c.bedrock, c.sand, c.water, c.ceiling] {
            eat(&v.to_bits().to_le_bytes());
        }
        for v in state.fluxes()[s] {
            eat(&v.to_bits().to_le_bytes());
        }
        for v in [state.stability()[s], state.sediment()[s], state.damage()[s]] {
            eat(&v.to_bits().to_le_bytes());
        }
    }
    h
}
