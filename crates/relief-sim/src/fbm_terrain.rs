//! Seeded fBm terrain: the generator of synthetic mountain height fields.
//!
//! The terrain is a sum of gradient-noise octaves in the style of Inigo Quilez's "eroded"
//! fBm: each octave is damped by the slope accumulated by the octaves above it, so steep
//! flanks stay smooth and detail gathers on ridges and valley floors. The first octave is
//! ridged (crests where its noise crosses zero) to give mountain chains, and the whole
//! domain is warped by a low-frequency noise so that features meander instead of following
//! the lattice.

use crate::gradient_noise::{mix64, CellCache, GradientNoise, NoiseBatch};
use crate::FbmParams;
use rayon::prelude::*;
use relief_core::{CoreError, GridGeometry, HeightField};
use std::sync::OnceLock;

/// Domain-warp displacement in units of the first octave's wavelength.
const WARP: f64 = 0.3;

/// Wavelength of the warp noise in units of the first octave's wavelength.
const WARP_WAVELENGTH: f64 = 2.0;

/// The largest lattice coordinate the finest octave may reach: far below 2^53, so lattice
/// coordinates keep a fractional part with enough precision for smooth noise.
const MAX_LATTICE_COORDINATE: f64 = (1u64 << 40) as f64;

/// Samples evaluated together along a row: small enough that a block's working arrays stay
/// in the first-level cache.
const BLOCK: usize = 256;

/// One noise layer: its lattice, orientation, frequency and amplitude.
#[derive(Debug, Clone)]
struct Octave {
    noise: GradientNoise,
    /// Cosine of the layer's rotation relative to the grid (layers are rotated so that their
    /// lattices do not line up).
    cos: f64,
    /// Sine of that rotation.
    sin: f64,
    /// Lattice cells per texel.
    frequency: f64,
    /// Sample units per unit of noise.
    amplitude: f32,
}

impl Octave {
    /// Layer `index` of the terrain seeded with `seed`.
    fn new(seed: u64, index: u64, frequency: f64, amplitude: f64) -> Self {
        let angle = index as f64 * 1.1;
        Octave {
            noise: GradientNoise::new(mix64(seed ^ index.wrapping_mul(0x2545_f491_4f6c_dd1d))),
            cos: angle.cos(),
            sin: angle.sin(),
            frequency,
            amplitude: amplitude as f32,
        }
    }

    /// The layer's noise at the grid points of `s.xs`, `s.ys` into `s.n`, with its gradient
    /// in lattice axes into `s.du`, `s.dv`.
    fn eval(&self, s: &mut Scratch, cache: &mut CellCache) {
        let len = s.xs.len();
        let (c, sn, f) = (self.cos, self.sin, self.frequency);
        for ((u, v), (&x, &y)) in s.us.iter_mut().zip(&mut s.vs).zip(s.xs.iter().zip(&s.ys)) {
            let (x, y) = (x * f, y * f);
            (*u, *v) = (c * x - sn * y, sn * x + c * y);
        }
        self.noise.locate(&s.us[..len], &s.vs[..len], cache, &mut s.batch);
        s.batch.evaluate(&mut s.n, &mut s.du, &mut s.dv);
    }
}

/// The terrain function: warp layers and octaves.
struct Terrain {
    octaves: Vec<Octave>,
    warp: [Octave; 2],
    /// Warp displacement in texels per unit of warp noise.
    warp_distance: f64,
}

/// One thread's working memory: a block's coordinates, noise and running sums, and a cell
/// cache per layer.
#[derive(Default)]
struct Scratch {
    caches: Vec<CellCache>,
    batch: NoiseBatch,
    xs: Vec<f64>,
    ys: Vec<f64>,
    us: Vec<f64>,
    vs: Vec<f64>,
    warp_x: Vec<f32>,
    n: Vec<f32>,
    du: Vec<f32>,
    dv: Vec<f32>,
    sum: Vec<f32>,
    slope_x: Vec<f32>,
    slope_y: Vec<f32>,
}

