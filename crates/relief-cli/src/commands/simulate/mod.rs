//! `relief simulate`: run the layered erosion simulation (relief_sim::erosion) on an MLHM
//! scene and write the result, the simulation state and step count included in a `.json`
//! scene so a later run continues it.

pub mod args;
pub(super) mod frames;
mod keep;

use crate::args::ReadArgs;
use crate::{input, outputs, progress};
use anyhow::{bail, Context, Result};
use args::SimulateArgs;
use frames::Frames;
use keep::{write_scene, Keeper, SNAPSHOT_BYTES_PER_SLOT};
use relief_sim::erosion::{ErosionError, ErosionParams, ErosionState, StepVolumes};
use serde_json::{Map, Value};
use std::sync::Arc;
use std::time::Instant;

use relief_render::simulation::{scene_params, start_state, BYTES_PER_SLOT};

/// Runs `relief simulate`.
pub fn run(args: &SimulateArgs) -> Result<()> {
    check_files(args)?;
    frames::check(args)?;
    let read = ReadArgs { max_memory: args.max_memory, ..ReadArgs::default() };
    let scene = input::load_mlhm(&args.input, &read)?;
    let params = params(args, &scene.settings)?;
    let held = BYTES_PER_SLOT + SNAPSHOT_BYTES_PER_SLOT;
    let mut state = start_state(&scene, &args.input, args.max_memory, held)?;
    let first_step = state.step_count();
    let mut frames = Frames::new(args, &Arc::new(scene.mlhm.clone()))?;
    let mut keeper = Keeper::new(args, &scene, &state)?;
    let bar = progress::bar(args.steps, "simulating");
    let log = |line: &str| bar.suspend(|| eprintln!("{line}"));
    let mut times = Vec::with_capacity(args.steps.min(1 << 16) as usize);
    let mut volumes = StepVolumes::default();
    for done in 1..=args.steps {
        let start = Instant::now();
        let step = state.step_count();
        let stepped = match step_once(&mut state, &params, args) {
            Ok(v) => v,
            Err(e) => {
                bar.finish_and_clear();
                return Err(keeper.fail_with_broken(e.into(), step, &params, args.seed));
            }
        };
        volumes.add(&stepped);
        let ms = start.elapsed().as_secs_f64() * 1e3;
        times.push(ms);
        let kept = match &mut frames {
            Some(frames) => frames.after_step(&state, ms, &log),
            None => Ok(()),
        }
        .and_then(|()| keeper.after_step(&state, done, done == args.steps));
        if let Err(e) = kept {
            bar.finish_and_clear();
            return Err(keeper.fail_with_valid(e, &state));
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let written = keeper.scene(&state).and_then(|out| write_scene(&args.output, &out));
    if let Err(e) = written {
        return Err(keeper.fail_with_valid(e, &state));
    }
    keeper.finish();
    let median = frames::median(times);
    eprintln!(
        "wrote {} after {} steps (now at step {}): median {median:.2} ms per step; {} splits, \
         {} collapses",
        args.output.display(),
        args.steps,
        state.step_count(),
        volumes.splits,
        volumes.collapses
    );
    if let Some(frames) = &frames {
        eprintln!("{}", frames.summary());
    }
    if let Some(path) = &args.stats {
        let mut stats = serde_json::json!({
            "steps": args.steps,
            "first_step": first_step,
            "median_step_ms": median,
            "rain_m3": volumes.rain,
            "evaporation_m3": volumes.evaporation,
            "water_clamped_m3": volumes.water_clamped,
            "horizontal_erosion_sand_m3": volumes.horizontal_erosion_sand,
            "damage_recovery_m3": volumes.damage_recovery,
            "split_bedrock_m3": volumes.split_bedrock,
            "split_sand_m3": volumes.split_sand,
            "collapse_damage_m3": volumes.collapse_damage,
            "sand_clamped_m3": volumes.sand_clamped,
            "sediment_clamped_m3": volumes.sediment_clamped,
            "material_created_m3": volumes.material_created(),
            "material_removed_m3": volumes.material_removed(),
            "splits": volumes.splits,
            "collapses": volumes.collapses,
        });
        if let (Some(frames), Some(map)) = (&frames, stats.as_object_mut()) {
            map.extend(frames.stats().into_iter().map(|(k, v)| (k.to_string(), v)));
        }
        outputs::write_stats(path, &stats)?;
    }
    Ok(())
}

/// One step of `state`, its invariants checked after every stage with `--check-stages`;
/// with the tests' `--test-fail-at-step N`, step N reports a broken terrain.
fn step_once(
    state: &mut ErosionState,
    params: &ErosionParams,
    args: &SimulateArgs,
) -> Result<StepVolumes, ErosionError> {
    let step = state.step_count();
    let volumes = if args.check_stages {
        state.step_checking_stages(params, args.seed)?
    } else {
        state.step(params, args.seed)?
    };
    if args.test_fail_at_step == Some(step) {
        return Err(ErosionError::Invariant {
            step,
            stage: None,
            error: Box::new(ErosionError::Parameter {
                name: "--test-fail-at-step",
                reason: "a failure injected by the tests".into(),
            }),
        });
    }
    Ok(volumes)
}

/// Refuses an input or output that is not an MLHM file, unwritable outputs, and outputs that
/// would overwrite the input or each other, before any work.
fn check_files(args: &SimulateArgs) -> Result<()> {
    if !input::is_mlhm_scene(&args.input) {
        bail!(
            "{}: relief simulate takes an MLHM scene (.json with its .dat, or .mlhm)",
            args.input.display()
        );
    }
    if !input::is_mlhm_scene(&args.output) {
        bail!(
            "-o {}: the result is written as .json (the reference simulator's scene, with its .dat \
             beside it) or .mlhm",
            args.output.display()
        );
    }
    outputs::check_writable(&args.output)?;
    let mut all = vec![("-o", args.output.as_path())];
    if let Some(stats) = &args.stats {
        outputs::check_stats(stats)?;
        all.push(("--stats", stats.as_path()));
    }
    outputs::check_distinct(&all, &[&args.input])
}

/// The parameters: the reference defaults, the scene's `Simulation/*` settings over them,
/// and the command line's over those.
fn params(args: &SimulateArgs, settings: &Map<String, Value>) -> Result<ErosionParams> {
    let mut p = scene_params(settings);
    if let Some(v) = args.rain {
        p.rain = v;
    }
    if let Some(v) = args.evaporation {
        p.evaporation = v;
    }
    if let Some(v) = args.dt {
        p.dt = v;
    }
    p.validate().with_context(|| format!("the simulation settings of {}", args.input.display()))?;
    Ok(p)
}
