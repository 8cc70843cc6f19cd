//! Seeded 2D gradient (Perlin-style) noise on the integer lattice, with a hashed lattice.
//!
//! Points are evaluated in batches, in two passes: [`GradientNoise::locate`] finds each
//! point's cell and fetches the cell's gradients (branchy, scalar), then
//! [`NoiseBatch::evaluate`] blends them (straight-line f32 arithmetic the compiler
//! vectorises). Each point's result depends on that point alone, so batching never changes a
//! value.

/// Number of gradient directions; a power of two so a hash picks one with a shift.
const DIRECTIONS: usize = 32;

/// 2D gradient noise: each lattice point `(ix, iy)` carries a unit gradient picked by an
/// integer hash of `(ix, iy, seed)`; the noise at a point blends the four surrounding
/// gradients' linear ramps with Perlin's quintic fade. Values lie in
/// `[-1/sqrt 2, 1/sqrt 2]`, are 0 on lattice points, and vary smoothly (C2).
#[derive(Debug, Clone)]
pub(crate) struct GradientNoise {
    seed: u64,
    gradients: [[f32; 2]; DIRECTIONS],
}

/// The cell located last and its corner gradients, reused while points stay in that cell
/// (neighbouring samples mostly share a cell at low frequencies).
#[derive(Debug, Clone, Copy)]
pub(crate) struct CellCache {
    /// Lower corner of the cell (integral values), NaN before the first point.
    cell: [f64; 2],
    /// Gradients at (ix, iy), (ix+1, iy), (ix, iy+1), (ix+1, iy+1).
    corners: [[f32; 2]; 4],
}

impl Default for CellCache {
    fn default() -> Self {
        CellCache { cell: [f64::NAN; 2], corners: [[0.0; 2]; 4] }
    }
}

/// A batch of located points: each one's offset in its cell and its cell's gradients.
#[derive(Debug, Clone, Default)]
pub(crate) struct NoiseBatch {
    cell_u: Vec<f64>,
    cell_v: Vec<f64>,
    dx: Vec<f32>,
    dy: Vec<f32>,
    /// Corner gradient components: x and y of the corners in [`CellCache`] order.
    corners: [Vec<f32>; 8],
}

impl GradientNoise {
    /// Noise whose lattice gradients are determined by `seed`.
    pub(crate) fn new(seed: u64) -> Self {
        let gradients = std::array::from_fn(|k| {
            // Offset by half a step so that no gradient lies on an axis.
            let angle = (k as f64 + 0.5) * std::f64::consts::TAU / DIRECTIONS as f64;
            [angle.cos() as f32, angle.sin() as f32]
        });
        GradientNoise { seed: mix64(seed), gradients }
    }

    /// The unit gradient at lattice point `(ix, iy)`.
    #[inline]
    fn gradient(&self, ix: i64, iy: i64) -> [f32; 2] {
        let h = mix64(
            self.seed
                ^ (ix as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
                ^ (iy as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f),
        );
        self.gradients[(h >> 59) as usize]
    }

    /// Locates the points `(us[i], vs[i])` (pairs beyond the shorter slice are ignored) into
    /// `batch`, replacing its contents. `cache` carries the last cell across calls.
    pub(crate) fn locate(
        &self,
        us: &[f64],
        vs: &[f64],
        cache: &mut CellCache,
        batch: &mut NoiseBatch,
    ) {
        let len = us.len().min(vs.len());
        for v in [&mut batch.cell_u, &mut batch.cell_v] {
            v.resize(len, 0.0);
        }
        batch.dx.resize(len, 0.0);
        batch.dy.resize(len, 0.0);
        batch.corners.iter_mut().for_each(|c| c.resize(len, 0.0));
        let (us, vs) = (&us[..len], &vs[..len]);
        let (cell_u, cell_v) = (&mut batch.cell_u[..len], &mut batch.cell_v[..len]);
        let (dx, dy) = (&mut batch.dx[..len], &mut batch.dy[..len]);
        // Branch-free, so vectorised.
        for i in 0..len {
            (cell_u[i], cell_v[i]) = (floor(us[i]), floor(vs[i]));
            dx[i] = (us[i] - cell_u[i]) as f32;
            dy[i] = (vs[i] - cell_v[i]) as f32;
        }
        let [g00x, g00y, g10x, g10y, g01x, g01y, g11x, g11y] =
            batch.corners.each_mut().map(|c| &mut c[..len]);
        for i in 0..len {
            let cell = [cell_u[i], cell_v[i]];
            // NaN in a fresh cache compares unequal to every cell.
            if cache.cell != cell {
                let (iu, iv) = (lattice_index(cell[0]), lattice_index(cell[1]));
                let (ju, jv) = (iu.wrapping_add(1), iv.wrapping_add(1));
                cache.corners = [
                    self.gradient(iu, iv),
                    self.gradient(ju, iv),
                    self.gradient(iu, jv),
                    self.gradient(ju, jv),
                ];
                cache.cell = cell;
            }
            let [[a, b], [c, d], [e, f], [g, h]] = cache.corners;
            (g00x[i], g00y[i], g10x[i], g10y[i]) = (a, b, c, d);
            (g01x[i], g01y[i], g11x[i], g11y[i]) = (e, f, g, h);
        }
    }
}

impl NoiseBatch {
    /// Number of points located.
    pub(crate) fn len(&self) -> usize {
        self.dx.len()
    }

