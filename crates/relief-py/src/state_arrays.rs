//! An MLHM scene's erosion state as NumPy arrays: the columns' heights and the simulator's
//! planes, layer-major `(L, H, W)` as the scene file stores them.

use crate::simulation::Simulation;
use numpy::ndarray::{Array2, Array3, Array4};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::MlhmColumn;
use relief_render::RenderError;
use relief_sim::erosion::SimulationPlanes;

/// A copy of a simulation's state, taken while the scene is locked, turned into arrays once
/// the GIL is held again.
pub struct StateCopy {
    /// Layer planes.
    layers: usize,
    /// Cells along x.
    width: usize,
    /// Cells along y.
    height: usize,
    /// Cell size, metres.
    cell_size: f64,
    /// Steps simulated so far.
    step: u64,
    /// Columns of each cell.
    layer_counts: Vec<u8>,
    /// Every column slot, layer-major.
    columns: Vec<MlhmColumn>,
    /// The simulator's planes, layer-major.
    planes: SimulationPlanes,
}

impl StateCopy {
    /// The state of `simulation` in the layer planes its file holds.
    pub fn of(simulation: &Simulation) -> Result<StateCopy, RenderError> {
        let map = simulation.terrain()?;
        Ok(StateCopy {
            layers: map.max_layers(),
            width: map.width(),
            height: map.height(),
            cell_size: map.cell_size(),
            step: simulation.state().step_count(),
            layer_counts: map.layer_counts().to_vec(),
            columns: map.raw_columns().to_vec(),
            planes: simulation.planes(),
        })
    }
}

/// The dict `Scene.state` returns (its docstring says what each array holds).
pub fn state_arrays(py: Python<'_>, copy: StateCopy) -> PyResult<Bound<'_, PyDict>> {
    let shape = (copy.layers, copy.height, copy.width);
    let plane = |values: Vec<f32>| -> PyResult<Bound<'_, PyAny>> {
        let array = Array3::from_shape_vec(shape, values)
            .map_err(|e| crate::errors::invalid(format!("state of {shape:?}: {e}")))?;
        Ok(array.into_pyarray(py).into_any())
    };
    let column_plane =
        |value: fn(&MlhmColumn) -> f32| plane(copy.columns.iter().map(value).collect());
    let dict = PyDict::new(py);
    dict.set_item("bedrock", column_plane(|c| c.bedrock)?)?;
    dict.set_item("sand", column_plane(|c| c.sand)?)?;
    dict.set_item("water", column_plane(|c| c.water)?)?;
    dict.set_item("ceiling", column_plane(|c| c.ceiling)?)?;
    let SimulationPlanes { fluxes, stability, sediment, damage } = copy.planes;
    dict.set_item("sediment", plane(sediment)?)?;
    dict.set_item("damage", plane(damage)?)?;
    dict.set_item("stability", plane(stability)?)?;
    let (l, h, w) = shape;
    let fluxes = Array4::from_shape_vec((l, h, w, 4), fluxes.into_iter().flatten().collect())
        .map_err(|e| crate::errors::invalid(format!("fluxes of {shape:?}: {e}")))?;
    dict.set_item("fluxes", fluxes.into_pyarray(py))?;
    let counts = Array2::from_shape_vec((h, w), copy.layer_counts)
        .map_err(|e| crate::errors::invalid(format!("layer counts of {h} x {w}: {e}")))?;
    dict.set_item("layer_counts", counts.into_pyarray(py))?;
    dict.set_item("step", copy.step)?;
    dict.set_item("cell_size", copy.cell_size)?;
    Ok(dict)
}
