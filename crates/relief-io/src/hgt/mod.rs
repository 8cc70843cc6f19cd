//! SRTM `.hgt` tiles: big-endian int16 squares named after their south-west corner, read whole
//! ([`read_hgt`]) or by rows, and written ([`write_hgt`]).

pub(crate) mod rows;
pub(crate) mod tile;

pub use tile::{hgt_tile_corner, read_hgt, write_hgt, HGT_VOID};