    /// The noise `n` and its gradient `(du, dv)` at every located point. The outputs must be
    /// at least [`NoiseBatch::len`] long; entries beyond it are left alone.
    pub(crate) fn evaluate(&self, n: &mut [f32], du: &mut [f32], dv: &mut [f32]) {
        let len = self.len().min(n.len()).min(du.len()).min(dv.len());
        let (dx, dy) = (&self.dx[..len], &self.dy[..len]);
        let [g00x, g00y, g10x, g10y, g01x, g01y, g11x, g11y] =
            self.corners.each_ref().map(|c| &c[..len]);
        let (n, du, dv) = (&mut n[..len], &mut du[..len], &mut dv[..len]);
        for i in 0..len {
            let (x, y) = (dx[i], dy[i]);
            let n00 = g00x[i] * x + g00y[i] * y;
            let n10 = g10x[i] * (x - 1.0) + g10y[i] * y;
            let n01 = g01x[i] * x + g01y[i] * (y - 1.0);
            let n11 = g11x[i] * (x - 1.0) + g11y[i] * (y - 1.0);
            let (u, v) = (fade(x), fade(y));
            let (su, sv) = (fade_slope(x), fade_slope(y));
            let bottom = n00 + u * (n10 - n00);
            let top = n01 + u * (n11 - n01);
            n[i] = bottom + v * (top - bottom);
            let bottom_u = g00x[i] + u * (g10x[i] - g00x[i]) + su * (n10 - n00);
            let top_u = g01x[i] + u * (g11x[i] - g01x[i]) + su * (n11 - n01);
            let bottom_v = g00y[i] + u * (g10y[i] - g00y[i]);
            let top_v = g01y[i] + u * (g11y[i] - g01y[i]);
            du[i] = bottom_u + v * (top_u - bottom_u);
            dv[i] = bottom_v + v * (top_v - bottom_v) + sv * (top - bottom);
        }
    }
}

/// Adding then subtracting 1.5 * 2^52 rounds an f64 of magnitude below 2^51 to an integer.
const ROUNDING: f64 = 6_755_399_441_055_744.0;

/// `x` rounded down, branch-free and without the library call `f64::floor` becomes on
/// baseline x86-64. Exact for |x| < 2^51 (lattice coordinates are kept far below).
#[inline]
fn floor(x: f64) -> f64 {
    let nearest = (x + ROUNDING) - ROUNDING;
    if nearest > x {
        nearest - 1.0
    } else {
        nearest
    }
}

/// The integer value of an integral `f` with |f| < 2^51, read from the bits of `f + 1.5 * 2^52`
/// (whose last place is worth 1); other inputs give some integer, never a panic.
#[inline]
fn lattice_index(f: f64) -> i64 {
    ((f + ROUNDING).to_bits() as i64).wrapping_sub(ROUNDING.to_bits() as i64)
}

/// Perlin's quintic fade 6t^5 - 15t^4 + 10t^3: zero first and second derivatives at 0 and 1.
#[inline]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Derivative of [`fade`]: 30t^2 (t - 1)^2.
#[inline]
fn fade_slope(t: f32) -> f32 {
    let s = t * (t - 1.0);
    30.0 * s * s
}

/// A 64-bit finalising hash (the one of SplitMix64): every input bit affects every output bit.
#[inline]
pub(crate) fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Noise and gradient at each point, evaluated as one batch.
    fn eval(noise: &GradientNoise, points: &[(f64, f64)]) -> Vec<[f32; 3]> {
        let (us, vs): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
        let mut batch = NoiseBatch::default();
        noise.locate(&us, &vs, &mut CellCache::default(), &mut batch);
        let mut out = vec![vec![0f32; points.len()]; 3];
        let [n, du, dv] = &mut out[..] else { unreachable!() };
        batch.evaluate(n, du, dv);
        (0..points.len()).map(|i| [n[i], du[i], dv[i]]).collect()
    }

