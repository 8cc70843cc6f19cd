//! Seeded fBm terrain: the generator of synthetic mountain height fields.

use crate::gradient_noise::{mix64, CellCache, GradientNoise};
use crate::FbmParams;
use rayon::prelude::*;
use relief_core::{CoreError, GridGeometry, HeightField};

/// One noise layer: its lattice, orientation, frequency and amplitude.
#[derive(Debug, Clone)]
struct Octave {
    noise: GradientNoise,
    /// Rotation (cos, sin) of the layer relative to the grid, so lattices do not align.
    cos: f64,
    sin: f64,
    frequency: f64,
    amplitude: f64,
}

/// Everything needed to evaluate the terrain at a point.
struct Terrain {
    octaves: Vec<Octave>,
    style: u32,
    warp: f64,
    warp_x: Octave,
    warp_y: Octave,
}

impl Terrain {
    fn new(seed: u64, params: &FbmParams) -> Self {
        let layer = |k: u64, frequency: f64, amplitude: f64| {
            let angle = k as f64 * 1.1;
            Octave {
                noise: GradientNoise::new(mix64(seed ^ k.wrapping_mul(0x2545_f491_4f6c_dd1d))),
                cos: angle.cos(),
                sin: angle.sin(),
                frequency,
                amplitude,
            }
        };
        let octaves = (0..params.octaves)
            .map(|k| {
                let frequency = params.lacunarity.powi(k as i32) / params.wavelength;
                layer(u64::from(k), frequency, params.amplitude * params.gain.powi(k as i32))
            })
            .collect();
        let style = std::env::var("STYLE").ok().and_then(|s| s.parse().ok()).unwrap_or(0);
        let warp = std::env::var("WARP").ok().and_then(|s| s.parse().ok()).unwrap_or(0.0);
        Terrain {
            octaves,
            style,
            warp: warp * params.wavelength,
            warp_x: layer(100, 0.5 / params.wavelength, 1.0),
            warp_y: layer(101, 0.5 / params.wavelength, 1.0),
        }
    }

    fn sample(&self, x: f64, y: f64, caches: &mut [CellCache]) -> f64 {
        let (mut x, mut y) = (x, y);
        let n = caches.len();
        if self.warp > 0.0 {
            let (a, b) = caches.split_at_mut(n - 1);
            let wx = self.warp_x.noise.eval(
                x * self.warp_x.frequency,
                y * self.warp_x.frequency,
                &mut a[n - 2],
            );
            let wy = self.warp_y.noise.eval(
                x * self.warp_y.frequency + 5.3,
                y * self.warp_y.frequency,
                &mut b[0],
            );
            x += self.warp * wx;
            y += self.warp * wy;
        }
        let mut sum = 0.0;
        let mut weight = 1.0;
        let (mut sx, mut sy) = (0.0, 0.0);
        for (o, cache) in self.octaves.iter().zip(caches.iter_mut()) {
            let (u, v) = (x * o.frequency, y * o.frequency);
            let (ru, rv) = (o.cos * u - o.sin * v, o.sin * u + o.cos * v);
            let [n, du, dv] = o.noise.eval_with_gradient(ru, rv, cache);
            match self.style {
                0 => sum += o.amplitude * n,
                1 => {
                    let r = 1.0 - n.abs() * std::f64::consts::SQRT_2;
                    let s = r * r * weight;
                    weight = (s * 2.0).clamp(0.0, 1.0);
                    sum += o.amplitude * s;
                }
                2 => {
                    // Gradient damping (erosion-like): back-rotate the gradient.
                    let gx = o.cos * du + o.sin * dv;
                    let gy = -o.sin * du + o.cos * dv;
                    sx += gx;
                    sy += gy;
                    sum += o.amplitude * n / (1.0 + sx * sx + sy * sy);
                }
                6 | 7 => {
                    let gx = o.cos * du + o.sin * dv;
                    let gy = -o.sin * du + o.cos * dv;
                    sx += gx;
                    sy += gy;
                    let m = if weight > if self.style == 6 { 0.3 } else { 0.6 } {
                        0.5 * (0.7 - 2.0 * n.abs())
                    } else {
                        n
                    };
                    sum += o.amplitude * m / (1.0 + sx * sx + sy * sy);
                    weight *= 0.5;
                }
                4 | 5 => {
                    // Sharp ridges in the coarse octaves, eroded detail.
                    let gx = o.cos * du + o.sin * dv;
                    let gy = -o.sin * du + o.cos * dv;
                    let ridged = self.style == 4 || weight > 0.5;
                    let (m, mx, my) = if ridged {
                        let sg = if n >= 0.0 { 1.0 } else { -1.0 };
                        (0.5 - n.abs(), -sg * gx, -sg * gy)
                    } else {
                        (n, gx, gy)
                    };
                    sx += mx;
                    sy += my;
                    sum += o.amplitude * m / (1.0 + sx * sx + sy * sy);
                    weight *= 0.5;
                }
                _ => {
                    let r = 1.0 - n.abs() * std::f64::consts::SQRT_2;
                    let s = r * r * weight;
                    weight = (s * 2.0).clamp(0.0, 1.0);
                    let gx = o.cos * du + o.sin * dv;
                    let gy = -o.sin * du + o.cos * dv;
                    sx += gx;
                    sy += gy;
                    sum += o.amplitude * s / (1.0 + 0.5 * (sx * sx + sy * sy));
                }
            }
        }
        sum
    }
}

/// A `width x height` height field of seeded fBm mountains with [`GridGeometry::unit`].
///
/// The same `seed` and `params` give the same samples, bit for bit, whatever the number of
/// threads. Samples are finite and at least 0, the lowest exactly 0.
///
/// Errors: [`CoreError::Parameter`] when `params` are out of range (see
/// [`FbmParams::validate`]), [`CoreError::Grid`] when the grid is empty or too large.
pub fn fbm_terrain(
    width: usize,
    height: usize,
    seed: u64,
    params: &FbmParams,
) -> Result<HeightField, CoreError> {
    params.validate()?;
    if width == 0 || height == 0 {
        return Err(CoreError::Grid(format!("{width} x {height} has no samples")));
    }
    let count = width
        .checked_mul(height)
        .ok_or_else(|| CoreError::Grid(format!("{width} x {height} samples overflow")))?;
    let mut heights: Vec<f64> = Vec::new();
    heights
        .try_reserve_exact(count)
        .map_err(|_| CoreError::Grid(format!("cannot allocate {width} x {height} samples")))?;
    heights.resize(count, 0.0);
    let terrain = Terrain::new(seed, params);
    heights.par_chunks_mut(width).enumerate().for_each(|(row, out)| {
        let mut caches = vec![CellCache::default(); terrain.octaves.len() + 2];
        let y = row as f64 + 0.5;
        for (col, h) in out.iter_mut().enumerate() {
            *h = terrain.sample(col as f64 + 0.5, y, &mut caches);
        }
    });
    let min = heights.iter().copied().fold(f64::INFINITY, f64::min);
    let samples = heights.iter().map(|&h| (h - min) as f32).collect();
    HeightField::new(width, height, samples, GridGeometry::unit())
}
