//! Volumes of bedrock, sand and water of an [`Mlhm`] weighted by a *blurred box*: the box of
//! half-size `half` averaged over one or two uniform shifts along each axis. Over box-shaped
//! columns the plain box's volume ([`Mlhm::material_volumes`]) has a kink wherever a face of
//! the box crosses a cell edge or a column's top; one blur makes the weighted volume
//! continuously differentiable in the box's centre, two make its gradient so. The smooth
//! MLHM surface takes its normals from it.

use crate::{DVec3, MaterialVolumes, Mlhm};

/// One axis of a blurred box: the indicator of `[-half, half]` averaged over two independent
/// uniform shifts, one in `[-blurs[0], blurs[0]]` and one in `[-blurs[1], blurs[1]]`: the
/// box convolved with two normalised boxes, a weight that reaches `half + blurs[0] +
/// blurs[1]`. With no blur it is the plain box; with one, a trapezoid (piecewise linear);
/// with two, piecewise quadratic and continuously differentiable.
///
/// ```
/// use relief_core::BlurredBox;
/// let k = BlurredBox { half: 1.0, blurs: [1.0, 0.0] };
/// // Its integral is the box's length; a tent of half-width 2 here.
/// assert_eq!(k.weight(f64::NEG_INFINITY, f64::INFINITY), 2.0);
/// assert_eq!(k.weight(0.0, f64::INFINITY), 1.0);
/// assert_eq!(k.weight(1.0, 2.0), 0.25);
/// assert_eq!(BlurredBox { half: 1.0, blurs: [0.0; 2] }.weight(0.5, 5.0), 0.5);
/// let smooth = BlurredBox { half: 1.0, blurs: [1.0, 1.0] };
/// assert!((smooth.weight(0.0, 3.0) - 1.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlurredBox {
    /// The box's half-size, metres (> 0).
    pub half: f64,
    /// The largest shifts, metres (>= 0 each).
    pub blurs: [f64; 2],
}

impl BlurredBox {
    /// How far from the centre the weight reaches: `half + blurs[0] + blurs[1]`.
    #[inline]
    pub fn reach(&self) -> f64 {
        self.half + self.blurs[0] + self.blurs[1]
    }

    /// The integral of the weight from minus infinity to `x` (relative to the centre):
    /// 0 below `-reach`, the box's length `2 half` above `reach`.
    #[inline]
    pub fn cumulative(&self, x: f64) -> f64 {
        let h = self.half;
        if x <= -self.reach() {
            return 0.0;
        }
        if x >= self.reach() {
            return 2.0 * h;
        }
        self.blurred(x, 1).clamp(0.0, 2.0 * h)
    }

    /// The weight at `x` (relative to the centre), the derivative of
    /// [`cumulative`](BlurredBox::cumulative): 1 inside the plain box and 0 outside it.
    #[inline]
    pub fn density(&self, x: f64) -> f64 {
        if x <= -self.reach() || x >= self.reach() {
            return 0.0;
        }
        self.blurred(x, 0).clamp(0.0, 1.0)
    }

    /// The `order`-th integral of the plain box's indicator (0: the indicator itself), blurred:
    /// each blur is a mean over its shifts, a difference of the next integral.
    #[inline]
    fn blurred(&self, x: f64, order: u32) -> f64 {
        let h = self.half;
        let [mut a, mut b] = self.blurs;
        if a <= 0.0 {
            (a, b) = (b, 0.0);
        }
        let integral = |y: f64, k: u32| box_integral(h, y, k);
        if a <= 0.0 {
            integral(x, order)
        } else if b <= 0.0 {
            (integral(x + a, order + 1) - integral(x - a, order + 1)) / (2.0 * a)
        } else {
            let k = order + 2;
            (integral(x + a + b, k) - integral(x + a - b, k) - integral(x - a + b, k)
                + integral(x - a - b, k))
                / (4.0 * a * b)
        }
    }