impl Terrain {
    fn new(seed: u64, params: &FbmParams) -> Self {
        let octaves = (0..params.octaves)
            .map(|k| {
                let frequency = params.lacunarity.powi(k as i32) / params.wavelength;
                let amplitude = params.amplitude * params.gain.powi(k as i32);
                Octave::new(seed, u64::from(k), frequency, amplitude)
            })
            .collect();
        let warp_frequency = 1.0 / (WARP_WAVELENGTH * params.wavelength);
        Terrain {
            octaves,
            warp: [
                Octave::new(seed, u64::from(u32::MAX) + 1, warp_frequency, 1.0),
                Octave::new(seed, u64::from(u32::MAX) + 2, warp_frequency, 1.0),
            ],
            warp_distance: WARP * params.wavelength,
        }
    }

    /// Working memory for [`Terrain::row`].
    fn scratch(&self) -> Scratch {
        Scratch { caches: vec![CellCache::default(); self.octaves.len() + 2], ..Scratch::default() }
    }

    /// Fills `out` with the (unshifted) heights of grid row `row` and returns their minimum.
    fn row(&self, row: usize, out: &mut [f32], s: &mut Scratch) -> f32 {
        let mut min = f32::INFINITY;
        let mut caches = std::mem::take(&mut s.caches);
        let (warp_caches, caches_rest) = caches.split_at_mut(2);
        for (b, block) in out.chunks_mut(BLOCK).enumerate() {
            let len = block.len();
            for v in [&mut s.xs, &mut s.ys, &mut s.us, &mut s.vs] {
                v.resize(len, 0.0);
            }
            for v in [&mut s.warp_x, &mut s.n, &mut s.du, &mut s.dv] {
                v.resize(len, 0.0);
            }
            for v in [&mut s.sum, &mut s.slope_x, &mut s.slope_y] {
                v.clear();
                v.resize(len, 0.0);
            }
            for (i, (x, y)) in s.xs.iter_mut().zip(&mut s.ys).enumerate() {
                (*x, *y) = ((b * BLOCK + i) as f64 + 0.5, row as f64 + 0.5);
            }
            // Warp the domain: both warp layers see the unwarped points.
            self.warp[0].eval(s, &mut warp_caches[0]);
            s.warp_x.copy_from_slice(&s.n);
            self.warp[1].eval(s, &mut warp_caches[1]);
            let d = self.warp_distance;
            for (i, (x, y)) in s.xs.iter_mut().zip(&mut s.ys).enumerate() {
                *x += d * f64::from(s.warp_x[i]);
                *y += d * f64::from(s.n[i]);
            }
            for (k, (octave, cache)) in self.octaves.iter().zip(caches_rest.iter_mut()).enumerate()
            {
                octave.eval(s, cache);
                accumulate(octave, k == 0, s);
            }
            for (h, &v) in block.iter_mut().zip(&s.sum) {
                *h = v;
                min = min.min(v);
            }
        }
        s.caches = caches;
        min
    }
}

/// Adds one octave's noise (in `s.n`, gradient in `s.du`, `s.dv`) to the running sums:
/// the slope accumulates the octave's gradient turned back into grid axes, and the octave's
/// contribution is divided by 1 + |slope|^2 (eroded fBm). A `ridged` octave contributes
/// `0.35 - |n|`, whose crests run where the noise crosses zero.
fn accumulate(octave: &Octave, ridged: bool, s: &mut Scratch) {
    let len = s.sum.len();
    let (c, sn, a) = (octave.cos as f32, octave.sin as f32, octave.amplitude);
    let (n, du, dv) = (&s.n[..len], &s.du[..len], &s.dv[..len]);
    let (sum, sx, sy) = (&mut s.sum[..len], &mut s.slope_x[..len], &mut s.slope_y[..len]);
    for i in 0..len {
        sx[i] += c * du[i] + sn * dv[i];
        sy[i] += c * dv[i] - sn * du[i];
        let value = if ridged { 0.35 - n[i].abs() } else { n[i] };
        sum[i] += a * value / (1.0 + sx[i] * sx[i] + sy[i] * sy[i]);
    }
}

