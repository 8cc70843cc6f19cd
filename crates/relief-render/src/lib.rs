//! relief's scene layer: any input relief takes (a height file, an MLHM scene, a
//! material-stacks file, a tile store, or the default fBm terrain) opened as a [`Scene`] with
//! its tracer or renderer ([`TracerSpec`], [`TracerChoice`]) and its shading, rendered from a
//! [`Camera`](relief_core::Camera) into a [`Picture`]. The command line, the viewer and the
//! Python module all draw through it, so that one camera gives one picture in each.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod antialias;
pub mod block_shade;
pub mod camera;
pub mod camera_path;
pub mod colours;
pub mod draw;
pub mod error;
pub mod furniture;
pub mod input;
pub mod memory;
pub mod options;
pub mod progress;
pub mod scene;
pub mod scenes;
pub mod simulation;
pub mod tracer_spec;
pub mod warnings;

pub use antialias::Antialiasing;
pub use camera::{place_camera, CameraOptions, PlacedCamera, ViewAngles, DEFAULT_FOV_DEG};
pub use camera_path::{CameraKey, CameraPath, CAMERA_PATH_FORMAT, CAMERA_PATH_VERSION};
pub use colours::ColourSettings;
pub use draw::mesh::StacksDrawing;
pub use draw::picture::Picture;
pub use error::RenderError;
pub use furniture::MapFurniture;
pub use input::InputKind;
pub use memory::{Budget, ImageHolding};
pub use options::{
    HybridSettings, LightSettings, MeshSettings, MlhmSettings, ReadSettings, RenderMode,
    SceneOptions, StoreSettings, TerrainSettings,
};
pub use progress::{Progress, Silent};
pub use relief_shade::KeptHits;
pub use scene::Scene;
pub use scenes::height_field::HeightFieldScene;
pub use scenes::mlhm::{LayeredScene, MlhmTracerChoice};
pub use scenes::stacks::StacksScene;
pub use scenes::store::StoreScene;
pub use tracer_spec::{BuiltTracer, SafetySettings, TracerChoice, TracerSpec};

/// The README's library examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
