//! One stack's layers, bottom to top: bedrock, the overhang stratum and the caves carved out
//! of it, sand on gentle low slopes, arches, and water below the sea level; a band of rows at
//! a time, on one thread.

use super::noise_field::{FieldScratch, NoiseField};
use super::world::World;
use relief_core::{StackLayer, StackMaterial};

/// Thinnest layer (and air gap) kept, in metres.
pub const MIN_LAYER: f32 = 0.05;

/// Bedrock, sand and water in [`StackMaterial::defaults`].
pub(super) const BEDROCK: u8 = StackMaterial::BEDROCK;
pub(super) const SAND: u8 = StackMaterial::SAND;
pub(super) const WATER: u8 = StackMaterial::WATER;

/// Overhang mask threshold and the width of its ramp to the full gap.
const OVERHANG_THRESHOLD: f32 = 0.16;
const OVERHANG_RAMP: f32 = 0.12;
/// Cave mask threshold and ramp.
const CAVE_THRESHOLD: f32 = 0.2;
const CAVE_RAMP: f32 = 0.1;
/// Half-width of the arches' ridge band in noise units, and the gate's threshold.
const ARCH_BAND: f32 = 0.05;
const ARCH_GATE: f32 = 0.14;

/// Slope (rise over run) from which no sand lies.
const SAND_SLOPE: f32 = 0.4;

/// Cubic smoothstep of `t` clamped to [0, 1].
#[inline]
fn smooth01(t: f32) -> f32 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// One thread's working memory: the noise rows and one stack's solid intervals.
pub(super) struct Worker {
    scratch: Vec<FieldScratch>,
    /// Noise rows: overhang mask, height, thickness; cave mask, depth; ridge, gate.
    rows: Vec<Vec<f32>>,
    /// `(start, end, material)` of one stack, bottom to top.
    solid: Vec<(f32, f32, u8)>,
}

impl Worker {
    /// Working memory for building the stacks of `world` on one thread.
    pub(super) fn for_world(world: &World) -> Self {
        let fields = world.overhang.iter().chain(&world.cave).chain(&world.arch);
        Worker {
            scratch: fields.map(NoiseField::scratch).collect(),
            rows: vec![vec![0.0; world.width]; 7],
            solid: Vec::new(),
        }
    }

    /// Rows from `first` on, as many as `ends` holds (`ends.len() / width`): fills `ends` with
    /// the band-local end offset of each stack and returns the band's layers.
    pub(super) fn band(
        &mut self,
        world: &World,
        first: usize,
        ends: &mut [u32],
    ) -> Vec<StackLayer> {
        let width = world.width;
        let mut layers = Vec::with_capacity(ends.len() * 2);
        for (k, row_ends) in ends.chunks_mut(width).enumerate() {
            let y = first + k;
            let fields = world.overhang.iter().chain(&world.cave).chain(&world.arch);
            for ((field, out), scratch) in fields.zip(&mut self.rows).zip(&mut self.scratch) {
                field.row(y, out, scratch);
            }
            for (x, end) in row_ends.iter_mut().enumerate() {
                self.stack(world, x, y);
                for &(start, stop, material) in &self.solid {
                    if stop - start >= MIN_LAYER {
                        layers.push(StackLayer::new(start, stop, material));
                    }
                }
                *end = layers.len() as u32;
            }
        }
        layers
    }

