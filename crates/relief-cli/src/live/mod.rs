//! The scenes `relief view` draws frame after frame: [`SceneRenderer`]s over the scenes the command
//! line opens, rendering with relief's tracers and shading exactly as `relief render` does (a tile
//! store's tiles streamed for each frame), with the settings the viewer switches at run time, and
//! an MLHM scene's erosion simulation, run as `relief simulate` runs it.
//!
//! [`SceneRenderer`]: relief_viewer::SceneRenderer

mod height_field;
mod interruptible;
mod mlhm;
mod simulation;
mod stacks;
mod tiles;

pub use height_field::LiveHeightField;
pub use mlhm::LiveMlhm;
pub use stacks::LiveStacks;
pub use tiles::LiveTiles;

/// The index of `name` in `names`, or 0.
fn position(names: &[String], name: &str) -> usize {
    names.iter().position(|n| n == name).unwrap_or(0)
}
