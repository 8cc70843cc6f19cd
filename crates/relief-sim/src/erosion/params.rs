//! The erosion simulation's parameters, with the reference simulator's defaults and units.

use super::ErosionError;

/// Parameters of one erosion step. [`Default`] gives the reference simulator's values
/// (`core/geo/components/terrain.hpp` and the notes in `mlhm-reference-notes.md`).
///
/// Lengths are metres, times seconds, volumes per cell are heights (m) times the cell area.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErosionParams {
    /// Time step, s (0.15).
    pub dt: f32,
    /// Gravity, m/s² (9.81; the reference stores -9.81 and subtracts).
    pub gravity: f32,
    /// Mean rain rate, m/s of water on the top column (0.07); each cell gets `2 u rain dt`
    /// with `u` uniform in [0, 1).
    pub rain: f32,
    /// Evaporation rate, m/s (0.09), scaled by the air gap (see `evaporation_air_gap`).
    pub evaporation: f32,
    /// Air gap, m, above which evaporation is at its full rate; below, it is scaled by
    /// `clamp(gap / evaporation_air_gap, 0.01, 1)` (10).
    pub evaporation_air_gap: f32,
    /// Damping of the pipes' flux, 1/s (0.01): `f <- (1 - damping dt) f + ...`.
    pub flux_damping: f32,
    /// Sand turning into bedrock, 1/s of the sand thickness (5e-4).
    pub petrification: f32,
    /// Whether sand slips down slopes steeper than the talus angle (true).
    pub slippage: bool,
    /// Talus angle of dry sand, degrees (30).
    pub dry_talus_angle: f32,
    /// Talus angle of wet sand, degrees (10), reached at `slippage_interpolation_range` m of
    /// mean water depth over the pipe.
    pub wet_talus_angle: f32,
    /// Water depth, m, over which the talus angle goes from dry to wet (1).
    pub slippage_interpolation_range: f32,
    /// Fraction of the excess sand-top difference that slips per step (0.125).
    pub slippage_rate: f32,
    /// Whether water dissolves and deposits material vertically (true).
    pub vertical_erosion: bool,
    /// Sediment capacity constant, m of sediment per (m/s) of speed (0.1).
    pub sediment_capacity: f32,
    /// Bedrock dissolving constant, 1/s (0.01).
    pub bedrock_dissolving: f32,
    /// Sand dissolving constant, 1/s (0.05).
    pub sand_dissolving: f32,
    /// Sediment deposition constant, 1/s (0.04).
    pub deposition: f32,
    /// Slope factor at zero slope (0.1): factor `min + (max - min) sin a (1 - fade)`.
    pub min_slope_erosion_scale: f32,
    /// Slope factor at the steepest slope (1).
    pub max_slope_erosion_scale: f32,
    /// sin of the slope where the slope factor starts to fade (0.6); fades to 0 at 1.
    pub slope_fade_start: f32,
    /// Speed factor at rest (0.1): factor `min_speed_erosion_scale + (1 - min) |v|`.
    pub min_speed_erosion_scale: f32,
    /// Water depth, m, at which the water factor `1 - tanh(2 depth / this)` nears 0 (10).
    pub erosion_water_max_height: f32,
    /// Sand thickness, m, below which bedrock dissolves (linearly more as sand thins) (0.01).
    pub sand_threshold: f32,
    /// Distance, m, of the water top below a ceiling within which water erodes the ceiling (2).
    pub top_erosion_distance: f32,
    /// Whether water erodes bedrock sideways, damaging and splitting columns (true).
    pub horizontal_erosion: bool,
    /// sin of the slope from which horizontal erosion starts (0.9).
    pub min_horizontal_erosion_slope: f32,
    /// Horizontal erosion strength, 1/m (0.1).
    pub horizontal_erosion_strength: f32,
    /// Damage, m, at which a column splits (0.75).
    pub split_damage: f32,
    /// Damage recovery, m/s (0.005): damage paid back by lowering the bedrock.
    pub damage_recovery: f32,
    /// Whether unsupported columns collapse (true).
    pub support_check: bool,
    /// Bedrock density, kg/m³ (2600).
    pub bedrock_density: f32,
    /// Sand density, kg/m³ (1600).
    pub sand_density: f32,
    /// Water density, kg/m³ (1000).
    pub water_density: f32,
    /// Weight a square metre of bedrock contact supports, kg/m² (60000).
    pub bedrock_support: f32,
    /// Weight a square metre of contact with the domain's wall supports, kg/m² (60000).
    pub border_support: f32,
    /// Bedrock thinner than this, m, above an air gap collapses (1).
    pub min_bedrock_thickness: f32,
    /// Distance, m, support propagates before the check collapses what is unsupported (100);
    /// one propagation pass per cell, so a check lasts `ceil(distance / cell size)` passes.
    pub support_distance: f32,
    /// Propagation passes (each a two-colour checkerboard sweep) per step (5).
    pub support_passes_per_step: u32,
}

