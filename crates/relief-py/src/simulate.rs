//! `relief.simulate`: steps of an MLHM scene's erosion, from a notebook, as `relief simulate`
//! takes them.

use crate::errors::invalid;
use crate::options::readable;
use crate::scene::PyScene;
use crate::simulation::Overrides;
use pyo3::prelude::*;
use std::ops::RangeInclusive;

/// Steps one call takes (as `relief simulate --steps`).
const STEPS: RangeInclusive<u64> = 1..=10_000_000;

/// Rain and evaporation, metres of water per second (as `--rain`, `--evaporation`).
const WATER_RATE: RangeInclusive<f64> = 0.0..=100.0;

/// The time step, seconds (as `--dt`).
const TIME_STEP: RangeInclusive<f64> = 0.001..=10.0;

/// Steps the erosion of an MLHM scene opened by ``relief.open`` (the layered erosion of
/// ``relief simulate``: rain, water flow, erosion and deposition, slippage, the support
/// check), ``steps`` steps with the rain's random numbers drawn from ``seed``. ``rain`` and
/// ``evaporation`` (metres of water per second, 0 to 100) and ``dt`` (seconds, 0.001 to 10)
/// replace the scene's own settings (else the reference simulator's defaults) for these
/// steps.
///
/// The first call starts from the scene's file (its saved simulation state and step count,
/// as ``relief simulate`` does); later calls continue, so that ``simulate(scene, 3)`` then
/// ``simulate(scene, 2)`` equal ``simulate(scene, 5)``. Afterwards ``scene.render`` draws the
/// stepped terrain, ``scene.state()`` reads it as arrays and ``scene.write(path)`` writes the
/// bytes ``relief simulate SCENE --steps N --seed S -o path`` writes, whatever the number of
/// threads. The GIL is released while the steps run.
///
/// Returns the steps simulated in all (the scene's own included). Raises
/// ``relief.ReliefError`` for a scene that is not an MLHM scene, options out of range, or a
/// step that breaks the terrain (the next call then starts again from the file).
#[pyfunction]
#[pyo3(signature = (scene, steps, *, seed=1, rain=None, evaporation=None, dt=None))]
pub fn simulate(
    py: Python<'_>,
    scene: &Bound<'_, PyScene>,
    steps: i64,
    seed: u64,
    rain: Option<f64>,
    evaporation: Option<f64>,
    dt: Option<f64>,
) -> PyResult<u64> {
    let steps = u64::try_from(steps).ok().filter(|s| STEPS.contains(s)).ok_or_else(|| {
        invalid(format!(
            "step count '{steps}' is not a whole number between {} and {}",
            STEPS.start(),
            STEPS.end()
        ))
    })?;
    let overrides = Overrides {
        rain: checked(rain, "water rate", &WATER_RATE, "m/s")?,
        evaporation: checked(evaporation, "water rate", &WATER_RATE, "m/s")?,
        dt: checked(dt, "time step", &TIME_STEP, "s")?,
    };
    scene.get().simulate(py, steps, seed, overrides)
}

/// `value` (named `what`, in `unit`), refused outside `range` with the command line's
/// message.
fn checked(
    value: Option<f64>,
    what: &str,
    range: &RangeInclusive<f64>,
    unit: &str,
) -> PyResult<Option<f32>> {
    match value {
        Some(v) if !range.contains(&v) => Err(invalid(format!(
            "{what} {} is outside {}..{} {unit}",
            readable(v),
            readable(*range.start()),
            readable(*range.end())
        ))),
        v => Ok(v.map(|v| v as f32)),
    }
}