/// A `width x height` height field of seeded fBm mountains with [`GridGeometry::unit`]
/// (sample (col, row) is the terrain at the texel centre (col + 0.5, row + 0.5)).
///
/// The same `width`, `height`, `seed` and `params` give the same samples, bit for bit,
/// whatever the number of threads. Samples are finite and at least 0, the lowest exactly 0.
///
/// Errors: [`CoreError::Parameter`] when `params` are out of range (see
/// [`FbmParams::validate`]) or their finest octave is too fine for the grid's size;
/// [`CoreError::Grid`] when the grid is empty or cannot be allocated.
///
/// ```
/// use relief_sim::{fbm_terrain, FbmParams};
/// let field = fbm_terrain(64, 32, 7, &FbmParams::for_size(64, 32))?;
/// assert_eq!((field.width(), field.height()), (64, 32));
/// assert_eq!(field.min_sample(), 0.0);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
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
    let rows = FbmRows::new(width, height, seed, params)?;
    let mut samples: Vec<f32> = Vec::new();
    samples
        .try_reserve_exact(count)
        .map_err(|_| CoreError::Grid(format!("cannot allocate {width} x {height} samples")))?;
    samples.resize(count, 0.0);
    let terrain = &rows.terrain;
    // Each row is computed from its own coordinates alone, so the split between threads
    // cannot change any value; the minimum is exact whatever the order of reduction.
    let min = samples
        .par_chunks_mut(width)
        .enumerate()
        .map_init(|| terrain.scratch(), |scratch, (row, out)| terrain.row(row, out, scratch))
        .reduce(|| f32::INFINITY, f32::min);
    samples.par_iter_mut().for_each(|h| *h -= min);
    HeightField::new(width, height, samples, GridGeometry::unit())
}

/// The seeded fBm terrain of [`fbm_terrain`] computed a band of rows at a time, for terrains
/// larger than memory: [`FbmRows::read_rows`] gives exactly `fbm_terrain`'s samples, bit for
/// bit, whatever the bands and the number of threads.
///
/// The samples are shifted so that the lowest is 0, which needs the lowest unshifted height
/// over the whole terrain: [`FbmRows::lowest`] computes it in a first pass over every row
/// (as costly as computing the terrain, in memory of one row per thread), once, on first use.
///
/// ```
/// use relief_sim::{fbm_terrain, FbmParams, FbmRows};
/// let params = FbmParams::for_size(64, 32);
/// let rows = FbmRows::new(64, 32, 7, &params)?;
/// let mut band = vec![0f32; 64 * 5];
/// rows.read_rows(10, &mut band)?;
/// let whole = fbm_terrain(64, 32, 7, &params)?;
/// assert_eq!(band, whole.samples()[64 * 10..64 * 15]);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
pub struct FbmRows {
    width: usize,
    height: usize,
    terrain: Terrain,
    /// The lowest unshifted height, once computed.
    lowest: OnceLock<f32>,
}

