//! What an MLHM rendering traced and looked up, by kind of ray.

use crate::TraceStats;

/// The rays and lookups a rendering made, by kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MlhmRayCounts {
    /// Camera rays.
    pub primary: TraceStats,
    /// Shadow rays towards the sun.
    pub shadow: TraceStats,
    /// Rays reflected off water.
    pub reflection: TraceStats,
    /// Rays refracted through water.
    pub refraction: TraceStats,
    /// Upward rays to the water surface (expensive absorption); in box mode each stays in
    /// its cell.
    pub upward: TraceStats,
    /// Ambient-occlusion volumes measured.
    pub occlusion: u64,
}

impl MlhmRayCounts {
    /// The counts of both `self` and `other`.
    #[must_use]
    pub fn merge(self, other: MlhmRayCounts) -> MlhmRayCounts {
        MlhmRayCounts {
            primary: self.primary.merge(other.primary),
            shadow: self.shadow.merge(other.shadow),
            reflection: self.reflection.merge(other.reflection),
            refraction: self.refraction.merge(other.refraction),
            upward: self.upward.merge(other.upward),
            occlusion: self.occlusion + other.occlusion,
        }
    }

    /// Rays traced through the scene: primary, shadow, reflected, refracted and upward rays.
    pub fn rays(&self) -> u64 {
        self.primary.rays
            + self.shadow.rays
            + self.reflection.rays
            + self.refraction.rays
            + self.upward.rays
    }
}