    /// The layers of stack `(x, y)` into `self.solid`, valid and clamped.
    fn stack(&mut self, w: &World, x: usize, y: usize) {
        let i = x + y * w.width;
        let s = w.sizes;
        let ground = w.ground[i];
        let solid = &mut self.solid;
        solid.clear();
        let mut top = ground;
        if top >= MIN_LAYER {
            solid.push((0.0, top, BEDROCK));
        }
        // Overhang stratum: an absolute height, carved inside the rock, cutting the ground
        // down to its floor where the roof would be too thin.
        let mask = self.rows[0][x];
        let thickness = s.overhang_gap * smooth01((mask - OVERHANG_THRESHOLD) / OVERHANG_RAMP) * {
            0.55 + 0.9 * (self.rows[2][x] + 0.5).clamp(0.0, 1.0)
        };
        if thickness >= MIN_LAYER {
            let centre = w.base + w.relief * (0.15 + 0.7 * (self.rows[1][x] + 0.5).clamp(0.0, 1.0));
            let (low, high) = ((centre - 0.5 * thickness).max(MIN_LAYER), centre + 0.5 * thickness);
            if high + s.roof <= top {
                carve(solid, low, high);
            } else if low < top {
                carve(solid, low, top);
            }
            top = solid.last().map_or(0.0, |l| l.1);
        }
        // Caves: a gap under a roof that follows the ground.
        let mask = self.rows[3][x];
        let thickness = s.cave_gap * smooth01((mask - CAVE_THRESHOLD) / CAVE_RAMP);
        if thickness >= MIN_LAYER {
            let depth = s.cave_depth + s.cave_depth_range * (self.rows[4][x] + 0.5).clamp(0.0, 1.0);
            let high = ground - depth;
            let low = (high - thickness).max(MIN_LAYER);
            if high - low >= MIN_LAYER && high <= top - s.roof {
                carve(solid, low, high);
            }
        }
        // Sand: the top of the ground, thicker on gentler slopes.
        if let Some(last) = solid.last_mut() {
            let slope = slope(w, x, y);
            let altitude = (last.1 - w.base) / w.relief;
            let depth = w.sand
                * (1.0 - slope / SAND_SLOPE).clamp(0.0, 1.0)
                * (1.0 - smooth01((altitude - 0.4) / 0.2));
            if depth >= MIN_LAYER && last.1 - last.0 >= 2.0 * MIN_LAYER {
                let split = (last.1 - depth).max(last.0 + MIN_LAYER);
                let end = last.1;
                last.1 = split;
                solid.push((split, end, SAND));
            }
        }
        // Arches: a slab along the ridge lines where the gate allows.
        let ridge = self.rows[5][x].abs();
        let gate = smooth01((self.rows[6][x] - ARCH_GATE) / 0.06);
        if ridge < ARCH_BAND && gate > 0.0 {
            let profile = 1.0 - (ridge / ARCH_BAND).powi(2);
            let deck = w.smooth[i] + s.deck_offset;
            let mut slab = s.slab * profile * gate;
            let bottom = deck - 0.6 * slab;
            let clearance = bottom - top;
            slab *= 1.0 - smooth01((clearance - 0.6 * s.max_clearance) / (0.4 * s.max_clearance));
            let (bottom, high) = (deck - 0.6 * slab, (deck + 0.4 * slab).min(w.max_height));
            if high - bottom >= MIN_LAYER && high > top {
                if bottom - top >= MIN_LAYER {
                    solid.push((bottom, high, BEDROCK));
                } else {
                    solid.push((top, high, BEDROCK));
                }
            }
        }
        // Water: all air below the sea level.
        let sea = w.sea_level;
        let mut below = 0.0f32;
        let mut k = 0;
        loop {
            let high = solid.get(k).map_or(f32::INFINITY, |l| l.0).min(sea);
            if high - below >= MIN_LAYER {
                solid.insert(k, (below, high, WATER));
                k += 1;
            }
            match solid.get(k) {
                Some(l) if l.1 < sea => below = l.1,
                _ => break,
            }
            k += 1;
        }
        for l in solid.iter_mut() {
            l.0 = l.0.clamp(0.0, w.max_height);
            l.1 = l.1.clamp(0.0, w.max_height);
        }
    }
}

/// Removes `[low, high]` from the solid intervals.
fn carve(solid: &mut Vec<(f32, f32, u8)>, low: f32, high: f32) {
    if high - low < MIN_LAYER {
        return;
    }
    let mut k = 0;
    while k < solid.len() {
        let (start, end, material) = solid[k];
        if end <= low || start >= high {
            k += 1;
            continue;
        }
        let below = (start, low.max(start), material);
        let above = (high.min(end), end, material);
        solid.remove(k);
        if above.1 - above.0 >= MIN_LAYER {
            solid.insert(k, above);
        }
        if below.1 - below.0 >= MIN_LAYER {
            solid.insert(k, below);
            k += 1;
        }
        if above.1 - above.0 >= MIN_LAYER {
            k += 1;
        }
    }
}

/// The ground's slope (rise over run) at stack `(x, y)`, by central differences.
fn slope(w: &World, x: usize, y: usize) -> f32 {
    let at = |x: usize, y: usize| w.ground[x + y * w.width];
    let (x0, x1) = (x.saturating_sub(1), (x + 1).min(w.width - 1));
    let (y0, y1) = (y.saturating_sub(1), (y + 1).min(w.height - 1));
    let gx = (at(x1, y) - at(x0, y)) / (((x1 - x0).max(1)) as f32 * w.spacing);
    let gy = (at(x, y1) - at(x, y0)) / (((y1 - y0).max(1)) as f32 * w.spacing);
    (gx * gx + gy * gy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn carve_splits_and_drops_slivers() {
        let mut solid = vec![(0.0, 10.0, BEDROCK)];
        carve(&mut solid, 4.0, 6.0);
        assert_eq!(solid, vec![(0.0, 4.0, BEDROCK), (6.0, 10.0, BEDROCK)]);
        carve(&mut solid, 3.98, 9.99);
        assert_eq!(solid, vec![(0.0, 3.98, BEDROCK)]);
    }
}
