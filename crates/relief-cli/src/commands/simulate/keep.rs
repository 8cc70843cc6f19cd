//! `relief simulate` loses no work: every `--checkpoint K` steps it writes the state beside
//! the output (`OUT.step-N.json`, atomically, the previous checkpoint removed), and when a
//! run fails mid-way it writes the last valid state there before it reports the error. A step
//! that broke the terrain leaves a state not worth saving: the last valid one is replayed
//! from an in-memory copy taken every [`SNAPSHOT_EVERY`] steps (the simulation is
//! deterministic, so the replay gives the same bytes).

use super::args::SimulateArgs;
use anyhow::{Context, Result};
use relief_core::Mlhm;
use relief_io::MlhmScene;
use relief_render::simulation::SceneTemplate;
use relief_render::RenderError;
use relief_sim::erosion::{ErosionParams, ErosionState, SimulationPlanes};
use std::path::{Path, PathBuf};

/// Steps between the in-memory copies a failed step is replayed from (at most this many
/// steps are replayed).
pub const SNAPSHOT_EVERY: u64 = 100;

/// Bytes per column slot of the in-memory copy: the terrain and the saved planes.
pub const SNAPSHOT_BYTES_PER_SLOT: u64 = 16 + 16 + 12;

/// The state saved at a step, as a file would hold it.
struct Snapshot {
    map: Mlhm,
    planes: SimulationPlanes,
    step: u64,
}

impl Snapshot {
    fn of(state: &ErosionState) -> Result<Snapshot> {
        let layers = state.used_layers();
        Ok(Snapshot {
            map: state.to_mlhm_with_layers(layers)?,
            planes: state.planes_with_layers(layers),
            step: state.step_count(),
        })
    }
}

/// The checkpoints and the last valid state of one run.
pub struct Keeper<'a> {
    output: &'a Path,
    input_path: &'a Path,
    /// The input scene, whose states are written.
    template: SceneTemplate,
    checkpoint_every: Option<u64>,
    /// Layer capacity of the run's state.
    capacity: usize,
    snapshot: Snapshot,
    /// The checkpoint written last (removed when the next one or the output is written).
    checkpoint: Option<PathBuf>,
}

impl<'a> Keeper<'a> {
    /// Keeps the work of the run `args` from `state`, read from `input`.
    pub fn new(args: &'a SimulateArgs, input: &'a MlhmScene, state: &ErosionState) -> Result<Self> {
        Ok(Keeper {
            output: &args.output,
            input_path: &args.input,
            template: SceneTemplate::of(input),
            checkpoint_every: args.checkpoint,
            capacity: state.max_layers(),
            snapshot: Snapshot::of(state)?,
            checkpoint: None,
        })
    }

    /// After the `done`-th step of the run (`last` for the run's last): writes a checkpoint
    /// when one is due (not after the last step: the output follows), keeps an in-memory copy
    /// every [`SNAPSHOT_EVERY`] steps.
    pub fn after_step(&mut self, state: &ErosionState, done: u64, last: bool) -> Result<()> {
        let due = self.checkpoint_every.is_some_and(|k| done.is_multiple_of(k)) && !last;
        if due {
            let path = self.write_beside(state)?;
            if let Some(previous) = self.checkpoint.replace(path) {
                remove_scene(&previous);
            }
        }
        if due || state.step_count() - self.snapshot.step >= SNAPSHOT_EVERY {
            self.snapshot = Snapshot::of(state)?;
        }
        Ok(())
    }

    /// The run's output was written: its last checkpoint is removed.
    pub fn finish(&mut self) {
        if let Some(previous) = self.checkpoint.take() {
            remove_scene(&previous);
        }
    }

    /// The scene file of `state`: the input's settings with the step count, the terrain in
    /// the layers it uses (at least the input's), the simulation planes.
    pub fn scene(&self, state: &ErosionState) -> Result<MlhmScene> {
        Ok(self.template.scene(state)?)
    }

    /// Writes `state` as `OUT.step-N.json` (with its `.dat`) beside the output; returns the
    /// path.
    fn write_beside(&self, state: &ErosionState) -> Result<PathBuf> {
        let path = beside(self.output, state.step_count());
        if same_file(&path, self.input_path) {
            // A run that failed at its first step, from a state saved so: the input holds it.
            return Ok(path);
        }
        write_scene(&path, &self.scene(state)?)
            .with_context(|| format!("writing the state at step {}", state.step_count()))?;
        Ok(path)
    }

    /// The run failed with `error` while `state` was still valid (a frame or a file could not
    /// be written): writes `state` beside the output and returns the error saying where.
    pub fn fail_with_valid(&mut self, error: anyhow::Error, state: &ErosionState) -> anyhow::Error {
        match self.write_beside(state) {
            Ok(path) => self.saved(error, &path, state.step_count()),
            Err(e) => error.context(format!("the last valid state was not saved either: {e:#}")),
        }
    }

    /// A step failed with `error` and left the state broken: replays the steps from the last
    /// in-memory copy up to the failed step's start (`failed_step`), writes that state
    /// beside the output and returns the error saying where.
    pub fn fail_with_broken(
        &mut self,
        error: anyhow::Error,
        failed_step: u64,
        params: &ErosionParams,
        seed: u64,
    ) -> anyhow::Error {
        match self.replay(failed_step, params, seed) {
            Ok((path, step)) => self.saved(error, &path, step),
            Err(e) => error.context(format!("the last valid state was not saved: {e:#}")),
        }
    }

    /// The state at step `until` (or the nearest before it the replay reaches), written
    /// beside the output; its path and step.
    fn replay(&self, until: u64, params: &ErosionParams, seed: u64) -> Result<(PathBuf, u64)> {
        let s = &self.snapshot;
        let mut state = ErosionState::from_mlhm(&s.map, Some(&s.planes), self.capacity, s.step)?;
        while state.step_count() < until {
            let mut next = state.clone();
            if next.step(params, seed).is_err() {
                break;
            }
            state = next;
        }
        Ok((self.write_beside(&state)?, state.step_count()))
    }

    /// `error`, with where the last valid state (at step `step`) was saved.
    fn saved(&self, error: anyhow::Error, path: &Path, step: u64) -> anyhow::Error {
        let shown = path.display();
        anyhow::anyhow!(
            "{error:#}; the last valid state, at step {step}, is saved as {shown} (continue \
             with relief simulate {shown} ...)"
        )
    }
}

/// Writes the simulated `scene` to `path` (`.json` or `.mlhm`, as relief-render's
/// [`relief_render::simulation::write_scene`]), saying "rounding to f16" where the terrain
/// could not be rounded to the scene's precision.
pub fn write_scene(path: &Path, scene: &MlhmScene) -> Result<()> {
    match relief_render::simulation::write_scene(path, scene) {
        Err(RenderError::Rounding(source)) => Err(source).context("rounding to f16"),
        written => Ok(written?),
    }
}

/// `OUT.step-N.json` beside the output `OUT.json` (or `OUT.mlhm`): a reference scene, which
/// holds the simulation state and step count whatever the output's format.
pub fn beside(output: &Path, step: u64) -> PathBuf {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    output.with_file_name(format!("{stem}.step-{step}.json"))
}

/// Removes the scene `path` wrote (its JSON first, then its `.dat`); a file already gone is
/// no error.
fn remove_scene(path: &Path) {
    let _ = std::fs::remove_file(path);
    let _ = std::fs::remove_file(path.with_extension("dat"));
}

/// Whether `a` and `b` name one existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}
