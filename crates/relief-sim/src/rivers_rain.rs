//! The reference simulator's procedural "RiversRain" scene: fBm hills on a slope, 256 m square.
//!
//! Every cell holds one column: bedrock `10 (1 + fbm(p)) + 16 (W - x) / W` metres (x the cell
//! column, so the ground falls by 16 m from west to east), 1 m of sand, no water. `fbm` sums
//! 8 octaves of gradient noise at the cell centre `p` in metres, the first at 0.05 cycles per
//! metre and amplitude 0.5, each next one at twice the frequency and half the amplitude. The
//! reference uses simplex noise; relief uses its seeded gradient noise scaled by sqrt 2 to
//! span [-1, 1] likewise, so the terrain is alike in character, not equal value for value.
//! The scene is always 256 m x 256 m: a grid of N x N cells has cells of 256 / N metres, and
//! sampling in metres makes every resolution show the same hills.

use crate::gradient_noise::{mix64, CellCache, GradientNoise, NoiseBatch};
use rayon::prelude::*;
use relief_core::{CoreError, Mlhm, MlhmColumn};

/// Side of the scene in metres.
pub const RIVERS_RAIN_EXTENT: f64 = 256.0;

/// The seed [`rivers_rain`] is meant to be called with for the canonical scene.
pub const RIVERS_RAIN_SEED: u64 = 2025;

/// Octaves of the fBm.
const OCTAVES: u32 = 8;

/// Frequency of the first octave, cycles per metre.
const FIRST_FREQUENCY: f64 = 0.05;

/// Amplitude of the first octave.
const FIRST_AMPLITUDE: f32 = 0.5;

/// Scales gradient noise (within +-1/sqrt 2) to simplex noise's +-1.
const NOISE_SCALE: f32 = std::f32::consts::SQRT_2;

/// Thickness of the sand on every cell, metres.
const SAND: f32 = 1.0;

/// The RiversRain scene on a `size x size` grid (cells of 256 / `size` metres), with room
/// for `max_layers` columns per cell (the reference's 4096^2 scene has 4), from noise seeded
/// by `seed`. Deterministic: the same arguments give the same map whatever the thread count.
///
/// Fails when `size` is 0 or `max_layers` is outside `1..=255`.
///
/// ```
/// let map = relief_sim::rivers_rain(64, 1, relief_sim::RIVERS_RAIN_SEED)?;
/// assert_eq!((map.width(), map.cell_size()), (64, 4.0));
/// assert_eq!(map.column(0, 0, 0).sand, 1.0);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
pub fn rivers_rain(size: usize, max_layers: usize, seed: u64) -> Result<Mlhm, CoreError> {
    if size == 0 {
        return Err(CoreError::Grid("a RiversRain scene of 0 x 0 cells is empty".into()));
    }
    let cell_size = RIVERS_RAIN_EXTENT / size as f64;
    // Checks the shape before the large allocations below.
    Mlhm::new(1, 1, max_layers, cell_size)?;
    let cells = size.checked_mul(size).ok_or_else(|| {
        CoreError::Grid(format!("a RiversRain scene of {size} x {size} cells is too large"))
    })?;
    let octaves: Vec<_> = (0..OCTAVES)
        .map(|k| GradientNoise::new(mix64(seed ^ u64::from(k).wrapping_mul(0x9e37_79b9))))
        .collect();
    let mut columns = vec![MlhmColumn::default(); cells * max_layers];
    columns[..cells]
        .par_chunks_mut(size)
        .enumerate()
        .for_each_init(|| Row::new(size), |row, (y, out)| row.fill(&octaves, y, cell_size, out));
    Mlhm::from_parts(size, size, max_layers, cell_size, vec![1; cells], columns)
}

/// One thread's working memory for a row of cells.
struct Row {
    xs: Vec<f64>,
    ys: Vec<f64>,
    n: Vec<f32>,
    du: Vec<f32>,
    dv: Vec<f32>,
    fbm: Vec<f32>,
    batch: NoiseBatch,
}

