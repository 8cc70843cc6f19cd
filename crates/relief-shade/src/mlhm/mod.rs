//! Shading of multi-layered height maps (Nilles & Müller 2025, sections 4.6 and 5): the
//! reference BRDF, the procedural sky as light, water, material colours, the geometric
//! ambient occlusion, the quality presets and the renderer that puts them together.

mod brdf;
mod environment;
mod materials;
mod preset;
mod render;
mod water;

pub use brdf::{
    fresnel, reflect, refract, schlick, MicrofacetLobe, TERRAIN_F0, TERRAIN_ROUGHNESS,
    TERRAIN_UNDER_WATER_F0, WATER_F0, WATER_IOR, WATER_ROUGHNESS,
};
pub use environment::{reference_sky, SkyLight, GROUND_RADIANCE};
pub use materials::{material_colour, solid_albedo, BEDROCK_COLOUR, SAND_COLOUR, WATER_COLOUR};
pub use preset::{MlhmPreset, MlhmQuality, WaterAbsorption};
pub use render::{render_mlhm, MlhmImage, MlhmRayCounts, MlhmShading, SKY_LIGHT};
pub use water::{absorption_distance, water_transmittance, WATER_EXTINCTION};
