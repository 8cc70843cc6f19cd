//! The native part of relief's Python package: `open` (any input as a `Scene`, drawn by the
//! scene layer, relief_render, as `relief render` draws it), `simulate` (an MLHM scene's
//! erosion), `flight_plan` (a camera path's frames as `relief flythrough` plays it), and
//! `render`, `shade`, `intersect`, `read` and `write_png` over NumPy arrays,
//! with relief's errors raised as Python exceptions. The package `relief` (python/relief)
//! re-exports them; its `_relief.pyi` holds their type stubs.
//!
//! Every function validates its arguments before any work (no panic crosses into Python)
//! and releases the GIL while it reads, traces or simulates.

#![deny(missing_docs)]

mod arrays;
mod camera;
mod errors;
mod flythrough;
mod georeference;
mod info;
mod intersect;
mod open;
mod options;
mod picture;
mod read;
mod render;
mod scene;
mod shade;
mod shade_window;
mod simulate;
mod simulation;
mod solar;
mod state_arrays;
mod terrain;
mod viewshed;
mod write_png;

use pyo3::prelude::*;

/// The module `relief._relief`.
#[pymodule]
fn _relief(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ReliefError", m.py().get_type::<errors::ReliefError>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(open::open, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(intersect::intersect, m)?)?;
    m.add_function(wrap_pyfunction!(read::read, m)?)?;
    m.add_function(wrap_pyfunction!(shade::shade, m)?)?;
    m.add_function(wrap_pyfunction!(shade_window::shade_window, m)?)?;
    m.add_function(wrap_pyfunction!(shade_window::source_info, m)?)?;
    m.add_function(wrap_pyfunction!(viewshed::viewshed, m)?)?;
    m.add_function(wrap_pyfunction!(write_png::write_png, m)?)?;
    m.add_function(wrap_pyfunction!(solar::sun_position, m)?)?;
    m.add_function(wrap_pyfunction!(flythrough::flight_plan, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
