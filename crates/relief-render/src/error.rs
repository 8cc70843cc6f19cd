//! What can go wrong opening or rendering a scene, by cause. The messages are the ones the
//! `relief` tool shows its users.

use crate::memory::{format_bytes, Budget};
use relief_core::CoreError;
use relief_io::IoError;
use relief_mesh::MeshError;
use relief_shade::ShadeError;
use relief_sim::erosion::ErosionError;
use relief_tiles::TileError;
use relief_trace::TraceError;
use std::path::PathBuf;

/// An error of the scene layer.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// Reading an input (or a texture) failed.
    #[error(transparent)]
    Io(#[from] IoError),
    /// A terrain, camera or grid that is not valid.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// A tracer could not be built or refused its rays.
    #[error(transparent)]
    Trace(#[from] TraceError),
    /// Shading or a renderer failed.
    #[error(transparent)]
    Shade(#[from] ShadeError),
    /// A mesher could not be made.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A tile store could not be opened or streamed.
    #[error(transparent)]
    Tiles(#[from] TileError),
    /// The spacing or z scale asked for cannot place the terrain.
    #[error("invalid placement")]
    Placement(#[source] CoreError),
    /// The default fBm terrain could not be generated.
    #[error("generating fBm terrain")]
    Fbm(#[source] CoreError),
    /// A default fBm terrain of a size out of range.
    #[error("terrain size {0} must be between 1 and 65536")]
    TerrainSize(usize),
    /// A default fBm terrain (with the pyramid a render builds over it) over the budget.
    #[error(
        "a {size}x{size} terrain needs {}, over the {} memory limit ({})",
        format_bytes(*.needed), format_bytes(.budget.bytes), .budget.origin
    )]
    TerrainOverBudget {
        /// Samples a side.
        size: usize,
        /// Bytes it needs.
        needed: u64,
        /// The budget.
        budget: Budget,
    },
    /// An image over the budget.
    #[error(
        "a {width}x{height} image needs {}, over the {} memory limit ({})",
        format_bytes(*.needed), format_bytes(.budget.bytes), .budget.origin
    )]
    ImageOverBudget {
        /// Pixels a row.
        width: u32,
        /// Rows.
        height: u32,
        /// Bytes it needs.
        needed: u64,
        /// The budget.
        budget: Budget,
    },
    /// Safety shapes over the memory limit.
    #[error(
        "{options} shapes for a {width}x{height} terrain need about {}, over the {} memory \
         limit (raise it with --max-memory, or use --isotropic or the mipmap tracer)",
        format_bytes(*.needed), format_bytes(*.limit)
    )]
    ShapesOverBudget {
        /// The shapes' variant and options, as they print.
        options: String,
        /// The terrain's samples a row.
        width: usize,
        /// The terrain's rows.
        height: usize,
        /// Bytes they need.
        needed: u64,
        /// The limit, bytes.
        limit: u64,
    },
    /// Safety options that do not go together.
    #[error("{0}")]
    SafetyOptions(String),
    /// The safety tracer could not be made from its shapes.
    #[error("safety tracer")]
    SafetyTracer(#[source] TraceError),
    /// A texture that cannot be draped.
    #[error("texture {}", .path.display())]
    Texture {
        /// The texture's file.
        path: PathBuf,
        /// Why.
        source: ShadeError,
    },
    /// An input whose material stacks cannot be made.
    #[error("stacks of {}", .path.display())]
    Stacks {
        /// The input.
        path: PathBuf,
        /// Why.
        source: CoreError,
    },
    /// A tracer, renderer, mode or option that does not draw this scene (the message says
    /// what does).
    #[error("{0}")]
    Unsupported(String),
    /// Map furniture the picture does not define (a scale bar on a perspective picture, ...).
    #[error("{0}")]
    Furniture(String),
    /// Colour options that cannot colour the heights (a reversed range, a sea level for a
    /// map without a sea, a colour map with a draped texture).
    #[error("{0}")]
    Colours(String),
    /// A smoothing radius out of the range the smooth surface renders in.
    #[error(
        "--sigma {} m is outside {}..{} m (1/64 of a cell to 8 cells of {} m): smaller radii \
         take ever more marching steps, larger ones ever larger volume queries",
        readable(*.sigma), readable(*.low), readable(*.high), readable(*.cell)
    )]
    SigmaOutOfRange {
        /// The radius asked for, metres.
        sigma: f64,
        /// The smallest radius, metres.
        low: f64,
        /// The largest radius, metres.
        high: f64,
        /// The scene's cell size, metres.
        cell: f64,
    },
    /// A simulation step failed.
    #[error(transparent)]
    Erosion(#[from] ErosionError),
    /// A scene whose simulation would not fit the memory budget.
    #[error(
        "simulating {width} x {height} cells of {capacity} layers needs {needed_mib} MiB, over \
         the {} MiB memory limit ({})",
        .budget.bytes >> 20, .budget.origin
    )]
    SimulationOverBudget {
        /// Cells a row.
        width: usize,
        /// Rows.
        height: usize,
        /// Layers a column holds.
        capacity: usize,
        /// MiB it needs.
        needed_mib: u128,
        /// The budget.
        budget: Budget,
    },
    /// A scene whose simulation state cannot be made.
    #[error("{}", .path.display())]
    SimulationState {
        /// The scene.
        path: PathBuf,
        /// Why.
        source: ErosionError,
    },
    /// A scene whose simulation settings are not valid.
    #[error("the simulation settings of {}", .path.display())]
    SimulationSettings {
        /// The scene.
        path: PathBuf,
        /// Why.
        source: ErosionError,
    },
    /// A simulated terrain that could not be rounded to its scene's precision.
    #[error("rounding to the scene's precision")]
    Rounding(#[source] CoreError),
    /// A camera-path file that is not one.
    #[error("camera path {}: {reason}", .path.display())]
    CameraPath {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A camera-path file that could not be read or written.
    #[error("{}: {source}", .path.display())]
    CameraPathFile {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// An MLHM scene without a finite box.
    #[error("the scene has no finite bounds ({0})")]
    NoFiniteBounds(String),
    /// A raster that cannot be shaded block by block, and why.
    #[error("{}: {reason}", .path.display())]
    ShadeSource {
        /// The raster or tile store.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// Shading block by block that does not fit in the memory budget even with the smallest
    /// blocks.
    #[error(
        "shading blocks of {block} x {block} samples with a halo of {halo} needs {}, over the \
         {} memory limit ({}){hint}",
        format_bytes(*.needed), format_bytes(.budget.bytes), .budget.origin
    )]
    ShadeOverBudget {
        /// The smallest block's side.
        block: usize,
        /// The halo around it.
        halo: usize,
        /// Bytes it needs.
        needed: u64,
        /// The budget.
        budget: Budget,
        /// What would help.
        hint: String,
    },
}

/// A number for a message: plain decimals for everyday magnitudes, scientific notation for
/// the rest (never 300 digits).
pub fn readable(v: f64) -> String {
    if v == 0.0 || (1e-4..1e9).contains(&v.abs()) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}
