//! The smooth noise fields that place the features: sums of rotated gradient-noise octaves,
//! evaluated a row at a time.

use crate::gradient_noise::{mix64, CellCache, GradientNoise, NoiseBatch};

/// Samples evaluated together along a row.
const BLOCK: usize = 256;

/// One octave of a noise field.
#[derive(Debug, Clone)]
struct Octave {
    noise: GradientNoise,
    cos: f64,
    sin: f64,
    /// Lattice cells per stack.
    frequency: f64,
    amplitude: f32,
}

/// A sum of rotated gradient-noise octaves (gain 0.5, lacunarity 2), amplitudes summing to 1.
#[derive(Debug, Clone)]
pub(super) struct NoiseField {
    octaves: Vec<Octave>,
}

/// One thread's working memory for one [`NoiseField`].
#[derive(Default)]
pub(super) struct FieldScratch {
    caches: Vec<CellCache>,
    batch: NoiseBatch,
    us: Vec<f64>,
    vs: Vec<f64>,
    n: Vec<f32>,
    du: Vec<f32>,
    dv: Vec<f32>,
}

impl NoiseField {
    /// Field `id` of the terrain seeded with `seed`: `octaves` octaves, the first of
    /// `wavelength` stacks.
    pub(super) fn new(seed: u64, id: u64, wavelength: f64, octaves: u32) -> Self {
        let norm: f64 = (0..octaves).map(|k| 0.5f64.powi(k as i32)).sum();
        let octaves = (0..octaves)
            .map(|k| {
                let index = id * 16 + u64::from(k);
                let angle = 0.7 + index as f64 * 1.3;
                Octave {
                    noise: GradientNoise::new(mix64(
                        seed ^ 0x5bd1_e995_u64.wrapping_mul(index + 1) ^ 0xa076_1d64_78bd_642f,
                    )),
                    cos: angle.cos(),
                    sin: angle.sin(),
                    frequency: 2f64.powi(k as i32) / wavelength,
                    amplitude: (0.5f64.powi(k as i32) / norm) as f32,
                }
            })
            .collect();
        NoiseField { octaves }
    }

    /// Working memory for [`NoiseField::row`] on one thread.
    pub(super) fn scratch(&self) -> FieldScratch {
        FieldScratch {
            caches: vec![CellCache::default(); self.octaves.len()],
            ..Default::default()
        }
    }

    /// The field at the stack centres of row `y` into `out` (one per column).
    pub(super) fn row(&self, y: usize, out: &mut [f32], s: &mut FieldScratch) {
        out.fill(0.0);
        let yc = y as f64 + 0.5;
        for (octave, cache) in self.octaves.iter().zip(s.caches.iter_mut()) {
            let (c, sn, f) = (octave.cos, octave.sin, octave.frequency);
            for (b, block) in out.chunks_mut(BLOCK).enumerate() {
                let len = block.len();
                s.us.clear();
                s.vs.clear();
                for i in 0..len {
                    let (x, y) = (((b * BLOCK + i) as f64 + 0.5) * f, yc * f);
                    s.us.push(c * x - sn * y);
                    s.vs.push(sn * x + c * y);
                }
                octave.noise.locate(&s.us, &s.vs, cache, &mut s.batch);
                for v in [&mut s.n, &mut s.du, &mut s.dv] {
                    v.resize(len, 0.0);
                }
                s.batch.evaluate(&mut s.n, &mut s.du, &mut s.dv);
                for (o, &n) in block.iter_mut().zip(&s.n[..len]) {
                    *o += octave.amplitude * n;
                }
            }
        }
    }
}
