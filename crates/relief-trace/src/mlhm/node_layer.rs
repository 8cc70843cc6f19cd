//! The bounds of one layer of an MLHM hierarchy node ([`MlhmNodeLayer`]): what the
//! hierarchy stores and its build merges.

/// The four bounds of one layer of a hierarchy node, over every column it stands for.
///
/// For layer `k` of a node, the boxes of the three [`MlhmMode`](crate::MlhmMode)s are enclosed by
///
/// - solids: `[ceiling_min(k - 1), solid_max(k)]`,
/// - solids + water: `[ceiling_min(k - 1), water_max(k)]`,
/// - solids + air: `[air_min(k - 1), solid_max(k)]`, plus the open sky above the node,
///   `[sky_min, +inf]` (see [`MlhmHierarchy::sky_min`](crate::MlhmHierarchy::sky_min)),
///
/// with `ceiling_min(-1) = air_min(-1) = -inf`. A layer no column of the node reaches holds
/// `-inf` maxima and `+inf` minima.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlhmNodeLayer {
    /// Highest water top (`bedrock + sand + water`).
    pub water_max: f32,
    /// Lowest ceiling: the lowest floor of the layer above.
    pub ceiling_min: f32,
    /// Highest solid top (`bedrock + sand`).
    pub solid_max: f32,
    /// Lowest water top: where the air of the layer (the bottom of the air box of the layer
    /// above, for rays inside water) begins at the lowest.
    pub air_min: f32,
}

impl MlhmNodeLayer {
    /// The bounds of a layer nothing reaches: any column merged in replaces them.
    pub const EMPTY: MlhmNodeLayer = MlhmNodeLayer {
        water_max: f32::NEG_INFINITY,
        ceiling_min: f32::INFINITY,
        solid_max: f32::NEG_INFINITY,
        air_min: f32::INFINITY,
    };

    /// These bounds widened to enclose `other` as well.
    #[inline]
    pub fn merge(self, other: MlhmNodeLayer) -> MlhmNodeLayer {
        MlhmNodeLayer {
            water_max: self.water_max.max(other.water_max),
            ceiling_min: self.ceiling_min.min(other.ceiling_min),
            solid_max: self.solid_max.max(other.solid_max),
            air_min: self.air_min.min(other.air_min),
        }
    }
}