impl Row {
    fn new(size: usize) -> Self {
        Row {
            xs: vec![0.0; size],
            ys: vec![0.0; size],
            n: vec![0.0; size],
            du: vec![0.0; size],
            dv: vec![0.0; size],
            fbm: vec![0.0; size],
            batch: NoiseBatch::default(),
        }
    }

    /// The columns of grid row `y` into `out`.
    fn fill(
        &mut self,
        octaves: &[GradientNoise],
        y: usize,
        cell_size: f64,
        out: &mut [MlhmColumn],
    ) {
        let width = out.len();
        self.fbm.iter_mut().for_each(|v| *v = 0.0);
        let (mut frequency, mut amplitude) = (FIRST_FREQUENCY, FIRST_AMPLITUDE);
        for noise in octaves {
            for (x, (u, v)) in self.xs.iter_mut().zip(&mut self.ys).enumerate() {
                *u = (x as f64 + 0.5) * cell_size * frequency;
                *v = (y as f64 + 0.5) * cell_size * frequency;
            }
            noise.locate(&self.xs, &self.ys, &mut CellCache::default(), &mut self.batch);
            self.batch.evaluate(&mut self.n, &mut self.du, &mut self.dv);
            for (f, n) in self.fbm.iter_mut().zip(&self.n) {
                *f += amplitude * NOISE_SCALE * n;
            }
            frequency *= 2.0;
            amplitude *= 0.5;
        }
        for (x, (c, f)) in out.iter_mut().zip(&self.fbm).enumerate() {
            let slope = 16.0 * (width - x) as f32 / width as f32;
            *c = MlhmColumn::new(10.0 * (1.0 + f) + slope, SAND, 0.0, f32::INFINITY);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sandy_column_per_cell_on_a_slope_falling_east() {
        let map = rivers_rain(128, 4, RIVERS_RAIN_SEED).unwrap();
        assert_eq!(
            (map.width(), map.height(), map.max_layers(), map.cell_size()),
            (128, 128, 4, 2.0)
        );
        assert!(map.layer_counts().iter().all(|&n| n == 1));
        let mean_column = |x: usize| {
            (0..128).map(|y| f64::from(map.column(x, y, 0).bedrock)).sum::<f64>() / 128.0
        };
        let (west, east) = (mean_column(0), mean_column(127));
        assert!(west - east > 8.0, "west {west}, east {east}");
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for c in &map.raw_columns()[..128 * 128] {
            assert_eq!((c.sand, c.water, c.ceiling), (1.0, 0.0, f32::INFINITY));
            (lo, hi) = (lo.min(c.bedrock), hi.max(c.bedrock));
        }
        // 10 (1 + fbm) with |fbm| < 1, plus up to 16 m of slope; real hills, not a plane.
        assert!(lo > 0.0 && hi < 36.0 && hi - lo > 15.0, "bedrock {lo}..{hi}");
        map.validate().unwrap();
    }

    #[test]
    fn deterministic_and_the_same_hills_at_every_resolution() {
        let a = rivers_rain(64, 1, 7).unwrap();
        assert_eq!(a, rivers_rain(64, 1, 7).unwrap());
        assert_ne!(a, rivers_rain(64, 1, 8).unwrap());
        // Cell (x, y) of the 64 grid (4 m) and cell (2x, 2y) of the 128 grid (2 m) have centres
        // 1 m apart; the smooth hills differ little there while the slope term is equal.
        let b = rivers_rain(128, 1, 7).unwrap();
        let mut worst = 0f32;
        for y in 0..64 {
            for x in 0..64 {
                let d = a.column(x, y, 0).bedrock - b.column(2 * x + 1, 2 * y + 1, 0).bedrock;
                worst = worst.max(d.abs());
            }
        }
        assert!(worst < 4.0, "{worst}");
        assert!(rivers_rain(0, 1, 7).is_err());
        assert!(rivers_rain(8, 0, 7).is_err());
    }
}
