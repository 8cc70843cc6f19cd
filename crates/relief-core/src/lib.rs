//! relief-core: the data every part of relief shares and the invariants that hold for it.
//!
//! - [`HeightField`]: a grid of elevation samples with its georeference (spacing, origin, z scale);
//! - [`Surface`]: how a height field's samples become a surface (`boxes` or `triangles`);
//! - [`Mlhm`]: the multi-layered height map (cells of stacked [`MlhmColumn`]s of bedrock, sand,
//!   water and air) in the reference layout, with its invariants and conservative f16
//!   [`Precision`];
//! - [`MaterialStacks`]: material-stack terrains (layers of materials per grid point, air
//!   between them) and their LOD [`StacksMipmap`];
//! - [`Ray`], [`Aabb`]: geometry used by the tracers;
//! - [`Camera`]: the camera of relief's conventions, pinhole or orthographic ([`Projection`]),
//!   with automatic [`Framing`];
//! - [`colour`]: the sRGB encoding and its 8-bit tables; [`texture`]: a pixel's footprint on
//!   the terrain and the texture filter over it (shared by relief-shade and relief-tiles).
//!
//! ```
//! use relief_core::{HeightField, GridGeometry, Surface};
//! let field = HeightField::new(2, 2, vec![0.0, 1.0, 2.0, 3.0], GridGeometry::unit()).unwrap();
//! assert_eq!(field.sample(1, 1), 3.0);
//! let bounds = field.world_bounds(Surface::Boxes);
//! assert_eq!(bounds.max.z, 3.0);
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod aabb;
mod camera;
pub mod colour;
mod error;
mod framing;
mod height_field;
mod mlhm;
mod ray;
mod sample_region;
mod smooth_normals;
mod stacks;
mod surface;
pub mod texture;

pub use aabb::{Aabb, BoxFace, Clip};
pub use camera::{Camera, Projection};
pub use error::CoreError;
pub use framing::{Framing, Lens};
pub use height_field::{GridGeometry, HeightField};
pub use mlhm::{BlurredBox, MaterialVolumes, Mlhm, MlhmColumn, MlhmHeights, Precision};
pub use ray::Ray;
pub use sample_region::SampleRegion;
pub use smooth_normals::SmoothNormals;
pub use stacks::{
    aggregate, MaterialKind, MaterialStacks, StackLayer, StackMaterial, StacksMipmap,
};
pub use surface::{splits_along_ad, Surface};

/// Re-exported vector types used throughout relief's public API.
pub use glam::{DVec2, DVec3};