    /// [`cumulative`](BlurredBox::cumulative) and [`density`](BlurredBox::density) at `x`
    /// together, sharing their work.
    #[inline]
    pub fn cumulative_and_density(&self, x: f64) -> (f64, f64) {
        let h = self.half;
        if x <= -self.reach() {
            return (0.0, 0.0);
        }
        if x >= self.reach() {
            return (2.0 * h, 0.0);
        }
        let [a, b] = self.blurs;
        if !(a > 0.0 && b > 0.0) {
            return (self.cumulative(x), self.density(x));
        }
        // The box's first two integrals at the four corners of the two shifts.
        let mut t = 0.0;
        let mut d = 0.0;
        for (y, sign) in [(x + a + b, 1.0), (x + a - b, -1.0), (x - a + b, -1.0), (x - a - b, 1.0)]
        {
            let (ti, si) = if y <= -h {
                (0.0, 0.0)
            } else if y <= h {
                let u = y + h;
                (u * u * u / 6.0, 0.5 * u * u)
            } else {
                (h * y * y + h * h * h / 3.0, 2.0 * h * y)
            };
            t += sign * ti;
            d += sign * si;
        }
        let scale = 1.0 / (4.0 * a * b);
        ((t * scale).clamp(0.0, 2.0 * h), (d * scale).clamp(0.0, 1.0))
    }

    /// The integral of the weight over `[lo, hi]` (relative to the centre; `lo <= hi`).
    #[inline]
    pub fn weight(&self, lo: f64, hi: f64) -> f64 {
        self.cumulative(hi) - self.cumulative(lo)
    }
}

/// The `order`-th integral from minus infinity of the indicator of `[-h, h]` at `y` (order 0
/// to 3: the indicator, the ramp `clamp(y + h, 0, 2h)`, and the ramp's first two integrals).
#[inline]
fn box_integral(h: f64, y: f64, order: u32) -> f64 {
    if y <= -h {
        return if order == 0 && y == -h { 1.0 } else { 0.0 };
    }
    let u = y + h;
    if y <= h {
        match order {
            0 => 1.0,
            1 => u,
            2 => 0.5 * u * u,
            _ => u * u * u / 6.0,
        }
    } else {
        match order {
            0 => 0.0,
            1 => 2.0 * h,
            2 => 2.0 * h * y,
            _ => h * y * y + h * h * h / 3.0,
        }
    }
}

/// The cells `first..end` whose span along an axis of `cells` cells of `size` metres meets
/// the weight of `kernel` centred at `centre`; `None` when none does.
#[inline]
fn covered(kernel: BlurredBox, centre: f64, cells: usize, size: f64) -> Option<(usize, usize)> {
    let (lo, hi) = ((centre - kernel.reach()) / size, (centre + kernel.reach()) / size);
    // `lo < hi` is false for NaN too.
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) || hi <= 0.0 || lo >= cells as f64 {
        return None;
    }
    let first = (lo.max(0.0).floor() as usize).min(cells - 1);
    let end = (hi.ceil().min(cells as f64) as usize).max(first + 1);
    Some((first, end))
}

