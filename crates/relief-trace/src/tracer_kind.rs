//! The height-field tracers to choose from by name, and building one.

use crate::{MipmapTracer, NaiveTracer, Tracer};
use relief_core::{HeightField, Surface};
use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

/// The height-field tracers relief offers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TracerKind {
    /// Cell-by-cell traversal: simple and slow, the reference.
    Naive,
    /// Max-mipmap quadtree traversal.
    #[default]
    Mipmap,
}

impl TracerKind {
    /// Every kind, in a fixed order.
    pub const ALL: [TracerKind; 2] = [TracerKind::Naive, TracerKind::Mipmap];

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            TracerKind::Naive => "naive",
            TracerKind::Mipmap => "mipmap",
        }
    }
}

impl fmt::Display for TracerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for TracerKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "naive" => Ok(TracerKind::Naive),
            "mipmap" => Ok(TracerKind::Mipmap),
            other => Err(format!("unknown tracer '{other}' (expected naive or mipmap)")),
        }
    }
}

/// Builds a tracer of `kind` for `surface` of `field` (for the mipmap, this builds the pyramid).
pub fn build_tracer(
    field: Arc<HeightField>,
    surface: Surface,
    kind: TracerKind,
) -> Box<dyn Tracer> {
    match kind {
        TracerKind::Naive => Box::new(NaiveTracer::new(field, surface)),
        TracerKind::Mipmap => Box::new(MipmapTracer::new(field, surface)),
    }
}
