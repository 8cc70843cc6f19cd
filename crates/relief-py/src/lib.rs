//! The native part of relief's Python package: `render`, `shade`, `intersect`, `read` and
//! `write_png` over NumPy arrays, with relief's errors raised as Python exceptions. The package
//! `relief` (python/relief) re-exports them; its `_relief.pyi` holds their type stubs.
//!
//! Every function validates its arguments before any work (no panic crosses into Python),
//! builds its tracer once per call and releases the GIL while it traces.

#![deny(missing_docs)]

mod arrays;
mod camera;
mod errors;
mod georeference;
mod intersect;
mod options;
mod read;
mod render;
mod shade;
mod terrain;
mod tracer;
mod write_png;

use pyo3::prelude::*;

/// The module `relief._relief`.
#[pymodule]
fn _relief(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ReliefError", m.py().get_type::<errors::ReliefError>())?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(intersect::intersect, m)?)?;
    m.add_function(wrap_pyfunction!(read::read, m)?)?;
    m.add_function(wrap_pyfunction!(shade::shade, m)?)?;
    m.add_function(wrap_pyfunction!(write_png::write_png, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
