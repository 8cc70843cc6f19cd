//! Scenes and checks the erosion tests share.
#![allow(dead_code)]

use relief_core::{Mlhm, MlhmColumn};
use relief_sim::erosion::{ErosionParams, ErosionState};

/// A small deterministic generator for scene values.
pub struct Lcg(pub u64);

impl Lcg {
    /// A number in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 40) as f32 / (1u64 << 24) as f32)
    }
}

/// A random layered scene of `w x h` cells (1 m) with up to `layers` columns per cell:
/// bedrock, sand and water, with overhangs separated by air gaps.
pub fn random_scene(w: usize, h: usize, layers: usize, seed: u64) -> Mlhm {
    let mut rng = Lcg(seed);
    let mut map = Mlhm::new(w, h, layers, 1.0).unwrap();
    for y in 0..h {
        for x in 0..w {
            let n = 1 + (rng.range(0.0, layers as f32) as usize).min(layers - 1);
            let mut cell = Vec::new();
            let mut bedrock = rng.range(0.0, 4.0);
            for k in 0..n {
                let sand = rng.range(0.0, 1.0);
                let water = if rng.range(0.0, 1.0) < 0.7 { rng.range(0.0, 2.0) } else { 0.0 };
                let top = bedrock + sand + water;
                let ceiling = if k + 1 == n { f32::INFINITY } else { top + rng.range(0.2, 3.0) };
                cell.push(MlhmColumn::new(bedrock, sand, water, ceiling));
                bedrock = ceiling + rng.range(0.5, 4.0);
            }
            map.set_cell(x, y, &cell).unwrap();
        }
    }
    map
}

/// Parameters with rain and evaporation off.
pub fn closed() -> ErosionParams {
    ErosionParams { rain: 0.0, evaporation: 0.0, ..ErosionParams::default() }
}

/// Checks the state's terrain against every MLHM invariant.
pub fn assert_valid(state: &ErosionState, when: &str) {
    let map = state.to_mlhm().unwrap_or_else(|e| panic!("{when}: {e}"));
    map.validate().unwrap_or_else(|e| panic!("{when}: {e}"));
}

/// The state's terrain and planes as bits, for byte-exact comparisons.
pub fn bits(state: &ErosionState) -> Vec<u32> {
    let mut out: Vec<u32> = state.layer_counts().iter().map(|&n| u32::from(n)).collect();
    for c in state.columns() {
        out.extend(c.to_array().map(f32::to_bits));
    }
    for f in state.fluxes() {
        out.extend(f.map(f32::to_bits));
    }
    out.extend(state.stability().iter().map(|v| v.to_bits()));
    out.extend(state.sediment().iter().map(|v| v.to_bits()));
    out.extend(state.damage().iter().map(|v| v.to_bits()));
    out
}
