//! The tracer each loaded tile gets: any tracer nests in a [`crate::TiledTerrain`], as pbrt's
//! aggregates nest, made by a constructor the caller gives ([`TileTracerFactory`]; by default
//! the max-mipmap tracer).

use relief_core::{HeightField, Surface};
use relief_trace::{build_tracer, MipmapTracer, Tracer, TracerKind};
use std::fmt;
use std::sync::Arc;

/// The constructor of a tile's tracer from the tile's heights and the surface to trace.
type MakeTracer = dyn Fn(Arc<HeightField>, Surface) -> Box<dyn Tracer> + Send + Sync;

/// Makes the tracer of every tile a [`crate::TileStore`] loads, from the tile's height field
/// (its samples and ring, standing on the raster's floor) and the surface: the leaves of a
/// [`crate::TiledTerrain`]. The default is relief-trace's [`MipmapTracer`].
#[derive(Clone)]
pub struct TileTracerFactory {
    make: Arc<MakeTracer>,
    /// What the tracers are, for reports and `Debug`.
    description: String,
}

impl TileTracerFactory {
    /// Tile tracers made by `make`, described as `description` (e.g. `naive`).
    pub fn new(
        description: impl Into<String>,
        make: impl Fn(Arc<HeightField>, Surface) -> Box<dyn Tracer> + Send + Sync + 'static,
    ) -> Self {
        TileTracerFactory { make: Arc::new(make), description: description.into() }
    }

    /// Tile tracers of `kind` ([`build_tracer`]).
    pub fn of_kind(kind: TracerKind) -> Self {
        Self::new(kind.to_string(), move |field, surface| build_tracer(field, surface, kind))
    }

    /// The tracer of a tile whose heights are `field`, on `surface`.
    pub fn make(&self, field: Arc<HeightField>, surface: Surface) -> Box<dyn Tracer> {
        (self.make)(field, surface)
    }

    /// What the tracers are (e.g. `mipmap`).
    pub fn description(&self) -> &str {
        &self.description
    }
}

impl Default for TileTracerFactory {
    /// Max-mipmap tracers, with their ray packets.
    fn default() -> Self {
        Self::new("mipmap", |field, surface| Box::new(MipmapTracer::new(field, surface)))
    }
}

impl fmt::Debug for TileTracerFactory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("TileTracerFactory").field(&self.description).finish()
    }
}

/// A loaded tile's heights and the tracer made over them.
pub struct TracedHeights {
    /// The tile's height field (for its slope under texture filtering).
    pub field: Arc<HeightField>,
    /// The tracer over it.
    pub tracer: Box<dyn Tracer>,
}

impl fmt::Debug for TracedHeights {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TracedHeights")
            .field("width", &self.field.width())
            .field("height", &self.field.height())
            .field("tracer", &self.tracer.name())
            .finish()
    }
}
