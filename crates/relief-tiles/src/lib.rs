//! relief-tiles: height fields far larger than memory, as a tile pyramid on disk that frames
//! read in bounded memory (Dick et al. 2009, sections 3.4 and 4).
//!
//! - [`build_store`]: the pyramid of a raster read band by band ([`relief_io::RowSource`]),
//!   levels averaged 2x2, tiles with a ring of one sample, checksummed, resumable;
//!   [`PyramidLayout`] says which tile holds which samples;
//! - the store's format ([`StoreHeader`], [`TileRecord`], docs/tile-store.md) and
//!   [`TileStore`], which opens one and loads tiles as [`LoadedTile`]s, each with its own
//!   tracer from a [`TileTracerFactory`] the caller may give (a max-mipmap tracer by default);
//! - [`select_tiles`]: view-frustum culling and the screen-space error bound;
//! - [`TileStreamer`]: a frame's tiles from a [`TileCache`] and a loader thread, as a
//!   [`TiledTerrain`], which implements relief-trace's `Tracer` like a single height field
//!   and nests any tracer per tile, as pbrt's aggregates nest;
//! - an ortho photo's pyramid beside the heights ([`build_textured_store`],
//!   [`place_ortho`], [`TextureHeader`], [`TextureStore`]) and [`TextureStreamer`], whose
//!   [`TexturedFrame`] colours a frame from the tiles its pixels' footprints need, filtered
//!   anisotropically (section 3.3).

#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod builder;
mod cache;
mod error;
mod format;
mod layout;
mod lod;
mod record_table;
mod sized_file;
mod store;
mod stored_georeference;
mod streamer;
mod texture_builder;
mod texture_format;
mod texture_frame;
mod texture_placement;
mod texture_store;
mod tile_tracer;
mod tiled_terrain;

pub use builder::{
    build_store, build_textured_store, working_set_bytes, BuildOptions, BuildReport,
};
pub use cache::{CachedTile, TileCache};
pub use error::TileError;
pub use format::{precision_name, SourceFile, StoreHeader, StoredGeometry, TileRecord};
pub use layout::{PyramidLayout, Rect, TileId, MIN_TILE};
pub use lod::{outside_view, screen_error, select_tiles, tile_bounds};
pub use relief_core::Precision;
pub use store::{LoadedTile, TileStore};
pub use stored_georeference::StoredGeoreference;
pub use streamer::{estimated_tile_bytes, FrameRequest, FrameStats, TileStreamer};
pub use texture_builder::{texture_working_set_bytes, TextureInput};
pub use texture_format::{TextureHeader, TextureRecord};
pub use texture_frame::{TextureFrameStats, TextureStreamer, TexturedFrame};
pub use texture_placement::{place_ortho, DemPlacement, TexturePlacement};
pub use texture_store::{TextureStore, TextureTile};
pub use tile_tracer::{TileTracerFactory, TracedHeights};
pub use tiled_terrain::{TiledTerrain, TreeNode};