    #[test]
    fn zero_on_lattice_points_and_bounded_elsewhere() {
        let noise = GradientNoise::new(7);
        let points: Vec<_> =
            (0..20_000).map(|i| (i as f64 * 0.137 - 500.0, i as f64 * 0.071 - 300.0)).collect();
        let max = eval(&noise, &points).iter().fold(0f32, |m, r| m.max(r[0].abs()));
        assert!(max > 0.3 && max <= std::f32::consts::FRAC_1_SQRT_2 + 1e-6, "max {max}");
        let lattice: Vec<_> = points.iter().map(|&(x, y)| (x.floor(), y.floor())).collect();
        assert!(eval(&noise, &lattice).iter().all(|r| r[0] == 0.0));
    }

    #[test]
    fn batching_and_caching_do_not_change_values() {
        let noise = GradientNoise::new(11);
        let points: Vec<_> =
            (0..1000).map(|i| (i as f64 * 0.01 - 4.0, 3.3 - i as f64 * 0.003)).collect();
        let together = eval(&noise, &points);
        for (p, expected) in points.iter().zip(&together) {
            let alone = eval(&noise, &[*p])[0];
            assert_eq!(alone.map(f32::to_bits), expected.map(f32::to_bits));
        }
    }

    #[test]
    fn gradient_matches_finite_differences_and_values_are_continuous() {
        let noise = GradientNoise::new(3);
        let h = 1e-3;
        for k in 0..400 {
            // Includes points just either side of cell borders.
            let (x, y) = (k as f64 * 0.05 - 10.0 + 1e-7, k as f64 * 0.031 - 6.0);
            let r = eval(&noise, &[(x, y), (x + h, y), (x - h, y), (x, y + h), (x, y - h)]);
            let fx = (r[1][0] - r[2][0]) / (2.0 * h as f32);
            let fy = (r[3][0] - r[4][0]) / (2.0 * h as f32);
            assert!((fx - r[0][1]).abs() < 2e-3 && (fy - r[0][2]).abs() < 2e-3, "at ({x}, {y})");
            let across = eval(&noise, &[(x - 2e-7, y)])[0][0];
            assert!((across - r[0][0]).abs() < 1e-5, "jump at ({x}, {y})");
        }
    }

    #[test]
    fn different_seeds_give_different_noise() {
        let points: Vec<_> = (0..100).map(|i| (i as f64 * 0.37, i as f64 * 0.11)).collect();
        assert_ne!(eval(&GradientNoise::new(1), &points), eval(&GradientNoise::new(2), &points));
    }

    #[test]
    fn floor_and_lattice_index_agree_with_the_library_on_both_sides_of_zero() {
        for x in [2.5, -0.5, -3.0, 0.0, 0.999_999_999, -1e-300, 1e12 + 0.5, -7.5e14, 4.5] {
            assert_eq!(floor(x), x.floor(), "floor({x})");
            assert_eq!(lattice_index(floor(x)), x.floor() as i64, "index of {x}");
        }
    }
}
