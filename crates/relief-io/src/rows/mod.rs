//! Rasters read in bands of rows, never whole, whatever their format: the [`RowSource`]
//! trait, [`open_rows`] for one file (streamed where its format allows it), [`open_mosaic`]
//! for several joined into one, and [`open_ortho`] for an ortho photo read row by row.
//! The formats' own row readers are in their folders (`geotiff/rows.rs`, `hgt/rows.rs`,
//! `npy/rows.rs`).
//!
//! [`RowSource`]: crate::RowSource
//! [`open_rows`]: crate::open_rows
//! [`open_mosaic`]: crate::open_mosaic
//! [`open_ortho`]: crate::open_ortho

pub(crate) mod mosaic;
pub(crate) mod open_rows;
pub(crate) mod ortho;
pub(crate) mod row_source;