impl FbmRows {
    /// The `width x height` terrain of [`fbm_terrain`] with the same arguments; computes no
    /// sample.
    ///
    /// Errors: [`CoreError::Parameter`] when `params` are out of range or their finest octave
    /// is too fine for the grid's size; [`CoreError::Grid`] when the grid is empty.
    pub fn new(
        width: usize,
        height: usize,
        seed: u64,
        params: &FbmParams,
    ) -> Result<Self, CoreError> {
        params.validate()?;
        if width == 0 || height == 0 {
            return Err(CoreError::Grid(format!("{width} x {height} has no samples")));
        }
        let finest = params.lacunarity.powi(params.octaves as i32 - 1);
        let reach = (width.max(height) as f64 / params.wavelength + WARP) * finest;
        if reach > MAX_LATTICE_COORDINATE {
            return Err(CoreError::Parameter {
                name: "octaves",
                reason: format!(
                    "the finest of {} octaves at lacunarity {} is too fine for a {width} x \
                     {height} grid",
                    params.octaves, params.lacunarity
                ),
            });
        }
        let terrain = Terrain::new(seed, params);
        Ok(FbmRows { width, height, terrain, lowest: OnceLock::new() })
    }

    /// Columns.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The lowest height of the terrain before it is shifted to start at 0: computed over
    /// every row, in parallel, the first time it is asked for (or rows are read).
    pub fn lowest(&self) -> f32 {
        self.lowest_with_progress(|_| {})
    }

    /// [`FbmRows::lowest`], calling `progress` with the number of rows done so far now and
    /// then while it is computed (not at all when it was already known).
    pub fn lowest_with_progress(&self, progress: impl Fn(usize)) -> f32 {
        *self.lowest.get_or_init(|| {
            let (terrain, width) = (&self.terrain, self.width);
            // Bands of about 2^20 samples between progress reports.
            let band = ((1 << 20) / width).clamp(1, self.height);
            let mut lowest = f32::INFINITY;
            for first in (0..self.height).step_by(band) {
                let end = (first + band).min(self.height);
                let band_lowest = (first..end)
                    .into_par_iter()
                    .map_init(
                        || (terrain.scratch(), vec![0f32; width]),
                        |(scratch, out), row| terrain.row(row, out, scratch),
                    )
                    .reduce(|| f32::INFINITY, f32::min);
                lowest = lowest.min(band_lowest);
                progress(end);
            }
            lowest
        })
    }

