//! The materials of a stacks terrain: a name, a display colour and whether it is a solid or a
//! liquid ([`StackMaterial`]).

/// Whether a material is part of the terrain's solid or a liquid (meshed apart, as `water`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MaterialKind {
    /// Rock, sand, soil: meshed into the `solid`.
    Solid,
    /// Water: meshed into its own mesh.
    Liquid,
}

/// One material a stacks terrain names.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct StackMaterial {
    /// Its name (`bedrock`, `sand`, `water`, ...).
    pub name: String,
    /// Its display colour, sRGB.
    pub color: [u8; 3],
    /// Solid or liquid.
    pub kind: MaterialKind,
}

impl StackMaterial {
    /// Index of bedrock in [`StackMaterial::defaults`].
    pub const BEDROCK: u8 = 0;
    /// Index of sand in [`StackMaterial::defaults`].
    pub const SAND: u8 = 1;
    /// Index of water in [`StackMaterial::defaults`].
    pub const WATER: u8 = 2;

    /// A material.
    pub fn new(name: &str, color: [u8; 3], kind: MaterialKind) -> Self {
        StackMaterial { name: name.to_string(), color, kind }
    }

    /// The palette of MLHM-made stacks: bedrock (0), sand (1) and water (2), in the colours of
    /// relief's MLHM shading.
    pub fn defaults() -> Vec<StackMaterial> {
        vec![
            StackMaterial::new("bedrock", [128, 118, 108], MaterialKind::Solid),
            StackMaterial::new("sand", [214, 190, 140], MaterialKind::Solid),
            StackMaterial::new("water", [40, 90, 150], MaterialKind::Liquid),
        ]
    }

    /// Whether the material is a liquid.
    pub fn is_liquid(&self) -> bool {
        self.kind == MaterialKind::Liquid
    }
}