impl Mlhm {
    /// The volumes of bedrock, sand and water weighted by the blurred box `kernel` (one per
    /// axis x, y, z) centred at `centre` (grid-local metres, as
    /// [`material_volumes`](Mlhm::material_volumes)): the mean of
    /// `material_volumes(centre + u - half, centre + u + half)` over the shifts `u = u1 + u2`
    /// with `|u1_i| <= kernel[i].blurs[0]` and `|u2_i| <= kernel[i].blurs[1]`, computed exactly in one pass over the cells the weight
    /// reaches. The lowest columns end at the [base](Mlhm::base); outside the grid there is
    /// nothing.
    ///
    /// ```
    /// use relief_core::{BlurredBox, DVec3, Mlhm};
    /// let map = Mlhm::new(8, 8, 1, 1.0)?; // flat bedrock at z = 0
    /// let k = BlurredBox { half: 1.0, blurs: [0.5, 0.25] };
    /// let v = map.blurred_volumes(DVec3::new(4.0, 4.0, 0.0), [k; 3]);
    /// assert!((v.bedrock - 4.0).abs() < 1e-12); // half the 2 m cube
    /// let (lo, hi) = (DVec3::new(3.0, 3.0, -0.75), DVec3::new(5.0, 5.0, 1.25));
    /// let box_volume = map.material_volumes(lo, hi);
    /// let plain = BlurredBox { half: 1.0, blurs: [0.0; 2] };
    /// let plain = map.blurred_volumes(DVec3::new(4.0, 4.0, 0.25), [plain; 3]);
    /// assert!((plain.bedrock - box_volume.bedrock).abs() < 1e-12);
    /// # Ok::<(), relief_core::CoreError>(())
    /// ```
    pub fn blurred_volumes(&self, centre: DVec3, kernel: [BlurredBox; 3]) -> MaterialVolumes {
        let s = self.cell_size();
        let (Some(xs), Some(ys)) = (
            covered(kernel[0], centre.x, self.width(), s),
            covered(kernel[1], centre.y, self.height(), s),
        ) else {
            return MaterialVolumes::ZERO;
        };
        let kz = kernel[2];
        if !centre.z.is_finite() {
            return MaterialVolumes::ZERO;
        }
        let g = |z: f32| kz.cumulative(f64::from(z) - centre.z);
        let z_reach = centre.z + kz.reach();
        let base = g(self.base());
        let stride = self.width() * self.height();
        let columns = self.raw_columns();
        let mut total = MaterialVolumes::ZERO;
        for y in ys.0..ys.1 {
            let wy = kernel[1].weight(y as f64 * s - centre.y, (y + 1) as f64 * s - centre.y);
            let mut row = MaterialVolumes::ZERO;
            for x in xs.0..xs.1 {
                let wx = kernel[0].weight(x as f64 * s - centre.x, (x + 1) as f64 * s - centre.x);
                let mut i = x + y * self.width();
                let mut floor = base;
                let mut cell = MaterialVolumes::ZERO;
                loop {
                    let column = columns[i];
                    let (bedrock, solid, water) =
                        (g(column.bedrock), g(column.solid_top()), g(column.water_top()));
                    cell.bedrock += bedrock - floor;
                    cell.sand += solid - bedrock;
                    cell.water += water - solid;
                    // The topmost column's ceiling is infinite.
                    if f64::from(column.ceiling) >= z_reach {
                        break;
                    }
                    floor = g(column.ceiling);
                    i += stride;
                }
                row += cell * wx;
            }
            total += row * wy;
        }
        total
    }
}

