//! One column of an MLHM cell ([`MlhmColumn`]): bedrock, sand, water and air up to its
//! ceiling, in the reference order, with its solid and water tops.

/// One column of an MLHM cell: four values in the reference order.
///
/// The column spans from its floor (the ceiling of the column below, or minus infinity for the
/// lowest column) up to [`water_top`](MlhmColumn::water_top): bedrock up to `bedrock`, then
/// `sand` metres of sand, then `water` metres of water; air from there up to `ceiling`, where
/// the bedrock of the next column begins. The topmost column's ceiling is `+inf`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct MlhmColumn {
    /// Absolute height of the bedrock's top, metres.
    pub bedrock: f32,
    /// Thickness of the sand on the bedrock, metres, >= 0.
    pub sand: f32,
    /// Thickness of the water on the sand, metres, >= 0.
    pub water: f32,
    /// Absolute height where this column's air ends (the floor of the column above); `+inf`
    /// for the topmost column.
    pub ceiling: f32,
}

impl MlhmColumn {
    /// A column with these four values.
    pub const fn new(bedrock: f32, sand: f32, water: f32, ceiling: f32) -> Self {
        MlhmColumn { bedrock, sand, water, ceiling }
    }

    /// Absolute height of the top of the solids: `bedrock + sand` (computed in f32).
    #[inline]
    pub fn solid_top(&self) -> f32 {
        self.bedrock + self.sand
    }

    /// Absolute height of the top of the water: `bedrock + sand + water` (computed in f32,
    /// left to right).
    #[inline]
    pub fn water_top(&self) -> f32 {
        self.bedrock + self.sand + self.water
    }

    /// The four values in the reference order (bedrock, sand, water, ceiling).
    #[inline]
    pub fn to_array(self) -> [f32; 4] {
        [self.bedrock, self.sand, self.water, self.ceiling]
    }

    /// A column from four values in the reference order (bedrock, sand, water, ceiling).
    #[inline]
    pub fn from_array(v: [f32; 4]) -> Self {
        MlhmColumn { bedrock: v[0], sand: v[1], water: v[2], ceiling: v[3] }
    }
}
