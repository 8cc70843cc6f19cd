//! The error type of relief-mesh: invalid meshes, targets and parameters, and failed mesh
//! exports, arranged by cause.

use std::path::PathBuf;
use thiserror::Error;

/// What can be wrong with a mesh, a raster target or a parameter handed to relief-mesh.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshError {
    /// A triangle names a vertex the mesh does not have.
    #[error(
        "triangle {triangle} refers to vertex {index}, but the mesh has {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the offending triangle.
        triangle: usize,
        /// The vertex index found.
        index: u32,
        /// Number of vertices of the mesh.
        vertex_count: usize,
    },
    /// A vertex position is NaN or infinite.
    #[error("vertex {index} has the non-finite position ({x}, {y}, {z})")]
    NonFinitePosition {
        /// Index of the offending vertex.
        index: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
        /// Its z.
        z: f64,
    },
    /// Per-vertex attributes do not match the vertices (count, or a value not finite).
    #[error("invalid vertex attributes: {0}")]
    Attributes(String),
    /// A raster target's size differs from the camera's image.
    #[error("raster target is {target_width}x{target_height} but the camera renders {camera_width}x{camera_height}")]
    TargetSize {
        /// Width of the target.
        target_width: usize,
        /// Height of the target.
        target_height: usize,
        /// Width of the camera's image.
        camera_width: u32,
        /// Height of the camera's image.
        camera_height: u32,
    },
    /// A size or count exceeds what relief-mesh can index (u32 vertex and triangle ids).
    #[error("limit exceeded: {0}")]
    Limits(String),
    /// A parameter is out of range.
    #[error("invalid {name}: {reason}")]
    Parameter {
        /// Which parameter.
        name: &'static str,
        /// Why it was refused.
        reason: String,
    },
    /// A path's extension names no mesh format relief-mesh writes.
    #[error("{}: unknown mesh format: the extension must be .glb, .obj or .ply", path.display())]
    UnknownFormat {
        /// The path whose extension was not recognised.
        path: PathBuf,
    },
}
