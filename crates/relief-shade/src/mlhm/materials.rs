//! The colours of an MLHM's materials and the albedo of a surface blended from the volume
//! fractions of the materials around it (Nilles & Müller 2025, section 4.6).

use relief_core::{DVec3, MaterialVolumes};
use relief_trace::MlhmMaterial;

/// Albedo of bedrock.
pub const BEDROCK_COLOUR: [f64; 3] = [0.5, 0.5, 0.5];
/// Albedo of sand.
pub const SAND_COLOUR: [f64; 3] = [0.9, 0.8, 0.6];
/// Colour of water seen as a surface (without refraction rays).
pub const WATER_COLOUR: [f64; 3] = [0.2, 0.4, 0.7];

/// The colour of one material (air has none: black).
pub fn material_colour(material: MlhmMaterial) -> DVec3 {
    match material {
        MlhmMaterial::Bedrock => DVec3::from(BEDROCK_COLOUR),
        MlhmMaterial::Sand => DVec3::from(SAND_COLOUR),
        MlhmMaterial::Water => DVec3::from(WATER_COLOUR),
        MlhmMaterial::Air => DVec3::ZERO,
    }
}

/// The albedo of terrain around a surface point: the colours of bedrock and sand weighted by
/// their shares of the solid `volumes` near the point; the colour of `hit_material` where no
/// solid is near (a degenerate neighbourhood).
pub fn solid_albedo(volumes: &MaterialVolumes, hit_material: MlhmMaterial) -> DVec3 {
    let solid = volumes.bedrock + volumes.sand;
    if solid.is_nan() || solid <= 0.0 {
        return material_colour(hit_material);
    }
    (DVec3::from(BEDROCK_COLOUR) * volumes.bedrock + DVec3::from(SAND_COLOUR) * volumes.sand)
        / solid
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn albedo_blends_by_volume() {
        let v = |bedrock, sand| MaterialVolumes { bedrock, sand, water: 5.0 };
        assert_eq!(solid_albedo(&v(2.0, 0.0), MlhmMaterial::Sand), DVec3::from(BEDROCK_COLOUR));
        assert_eq!(solid_albedo(&v(0.0, 1.0), MlhmMaterial::Bedrock), DVec3::from(SAND_COLOUR));
        let half = solid_albedo(&v(1.0, 1.0), MlhmMaterial::Sand);
        assert!((half - DVec3::new(0.7, 0.65, 0.55)).abs().max_element() < 1e-12);
        assert_eq!(solid_albedo(&v(0.0, 0.0), MlhmMaterial::Sand), DVec3::from(SAND_COLOUR));
    }
}
