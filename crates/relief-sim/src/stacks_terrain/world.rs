//! Everything computed once for a whole stacks terrain: the fBm ground rescaled, its smoothed
//! copy, the sea level, the noise fields and the features' sizes.

use super::noise_field::NoiseField;
use super::params::StacksTerrainParams;
use crate::{fbm_terrain, FbmParams, SimError};
use rayon::prelude::*;

/// Everything computed once for the whole terrain: the ground, its smoothed copy, the sea
/// level, the noise fields and the feature sizes.
pub(super) struct World {
    /// Stacks along x.
    pub width: usize,
    /// Stacks along y.
    pub height: usize,
    /// Ground height per stack, metres.
    pub ground: Vec<f32>,
    /// The ground smoothed over a few hundred metres: the arches' deck below its offset.
    pub smooth: Vec<f32>,
    pub sea_level: f32,
    pub max_height: f32,
    pub spacing: f32,
    pub sand: f32,
    /// Overhang stratum: mask, height (0..1 of the relief), thickness modulation.
    pub overhang: [NoiseField; 3],
    /// Caves: mask, depth.
    pub cave: [NoiseField; 2],
    /// Arches: ridge (slabs along its zero lines), gate.
    pub arch: [NoiseField; 2],
    /// Lowest ground, and the ground's relief.
    pub base: f32,
    pub relief: f32,
    /// Feature sizes in metres.
    pub sizes: Sizes,
}

/// Vertical sizes of the features, in metres, scaled down on domains of little relief.
#[derive(Debug, Clone, Copy)]
pub(super) struct Sizes {
    pub overhang_gap: f32,
    pub roof: f32,
    pub cave_depth: f32,
    pub cave_depth_range: f32,
    pub cave_gap: f32,
    pub slab: f32,
    pub deck_offset: f32,
    pub max_clearance: f32,
}

impl World {
    /// The ground, the sea level, the noise fields and the feature sizes of the terrain of
    /// `width x height` stacks seeded with `seed`.
    pub(super) fn new(
        width: usize,
        height: usize,
        seed: u64,
        params: &StacksTerrainParams,
    ) -> Result<Self, SimError> {
        let side = width.max(height) as f64;
        let field = fbm_terrain(width, height, seed, &FbmParams::for_size(width, height))?;
        let top = f64::from(field.max_sample()).max(f64::MIN_POSITIVE);
        let max_height = params.max_height;
        // Relief: most of the height range, but no steeper than a quarter of the extent.
        let relief = (0.85 * max_height).min(0.25 * side * params.spacing);
        let base = 0.04 * max_height;
        let scale = relief / top;
        let ground: Vec<f32> = field
            .samples()
            .par_iter()
            .map(|&h| (base + f64::from(h) * scale).clamp(0.0, max_height) as f32)
            .collect();
        drop(field);
        let sea_level = sea_level(&ground, max_height as f32, params.water_fraction);
        // Wavelengths in metres, at most 2/5 of the longer side so that small domains have
        // features too.
        let stacks = |metres: f64| (metres / params.spacing).min(side / 2.5).max(2.0);
        let radius = ((160.0 / params.spacing).min(side / 6.0) as usize).max(1);
        let smooth = box_blur(&ground, width, height, radius);
        let r = relief as f32;
        let sizes = Sizes {
            overhang_gap: (0.25 * r).min(14.0),
            roof: (0.06 * r).clamp(0.5, 4.0),
            cave_depth: (0.1 * r).clamp(0.6, 6.0),
            cave_depth_range: (0.3 * r).min(30.0),
            cave_gap: (0.2 * r).min(9.0),
            slab: (0.12 * r).min(9.0),
            deck_offset: (0.08 * r).min(25.0),
            max_clearance: (0.5 * r).min(120.0),
        };
        Ok(World {
            width,
            height,
            ground,
            smooth,
            sea_level,
            max_height: max_height as f32,
            spacing: params.spacing as f32,
            sand: params.sand_thickness as f32,
            overhang: [
                NoiseField::new(seed, 1, stacks(180.0), 2),
                NoiseField::new(seed, 2, stacks(900.0), 1),
                NoiseField::new(seed, 3, stacks(90.0), 1),
            ],
            cave: [
                NoiseField::new(seed, 4, stacks(140.0), 2),
                NoiseField::new(seed, 5, stacks(220.0), 1),
            ],
            arch: [
                NoiseField::new(seed, 6, stacks(260.0), 1),
                NoiseField::new(seed, 7, stacks(700.0), 1),
            ],
            base: base as f32,
            relief: r,
            sizes,
        })
    }
}

/// The ground height under which `fraction` of `ground` lies, from a histogram of 4096 bins
/// over `[0, max_height]` (exact enough, and independent of the order of the samples).
fn sea_level(ground: &[f32], max_height: f32, fraction: f64) -> f32 {
    const BINS: usize = 4096;
    if fraction <= 0.0 {
        return 0.0;
    }
    let bin = |h: f32| ((h / max_height * BINS as f32) as usize).min(BINS - 1);
    let histogram = ground
        .par_chunks(1 << 16)
        .map(|chunk| {
            let mut counts = vec![0u64; BINS];
            chunk.iter().for_each(|&h| counts[bin(h)] += 1);
            counts
        })
        .reduce(
            || vec![0u64; BINS],
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                a
            },
        );
    let wanted = (fraction * ground.len() as f64).ceil() as u64;
    let mut below = 0;
    for (k, count) in histogram.iter().enumerate() {
        below += count;
        if below >= wanted {
            return (k + 1) as f32 / BINS as f32 * max_height;
        }
    }
    max_height
}

/// `values` (`width x height`, row-major) averaged over the `(2r + 1)^2` square around each
/// point, the edges repeated outwards: a horizontal then a vertical running sum.
fn box_blur(values: &[f32], width: usize, height: usize, r: usize) -> Vec<f32> {
    let n = (2 * r + 1) as f64;
    let mut rows = vec![0f32; values.len()];
    rows.par_chunks_mut(width).zip(values.par_chunks(width)).for_each(|(out, row)| {
        let at = |i: isize| f64::from(row[i.clamp(0, width as isize - 1) as usize]);
        let mut sum: f64 = (-(r as isize)..=r as isize).map(at).sum();
        for (x, o) in out.iter_mut().enumerate() {
            *o = (sum / n) as f32;
            let x = x as isize;
            sum += at(x + r as isize + 1) - at(x - r as isize);
        }
    });
    let mut out = vec![0f32; values.len()];
    let row = |y: isize| &rows[y.clamp(0, height as isize - 1) as usize * width..][..width];
    let mut sum = vec![0f64; width];
    for y in -(r as isize)..=r as isize {
        sum.iter_mut().zip(row(y)).for_each(|(s, &v)| *s += f64::from(v));
    }
    for (y, o) in out.chunks_mut(width).enumerate() {
        o.iter_mut().zip(&sum).for_each(|(o, &s)| *o = (s / n) as f32);
        let y = y as isize;
        let (add, remove) = (row(y + r as isize + 1), row(y - r as isize));
        for ((s, &a), &b) in sum.iter_mut().zip(add).zip(remove) {
            *s += f64::from(a) - f64::from(b);
        }
    }
    out
}