    /// Fills `out` with the `out.len() / width` rows from `first_row` on (row 0 south, as in
    /// [`fbm_terrain`]'s height field), computed in parallel, row by row.
    ///
    /// Errors: [`CoreError::Grid`] when `out` is not whole rows or the rows run past the
    /// terrain.
    pub fn read_rows(&self, first_row: usize, out: &mut [f32]) -> Result<(), CoreError> {
        let width = self.width;
        let rows = out.len() / width;
        if !out.len().is_multiple_of(width)
            || first_row.checked_add(rows).is_none_or(|end| end > self.height)
        {
            return Err(CoreError::Grid(format!(
                "{} samples from row {first_row}: not whole rows of {width} within the {} rows \
                 of the terrain",
                out.len(),
                self.height
            )));
        }
        let lowest = self.lowest();
        let terrain = &self.terrain;
        out.par_chunks_mut(width).enumerate().for_each_init(
            || terrain.scratch(),
            |scratch, (k, values)| {
                terrain.row(first_row + k, values, scratch);
                for h in values.iter_mut() {
                    *h -= lowest;
                }
            },
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn terrain(width: usize, height: usize, seed: u64) -> HeightField {
        fbm_terrain(width, height, seed, &FbmParams::for_size(width, height)).unwrap()
    }

    #[test]
    fn same_seed_same_samples_other_seed_other_samples() {
        let a = terrain(300, 200, 42);
        assert_eq!(a.samples(), terrain(300, 200, 42).samples());
        let b = terrain(300, 200, 43);
        let differing = a.samples().iter().zip(b.samples()).filter(|(x, y)| x != y).count();
        assert!(differing > 300 * 200 * 9 / 10, "only {differing} samples differ");
    }

    #[test]
    fn thread_count_does_not_change_any_bit() {
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| terrain(700, 90, 5))
        };
        let (one, two) = (run(1), run(2));
        let bits = |f: &HeightField| f.samples().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&one), bits(&two));
    }

    #[test]
    fn samples_are_finite_non_negative_and_start_at_zero() {
        for (w, h) in [(1, 1), (1, 50), (50, 1), (257, 3)] {
            let field = terrain(w, h, 9);
            assert_eq!((field.width(), field.height()), (w, h));
            assert!(field.samples().iter().all(|v| v.is_finite() && *v >= 0.0));
            assert_eq!(field.min_sample(), 0.0);
        }
        // A row of more than one sample has some relief.
        assert!(terrain(1, 50, 9).max_sample() > 0.0);
    }

    #[test]
    fn relief_is_about_the_documented_fraction_of_the_longer_side() {
        for (w, h) in [(128, 128), (256, 96)] {
            for seed in 0..6 {
                let field = terrain(w, h, seed);
                let fraction = f64::from(field.max_sample()) / w.max(h) as f64;
                assert!((0.07..0.3).contains(&fraction), "{w}x{h} seed {seed}: {fraction}");
            }
        }
    }

    #[test]
    fn looks_like_mountains_not_noise() {
        // Neighbouring samples are strongly correlated: the mean step between neighbours is
        // far smaller than the total relief.
        let field = terrain(256, 256, 3);
        let s = field.samples();
        let steps: f64 = s.windows(2).map(|p| f64::from((p[1] - p[0]).abs())).sum();
        let mean_step = steps / (s.len() - 1) as f64;
        assert!(mean_step < 0.05 * f64::from(field.max_sample()), "mean step {mean_step}");
    }

    #[test]
    fn bad_sizes_and_parameters_are_errors() {
        let p = FbmParams::for_size(16, 16);
        assert!(matches!(fbm_terrain(0, 16, 1, &p), Err(CoreError::Grid(_))));
        assert!(matches!(fbm_terrain(usize::MAX, 3, 1, &p), Err(CoreError::Grid(_))));
        assert!(matches!(fbm_terrain(1 << 31, 1 << 31, 1, &p), Err(CoreError::Grid(_))));
        let bad = FbmParams { gain: 2.0, ..p };
        assert!(matches!(fbm_terrain(16, 16, 1, &bad), Err(CoreError::Parameter { .. })));
        let too_fine = FbmParams { octaves: 32, lacunarity: 1e3, ..p };
        assert!(matches!(
            fbm_terrain(16, 16, 1, &too_fine),
            Err(CoreError::Parameter { name: "octaves", .. })
        ));
    }

    #[test]
    fn rows_are_the_terrains_whatever_the_bands_and_threads() {
        let (w, h) = (333, 101);
        let params = FbmParams::for_size(w, h);
        let whole = terrain(w, h, 11);
        let bits = |s: &[f32]| s.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let rows = FbmRows::new(w, h, 11, &params).unwrap();
                let mut all = vec![0f32; w * h];
                let mut first = 0;
                for band in [1, 7, 50, 43] {
                    rows.read_rows(first, &mut all[first * w..(first + band) * w]).unwrap();
                    first += band;
                }
                assert_eq!(first, h);
                assert_eq!(bits(&all), bits(whole.samples()), "{threads} threads");
            });
        }
    }

    #[test]
    fn bad_row_requests_and_sizes_are_errors() {
        let p = FbmParams::for_size(16, 16);
        let rows = FbmRows::new(16, 16, 1, &p).unwrap();
        assert_eq!((rows.width(), rows.height()), (16, 16));
        for (first, len) in [(0, 15), (15, 32), (16, 16), (usize::MAX, 16)] {
            let mut out = vec![0f32; len];
            assert!(matches!(rows.read_rows(first, &mut out), Err(CoreError::Grid(_))));
        }
        assert!(matches!(FbmRows::new(0, 16, 1, &p), Err(CoreError::Grid(_))));
        let bad = FbmParams { gain: 2.0, ..p };
        assert!(matches!(FbmRows::new(16, 16, 1, &bad), Err(CoreError::Parameter { .. })));
    }
}
