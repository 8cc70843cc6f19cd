//! Seeded 2D gradient (Perlin-style) noise on the integer lattice, with a hashed lattice.

/// Number of gradient directions; a power of two so a hash picks one with a mask.
const DIRECTIONS: usize = 32;

/// 2D gradient noise: each lattice point `(ix, iy)` carries a unit gradient picked by an
/// integer hash of `(ix, iy, seed)`; the noise at a point blends the four surrounding
/// gradients' linear ramps with a quintic fade. Values lie in about `[-0.71, 0.71]` and are 0
/// on lattice points.
#[derive(Debug, Clone)]
pub(crate) struct GradientNoise {
    seed: u64,
    gradients: [[f64; 2]; DIRECTIONS],
}

/// The gradients of the lattice cell evaluated last, reused while points stay in that cell
/// (neighbouring samples of a row mostly share a cell at low frequencies).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct CellCache {
    cell: Option<(i64, i64)>,
    /// Gradients at (ix, iy), (ix+1, iy), (ix, iy+1), (ix+1, iy+1).
    corners: [[f64; 2]; 4],
}

impl GradientNoise {
    /// Noise whose lattice gradients are determined by `seed`.
    pub(crate) fn new(seed: u64) -> Self {
        let gradients = std::array::from_fn(|k| {
            // Offset by half a step so that no gradient lies on an axis.
            let angle = (k as f64 + 0.5) * std::f64::consts::TAU / DIRECTIONS as f64;
            [angle.cos(), angle.sin()]
        });
        GradientNoise { seed: mix64(seed), gradients }
    }

    /// The unit gradient at lattice point `(ix, iy)`.
    #[inline]
    fn gradient(&self, ix: i64, iy: i64) -> [f64; 2] {
        let h = mix64(
            self.seed
                ^ (ix as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
                ^ (iy as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f),
        );
        self.gradients[(h >> 59) as usize & (DIRECTIONS - 1)]
    }

    /// The noise at `(x, y)`, reusing `cache` when the point lies in the cell evaluated last.
    #[inline]
    pub(crate) fn eval(&self, x: f64, y: f64, cache: &mut CellCache) -> f64 {
        let (fx, fy) = (x.floor(), y.floor());
        // Saturating casts: far-away (or non-finite) points land on some cell, never panic.
        let cell = (fx as i64, fy as i64);
        if cache.cell != Some(cell) {
            let (ix, iy) = cell;
            let (jx, jy) = (ix.wrapping_add(1), iy.wrapping_add(1));
            cache.corners = [
                self.gradient(ix, iy),
                self.gradient(jx, iy),
                self.gradient(ix, jy),
                self.gradient(jx, jy),
            ];
            cache.cell = Some(cell);
        }
        let (dx, dy) = (x - fx, y - fy);
        let [g00, g10, g01, g11] = cache.corners;
        let n00 = g00[0] * dx + g00[1] * dy;
        let n10 = g10[0] * (dx - 1.0) + g10[1] * dy;
        let n01 = g01[0] * dx + g01[1] * (dy - 1.0);
        let n11 = g11[0] * (dx - 1.0) + g11[1] * (dy - 1.0);
        let (u, v) = (fade(dx), fade(dy));
        let bottom = n00 + u * (n10 - n00);
        let top = n01 + u * (n11 - n01);
        bottom + v * (top - bottom)
    }

    /// The noise at `(x, y)` and its gradient `[n, dn/dx, dn/dy]`, reusing `cache` like
    /// [`GradientNoise::eval`].
    #[inline]
    pub(crate) fn eval_with_gradient(&self, x: f64, y: f64, cache: &mut CellCache) -> [f64; 3] {
        let (fx, fy) = (x.floor(), y.floor());
        let cell = (fx as i64, fy as i64);
        if cache.cell != Some(cell) {
            let (ix, iy) = cell;
            let (jx, jy) = (ix.wrapping_add(1), iy.wrapping_add(1));
            cache.corners = [
                self.gradient(ix, iy),
                self.gradient(jx, iy),
                self.gradient(ix, jy),
                self.gradient(jx, jy),
            ];
            cache.cell = Some(cell);
        }
        let (dx, dy) = (x - fx, y - fy);
        let [g00, g10, g01, g11] = cache.corners;
        let n00 = g00[0] * dx + g00[1] * dy;
        let n10 = g10[0] * (dx - 1.0) + g10[1] * dy;
        let n01 = g01[0] * dx + g01[1] * (dy - 1.0);
        let n11 = g11[0] * (dx - 1.0) + g11[1] * (dy - 1.0);
        let (u, v) = (fade(dx), fade(dy));
        let (du, dv) = (fade_slope(dx), fade_slope(dy));
        let bottom = n00 + u * (n10 - n00);
        let top = n01 + u * (n11 - n01);
        let n = bottom + v * (top - bottom);
        let lerp = |a: f64, b: f64, t: f64| a + t * (b - a);
        let bottom_x = lerp(g00[0], g10[0], u) + du * (n10 - n00);
        let top_x = lerp(g01[0], g11[0], u) + du * (n11 - n01);
        let bottom_y = lerp(g00[1], g10[1], u);
        let top_y = lerp(g01[1], g11[1], u);
        [n, lerp(bottom_x, top_x, v), lerp(bottom_y, top_y, v) + dv * (top - bottom)]
    }
}

/// Perlin's quintic fade 6t^5 - 15t^4 + 10t^3: zero first and second derivatives at 0 and 1.
#[inline]
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Derivative of [`fade`]: 30t^2 (t - 1)^2.
#[inline]
fn fade_slope(t: f64) -> f64 {
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

    #[test]
    fn zero_on_lattice_points_and_bounded_elsewhere() {
        let noise = GradientNoise::new(7);
        let mut cache = CellCache::default();
        let mut max: f64 = 0.0;
        for i in 0..20_000 {
            let (x, y) = (i as f64 * 0.137 - 500.0, i as f64 * 0.071 - 300.0);
            max = max.max(noise.eval(x, y, &mut cache).abs());
            assert_eq!(noise.eval(x.floor(), y.floor(), &mut cache), 0.0);
        }
        assert!(max > 0.3 && max <= std::f64::consts::FRAC_1_SQRT_2 + 1e-12, "max {max}");
    }

    #[test]
    fn cache_does_not_change_values() {
        let noise = GradientNoise::new(11);
        let mut warm = CellCache::default();
        for i in 0..1000 {
            let (x, y) = (i as f64 * 0.01, 3.3 - i as f64 * 0.003);
            let cold = noise.eval(x, y, &mut CellCache::default());
            assert_eq!(noise.eval(x, y, &mut warm).to_bits(), cold.to_bits());
        }
    }

    #[test]
    fn continuous_across_cell_borders() {
        let noise = GradientNoise::new(3);
        let mut cache = CellCache::default();
        let eps = 1e-9;
        for k in -5..5 {
            let (x, y) = (k as f64, 0.37 * k as f64 + 0.5);
            let jump = noise.eval(x - eps, y, &mut cache) - noise.eval(x + eps, y, &mut cache);
            assert!(jump.abs() < 1e-6, "jump {jump} at x = {x}");
        }
    }
}
