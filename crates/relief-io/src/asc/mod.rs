//! ESRI ASCII grids (`.asc`): read ([`read_asc`]) and written ([`write_asc`]), with the `.prj`
//! beside them naming their CRS.

pub(crate) mod grid;

pub use grid::{read_asc, write_asc};
