//! Volume accounting: what a step adds or removes by design, and the totals of the terrain.

use super::ErosionState;

/// Volumes (m³) a step, or a run of steps, adds or removes by design. Water changes only by
/// rain, evaporation and `water_clamped`; material (bedrock + sand + suspended sediment)
/// changes only by [`StepVolumes::material_created`] minus
/// [`StepVolumes::material_removed`]. Counts are of events.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepVolumes {
    /// Steps accumulated.
    pub steps: u64,
    /// Water added by rain.
    pub rain: f64,
    /// Water removed by evaporation.
    pub evaporation: f64,
    /// Water removed where f32 rounding left it above a ceiling or below zero (negative:
    /// added); a few ulps per column at most.
    pub water_clamped: f64,
    /// Sand created beside bedrock that water erodes sideways; the column owes as much
    /// bedrock as damage until damage recovery or a split removes it.
    pub horizontal_erosion_sand: f64,
    /// Bedrock removed by damage recovery (paying damage back).
    pub damage_recovery: f64,
    /// Bedrock removed when a column splits: the whole exposed window.
    pub split_bedrock: f64,
    /// Sand filling the lower part of a split's gap: the window less the damage paid.
    pub split_sand: f64,
    /// Bedrock removed, as its damage, when a damaged column collapses.
    pub collapse_damage: f64,
    /// Sand removed where it would not fit under a ceiling (slippage into a full column, or
    /// f32 rounding); negative: added.
    pub sand_clamped: f64,
    /// Sediment added where f32 rounding drove it below zero (negative: removed).
    pub sediment_clamped: f64,
    /// Columns split.
    pub splits: u64,
    /// Columns collapsed (unsupported, too thin, or too close to the column below).
    pub collapses: u64,
}

impl StepVolumes {
    /// Material (bedrock + sand + sediment) the steps created by design.
    pub fn material_created(&self) -> f64 {
        self.horizontal_erosion_sand + self.split_sand + self.sediment_clamped
    }

    /// Material the steps removed by design.
    pub fn material_removed(&self) -> f64 {
        self.damage_recovery + self.split_bedrock + self.collapse_damage + self.sand_clamped
    }

    /// Fits `c` under its ceiling ([`fit_column`](super::slots::fit_column)), counting the
    /// water and sand removed as clamped.
    pub(crate) fn fit(&mut self, c: &mut relief_core::MlhmColumn) {
        let (water, sand) = super::slots::fit_column(c);
        self.water_clamped += f64::from(water);
        self.sand_clamped += f64::from(sand);
    }

    /// Adds `other` to these volumes.
    pub fn add(&mut self, other: &StepVolumes) {
        self.steps += other.steps;
        self.rain += other.rain;
        self.evaporation += other.evaporation;
        self.water_clamped += other.water_clamped;
        self.horizontal_erosion_sand += other.horizontal_erosion_sand;
        self.damage_recovery += other.damage_recovery;
        self.split_bedrock += other.split_bedrock;
        self.split_sand += other.split_sand;
        self.collapse_damage += other.collapse_damage;
        self.sand_clamped += other.sand_clamped;
        self.sediment_clamped += other.sediment_clamped;
        self.splits += other.splits;
        self.collapses += other.collapses;
    }

    /// Scales every volume by `area` (per-cell heights to m³).
    pub(crate) fn scaled(mut self, area: f64) -> Self {
        for v in [
            &mut self.rain,
            &mut self.evaporation,
            &mut self.water_clamped,
            &mut self.horizontal_erosion_sand,
            &mut self.damage_recovery,
            &mut self.split_bedrock,
            &mut self.split_sand,
            &mut self.collapse_damage,
            &mut self.sand_clamped,
            &mut self.sediment_clamped,
        ] {
            *v *= area;
        }
        self
    }

    /// The sum of `parts` in their order (deterministic whatever produced them).
    pub(crate) fn sum<'a>(parts: impl IntoIterator<Item = &'a StepVolumes>) -> StepVolumes {
        let mut total = StepVolumes::default();
        for p in parts {
            total.add(p);
        }
        total
    }
}

/// Totals of a terrain, m³. Bedrock counts from height 0 for the lowest column of each cell
/// (so changes of it are volumes) and from the floor for the columns above.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TerrainTotals {
    /// Bedrock.
    pub bedrock: f64,
    /// Sand.
    pub sand: f64,
    /// Water.
    pub water: f64,
    /// Suspended sediment.
    pub sediment: f64,
    /// Damage (bedrock owed).
    pub damage: f64,
}

impl TerrainTotals {
    /// Bedrock + sand + suspended sediment.
    pub fn material(&self) -> f64 {
        self.bedrock + self.sand + self.sediment
    }
}

impl ErosionState {
    /// The totals of the terrain, summed in f64 in slot order.
    pub fn totals(&self) -> TerrainTotals {
        let cells = self.cells();
        let mut t = TerrainTotals::default();
        for i in 0..cells {
            let mut floor = 0.0f64;
            for k in 0..usize::from(self.layer_counts[i]) {
                let s = i + k * cells;
                let c = self.columns[s];
                t.bedrock += f64::from(c.bedrock) - floor;
                t.sand += f64::from(c.sand);
                t.water += f64::from(c.water);
                t.sediment += f64::from(self.sediment[s]);
                t.damage += f64::from(self.damage[s]);
                floor = f64::from(c.ceiling);
            }
        }
        let area = f64::from(self.cell_size) * f64::from(self.cell_size);
        TerrainTotals {
            bedrock: t.bedrock * area,
            sand: t.sand * area,
            water: t.water * area,
            sediment: t.sediment * area,
            damage: t.damage * area,
        }
    }
}
