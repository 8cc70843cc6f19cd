//! The argument groups several subcommands share: how an input is read, the scene (tracer,
//! camera, light), the renderers' options, and the values' parsers. Each subcommand's own
//! arguments are in its folder (`commands/<command>/args.rs`).

mod furniture;
mod input;
mod renderer;
mod scene;
pub(crate) mod values;

pub use furniture::*;
pub use input::*;
pub use renderer::*;
pub use scene::*;
