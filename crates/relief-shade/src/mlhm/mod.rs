//! Shading of multi-layered height maps (Nilles & Müller 2025, sections 4.6 and 5): the
//! reference materials and water optics, the procedural sky as light, the geometric ambient
//! occlusion, the quality presets, the renderer that draws a G-buffer of MLHM hits and the
//! deferred lighting over it.

mod brdf;
mod environment;
mod footprint;
mod lighting;
mod materials;
mod preset;
mod ray_counts;
mod render;
mod renderer;
mod shading;
mod water;

pub use crate::shading::schlick;
pub use brdf::{
    fresnel, reflect, refract, TERRAIN_F0, TERRAIN_ROUGHNESS, TERRAIN_UNDER_WATER_F0, WATER_F0,
    WATER_IOR, WATER_ROUGHNESS,
};
pub use environment::{reference_sky, SkyLight, GROUND_RADIANCE};
pub use footprint::{
    filtered_normal, lift_direction, lit_share, NORMAL_FILTER_FOOTPRINTS, VISIBILITY_BISECTIONS,
};
pub use lighting::shade_mlhm;
pub use materials::{material_colour, solid_albedo, BEDROCK_COLOUR, SAND_COLOUR, WATER_COLOUR};
pub use preset::{MlhmPreset, MlhmQuality, WaterAbsorption};
pub use ray_counts::MlhmRayCounts;
pub use render::{render_mlhm, render_mlhm_marked, MlhmImage};
pub use renderer::MlhmRenderer;
pub use shading::{MlhmShading, SKY_LIGHT};
pub use water::{absorption_distance, water_transmittance, WATER_EXTINCTION};