impl Default for ErosionParams {
    fn default() -> Self {
        ErosionParams {
            dt: 0.15,
            gravity: 9.81,
            rain: 0.07,
            evaporation: 0.09,
            evaporation_air_gap: 10.0,
            flux_damping: 0.01,
            petrification: 5e-4,
            slippage: true,
            dry_talus_angle: 30.0,
            wet_talus_angle: 10.0,
            slippage_interpolation_range: 1.0,
            slippage_rate: 0.125,
            vertical_erosion: true,
            sediment_capacity: 0.1,
            bedrock_dissolving: 0.01,
            sand_dissolving: 0.05,
            deposition: 0.04,
            min_slope_erosion_scale: 0.1,
            max_slope_erosion_scale: 1.0,
            slope_fade_start: 0.6,
            min_speed_erosion_scale: 0.1,
            erosion_water_max_height: 10.0,
            sand_threshold: 0.01,
            top_erosion_distance: 2.0,
            horizontal_erosion: true,
            min_horizontal_erosion_slope: 0.9,
            horizontal_erosion_strength: 0.1,
            split_damage: 0.75,
            damage_recovery: 0.005,
            support_check: true,
            bedrock_density: 2600.0,
            sand_density: 1600.0,
            water_density: 1000.0,
            bedrock_support: 60000.0,
            border_support: 60000.0,
            min_bedrock_thickness: 1.0,
            support_distance: 100.0,
            support_passes_per_step: 5,
        }
    }
}

impl ErosionParams {
    /// Checks every parameter; the error names the first one out of range.
    pub fn validate(&self) -> Result<(), ErosionError> {
        let positive = [
            ("dt", self.dt),
            ("slippage_interpolation_range", self.slippage_interpolation_range),
            ("evaporation_air_gap", self.evaporation_air_gap),
            ("erosion_water_max_height", self.erosion_water_max_height),
            ("sand_threshold", self.sand_threshold),
            ("top_erosion_distance", self.top_erosion_distance),
            ("split_damage", self.split_damage),
            ("support_distance", self.support_distance),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(name, v, "is not a finite number > 0"));
            }
        }
        let non_negative = [
            ("gravity", self.gravity),
            ("rain", self.rain),
            ("evaporation", self.evaporation),
            ("flux_damping", self.flux_damping),
            ("petrification", self.petrification),
            ("sediment_capacity", self.sediment_capacity),
            ("bedrock_dissolving", self.bedrock_dissolving),
            ("sand_dissolving", self.sand_dissolving),
            ("deposition", self.deposition),
            ("min_slope_erosion_scale", self.min_slope_erosion_scale),
            ("max_slope_erosion_scale", self.max_slope_erosion_scale),
            ("min_speed_erosion_scale", self.min_speed_erosion_scale),
            ("horizontal_erosion_strength", self.horizontal_erosion_strength),
            ("damage_recovery", self.damage_recovery),
            ("bedrock_density", self.bedrock_density),
            ("sand_density", self.sand_density),
            ("water_density", self.water_density),
            ("bedrock_support", self.bedrock_support),
            ("border_support", self.border_support),
            ("min_bedrock_thickness", self.min_bedrock_thickness),
        ];
        for (name, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(bad(name, v, "is not a finite number >= 0"));
            }
        }
        let unit = [
            ("slippage_rate", self.slippage_rate),
            ("slope_fade_start", self.slope_fade_start),
            ("min_horizontal_erosion_slope", self.min_horizontal_erosion_slope),
        ];
        for (name, v) in unit {
            if !(0.0..1.0).contains(&v) {
                return Err(bad(name, v, "is outside [0, 1)"));
            }
        }
        for (name, v) in
            [("dry_talus_angle", self.dry_talus_angle), ("wet_talus_angle", self.wet_talus_angle)]
        {
            if !(0.0..90.0).contains(&v) {
                return Err(bad(name, v, "is outside [0, 90) degrees"));
            }
        }
        for (name, v) in [
            ("flux_damping * dt", self.flux_damping * self.dt),
            ("petrification * dt", self.petrification * self.dt),
        ] {
            if v > 1.0 {
                return Err(bad(name, v, "exceeds 1: a step would remove more than there is"));
            }
        }
        if self.support_passes_per_step == 0 {
            return Err(ErosionError::Parameter {
                name: "support_passes_per_step",
                reason: "0 passes never propagate support".into(),
            });
        }
        Ok(())
    }

    /// Number of steps between two collapses of the support check for cells of `cell_size` m:
    /// `ceil(ceil(support_distance / cell_size) / support_passes_per_step)`, at least 1.
    pub fn support_cycle_steps(&self, cell_size: f32) -> u64 {
        let passes = (f64::from(self.support_distance) / f64::from(cell_size)).ceil().max(1.0);
        let per_step = f64::from(self.support_passes_per_step.max(1));
        ((passes / per_step).ceil() as u64).max(1)
    }
}

fn bad(name: &'static str, value: f32, what: &str) -> ErosionError {
    ErosionError::Parameter { name, reason: format!("{value} {what}") }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        assert_eq!(ErosionParams::default().validate(), Ok(()));
        let p = ErosionParams { rain: -1.0, ..Default::default() };
        assert!(matches!(p.validate(), Err(ErosionError::Parameter { name: "rain", .. })));
        let p = ErosionParams { dt: f32::NAN, ..Default::default() };
        assert!(matches!(p.validate(), Err(ErosionError::Parameter { name: "dt", .. })));
        let p = ErosionParams { wet_talus_angle: 95.0, ..Default::default() };
        let e = p.validate().unwrap_err();
        assert!(e.to_string().contains("wet_talus_angle"), "{e}");
    }

    #[test]
    fn support_cycle_covers_the_distance() {
        let p = ErosionParams::default();
        assert_eq!(p.support_cycle_steps(1.0), 20);
        assert_eq!(p.support_cycle_steps(0.25), 80);
        assert_eq!(p.support_cycle_steps(1000.0), 1);
    }
}