impl Mlhm {
    /// The gradient of [`blurred_volumes`](Mlhm::blurred_volumes) with respect to `centre`:
    /// the derivatives of the weighted volumes of bedrock, sand and water along x, y and z,
    /// exact, in one pass over the cells the weight reaches (the weight's derivative along
    /// an axis is the difference of its [density](BlurredBox::density) at the two ends of
    /// each cell or material interval).
    ///
    /// ```
    /// use relief_core::{BlurredBox, DVec3, Mlhm};
    /// let map = Mlhm::new(8, 8, 1, 1.0)?; // flat bedrock at z = 0
    /// let k = BlurredBox { half: 1.0, blurs: [1.0, 1.0] };
    /// let [dx, dy, dz] = map.blurred_volume_gradient(DVec3::new(4.0, 4.0, 0.3), [k; 3]);
    /// assert!(dx.bedrock.abs() < 1e-12 && dy.bedrock.abs() < 1e-12); // flat across
    /// assert!((dz.bedrock + 4.0 * k.density(-0.3)).abs() < 1e-12); // rock leaves the box
    /// # Ok::<(), relief_core::CoreError>(())
    /// ```
    pub fn blurred_volume_gradient(
        &self,
        centre: DVec3,
        kernel: [BlurredBox; 3],
    ) -> [MaterialVolumes; 3] {
        let zero = [MaterialVolumes::ZERO; 3];
        let s = self.cell_size();
        let (Some(xs), Some(ys)) = (
            covered(kernel[0], centre.x, self.width(), s),
            covered(kernel[1], centre.y, self.height(), s),
        ) else {
            return zero;
        };
        let kz = kernel[2];
        if !centre.z.is_finite() {
            return zero;
        }
        // An interval's weight and the derivative of its weight along the axis, from its
        // ends relative to the centre.
        let ends = |k: BlurredBox, lo: f64, hi: f64| {
            let ((c_lo, d_lo), (c_hi, d_hi)) =
                (k.cumulative_and_density(lo), k.cumulative_and_density(hi));
            (c_hi - c_lo, d_lo - d_hi)
        };
        let g = |z: f32| kz.cumulative_and_density(f64::from(z) - centre.z);
        let z_reach = centre.z + kz.reach();
        let base = g(self.base());
        let stride = self.width() * self.height();
        let columns = self.raw_columns();
        let axis = |k: BlurredBox, cell: usize, c: f64| {
            ends(k, cell as f64 * s - c, (cell + 1) as f64 * s - c)
        };
        let mut total = zero;
        for y in ys.0..ys.1 {
            let (wy, dy) = axis(kernel[1], y, centre.y);
            let mut row = zero;
            for x in xs.0..xs.1 {
                let (wx, dx) = axis(kernel[0], x, centre.x);
                let mut i = x + y * self.width();
                let mut floor = base;
                let (mut cell, mut along_z) = (MaterialVolumes::ZERO, MaterialVolumes::ZERO);
                loop {
                    let column = columns[i];
                    let bedrock = g(column.bedrock);
                    // Most columns hold no sand or no water: their tops coincide.
                    let (solid_top, water_top) = (column.solid_top(), column.water_top());
                    let solid = if solid_top == column.bedrock { bedrock } else { g(solid_top) };
                    let water = if water_top == solid_top { solid } else { g(water_top) };
                    cell.bedrock += bedrock.0 - floor.0;
                    cell.sand += solid.0 - bedrock.0;
                    cell.water += water.0 - solid.0;
                    along_z.bedrock += floor.1 - bedrock.1;
                    along_z.sand += bedrock.1 - solid.1;
                    along_z.water += solid.1 - water.1;
                    if f64::from(column.ceiling) >= z_reach {
                        break;
                    }
                    floor = g(column.ceiling);
                    i += stride;
                }
                row[0] += cell * dx;
                row[1] += cell * wx;
                row[2] += along_z * wx;
            }
            total[0] += row[0] * wy;
            total[1] += row[1] * dy;
            total[2] += row[2] * wy;
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MlhmColumn;

    #[test]
    fn cumulative_is_the_mean_of_the_shifted_boxes() {
        let cases = [([1.0, 0.0], 1.0), ([0.5, 0.0], 1.0), ([2.0, 0.0], 0.5), ([1.0, 1.0], 1.0)];
        let cases = cases.into_iter().chain([([0.5, 0.25], 2.0), ([0.0, 0.7], 1.0)]);
        for (blurs, half) in cases {
            let k = BlurredBox { half, blurs };
            for i in -50..=50 {
                let x = i as f64 * 0.1;
                // The mean over 400 x 400 shifts of the box's cumulative, by the midpoint rule.
                let n = 400;
                let shift = |j: usize, b: f64| -b + (j as f64 + 0.5) / n as f64 * 2.0 * b;
                let mut mean = 0.0;
                for j in 0..n {
                    for l in 0..n {
                        let u = shift(j, blurs[0]) + shift(l, blurs[1]);
                        mean += (x - u + half).clamp(0.0, 2.0 * half);
                    }
                }
                let mean = mean / (n * n) as f64;
                assert!((k.cumulative(x) - mean).abs() < 1e-4, "{half} {blurs:?} {x}");
                let (c, d) = k.cumulative_and_density(x);
                assert!((c - k.cumulative(x)).abs() < 1e-12 && (d - k.density(x)).abs() < 1e-12);
                let e = 1e-6;
                let slope = (k.cumulative(x + e) - k.cumulative(x - e)) / (2.0 * e);
                assert!((slope - d).abs() < 1e-4 || blurs == [0.0; 2], "{blurs:?} {x}");
            }
        }
    }

    #[test]
    fn the_gradient_is_the_derivative_of_the_blurred_volumes() {
        let mut map = Mlhm::new(6, 5, 3, 0.5).unwrap();
        for y in 0..5 {
            for x in 0..6 {
                let t = (x * 7 + y * 3) as f32 * 0.13;
                let cell = [
                    MlhmColumn::new(t, 0.1, 0.2, t + 0.9),
                    MlhmColumn::new(t + 1.4, 0.2, 0.0, f32::INFINITY),
                ];
                map.set_cell(x, y, &cell).unwrap();
            }
        }
        map.set_base(-0.2);
        let kernel =
            [[0.3, 0.2], [0.25, 0.0], [0.2, 0.3]].map(|blurs| BlurredBox { half: 0.6, blurs });
        let e = 1e-5;
        for p in [DVec3::new(1.3, 1.1, 1.0), DVec3::new(0.1, 2.4, 2.2), DVec3::new(2.9, 0.2, -0.3)]
        {
            let gradient = map.blurred_volume_gradient(p, kernel);
            for (axis, g) in gradient.iter().enumerate() {
                let mut d = DVec3::ZERO;
                d[axis] = e;
                let (hi, lo) =
                    (map.blurred_volumes(p + d, kernel), map.blurred_volumes(p - d, kernel));
                let fd = (hi + lo * -1.0) * (0.5 / e);
                for (a, b) in [(g.bedrock, fd.bedrock), (g.sand, fd.sand), (g.water, fd.water)] {
                    assert!((a - b).abs() < 1e-5, "{p} axis {axis}: {g:?} {fd:?}");
                }
            }
        }
    }

    #[test]
    fn blurred_volumes_are_the_mean_of_the_shifted_box_volumes() {
        let mut map = Mlhm::new(6, 5, 3, 0.5).unwrap();
        for y in 0..5 {
            for x in 0..6 {
                let t = (x * 7 + y * 3) as f32 * 0.13;
                map.set_cell(
                    x,
                    y,
                    &[
                        MlhmColumn::new(t, 0.1, 0.2, t + 0.9),
                        MlhmColumn::new(t + 1.4, 0.2, 0.0, f32::INFINITY),
                    ],
                )
                .unwrap();
            }
        }
        map.set_base(-0.3);
        let half = 0.6;
        let blur = DVec3::new(0.3, 0.45, 0.2);
        let kernel = [0, 1, 2].map(|a| BlurredBox { half, blurs: [blur[a], 0.0] });
        for p in [DVec3::new(1.3, 1.1, 1.0), DVec3::new(0.1, 2.4, 2.2), DVec3::new(2.9, 0.2, -0.2)]
        {
            let v = map.blurred_volumes(p, kernel);
            // Midpoint rule over the shifts: exact enough for piecewise smooth means.
            let n = 24;
            let mut mean = MaterialVolumes::ZERO;
            for i in 0..n {
                for j in 0..n {
                    for k in 0..n {
                        let f = |m: usize| (m as f64 + 0.5) / n as f64 * 2.0 - 1.0;
                        let u = DVec3::new(f(i), f(j), f(k)) * blur;
                        mean += map.material_volumes(p + u - half, p + u + half);
                    }
                }
            }
            let mean = mean * (1.0 / (n * n * n) as f64);
            for (a, b) in [(v.bedrock, mean.bedrock), (v.sand, mean.sand), (v.water, mean.water)] {
                assert!((a - b).abs() < 2e-3 * (2.0 * half).powi(3), "{p}: {v:?} {mean:?}");
            }
        }
    }
}
