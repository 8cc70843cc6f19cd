//! The precomputation of one ray class's shapes (Baboud et al., 6.1-6.3), in its local frame.

use super::frame::LocalField;
use super::limiting::LimitingTest;
use super::nbuffer::NBuffer;
use super::options::{ConeMode, SafetyOptions};

/// One texel's shape for one class: the safety radius `r` (a number of x-centerlines) and the
/// cone plane `z0 + slope * x` (`x` counted in centerlines from the texel) that lies above
/// every limiting triangle past the radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexelShape {
    /// Safety distance: no limiting triangle lies in the first `radius` columns.
    pub radius: u16,
    /// Cone plane height at the texel (`+inf`: no cone, the radius is the whole shape).
    pub z0: f64,
    /// Cone plane slope per centerline (`-inf`: nothing beyond the radius to stay above).
    pub slope: f64,
}

impl TexelShape {
    /// A shape with no cone.
    pub fn cylinder(radius: u16) -> Self {
        TexelShape { radius, z0: f64::INFINITY, slope: f64::INFINITY }
    }
}

/// Computes the shapes of one class, texel by texel, in its local frame.
pub struct ClassPrecompute<'a> {
    test: LimitingTest<'a>,
    nbuffer: Option<NBuffer>,
    /// Highest sample in local columns `x..` (for cutting the cone scans short).
    suffix_max: Vec<f64>,
    options: SafetyOptions,
}

impl<'a> ClassPrecompute<'a> {
    /// Prepares the class's limiting test and, for cones, its N-buffer.
    pub fn new(test: LimitingTest<'a>, options: SafetyOptions) -> Self {
        let field = *test.field();
        let nbuffer = (options.cone != ConeMode::None).then(|| NBuffer::new(&field));
        let mut suffix_max = vec![f64::NEG_INFINITY; field.width() + 1];
        for i in (0..field.width()).rev() {
            let column =
                (0..field.height()).map(|j| field.h(i, j)).fold(f64::NEG_INFINITY, f64::max);
            suffix_max[i] = suffix_max[i + 1].max(column);
        }
        ClassPrecompute { test, nbuffer, suffix_max, options }
    }

    fn field(&self) -> &LocalField<'a> {
        self.test.field()
    }

    /// Local cells of column `col` that rays of class `x+` leaving `s_tau` (texel row `j`) can
    /// reach, `m = col - i` columns ahead.
    fn reachable_rows(&self, j: usize, m: usize) -> std::ops::RangeInclusive<usize> {
        let rows = self.field().height() - 1;
        let first = (j as isize - m as isize - 2).max(0) as usize;
        let last = (j + m + 1).min(rows - 1);
        first..=last
    }

    /// The highest vertex a class-`x+` ray from texel row `j` can meet at local column `x`
    /// (`dx` columns ahead).
    fn reachable_max(&self, x: usize, j: usize, dx: usize) -> f64 {
        let nb = self.nbuffer.as_ref().expect("cones have an N-buffer");
        nb.window_max(x, j as isize - dx as isize - 2, (j + dx + 2) as isize) as f64
    }

    /// The steepest slope from `(radius, z_c)` that any sample in local columns `x..` can ask
    /// for, `dx..=dx_max` columns past the radius.
    fn slope_bound(&self, x: usize, z_c: f64, dx: usize, dx_max: usize) -> f64 {
        let rise = self.suffix_max[x] - z_c;
        rise / if rise >= 0.0 { dx } else { dx_max } as f64
    }

    /// The shape of texel (i, j).
    pub fn texel(&self, i: usize, j: usize) -> TexelShape {
        let reach = self.options.reach;
        let columns = (reach as usize).min(self.field().width() - 1 - i);
        let limiting_in = |m: usize| {
            self.reachable_rows(j, m)
                .flat_map(|cj| [(cj, 0), (cj, 1)])
                .filter(move |&(cj, k)| self.test.is_limiting(i, j, i + m, cj, k))
        };
        let Some(radius) = (0..columns).find(|&m| limiting_in(m).next().is_some()) else {
            return TexelShape::cylinder(reach);
        };
        let radius_u16 = if self.options.strictly_positive { radius.max(1) } else { radius } as u16;
        let (z0, slope) = match self.options.cone {
            ConeMode::None => return TexelShape::cylinder(radius_u16),
            ConeMode::NBuffer => self.nbuffer_cone(i, j, radius, columns),
            ConeMode::Exact => self.exact_cone(i, j, radius, columns, &limiting_in),
        };
        TexelShape { radius: radius_u16, z0, slope }
    }

    /// The conservative cone (6.3.2, "accelerating computations"): every reachable vertex past
    /// the radius stays under the plane.
    fn nbuffer_cone(&self, i: usize, j: usize, r: usize, columns: usize) -> (f64, f64) {
        let z_c = self.reachable_max(i + r, j, r);
        let mut slope = f64::NEG_INFINITY;
        for x in r + 1..=columns {
            if self.slope_bound(i + x, z_c, x - r, columns - r) <= slope {
                break;
            }
            let s = (self.reachable_max(i + x, j, x) - z_c) / (x - r) as f64;
            slope = slope.max(s);
        }
        cone_plane(z_c, r, slope)
    }

    /// The exact cone (6.3.2): `z_c` is the highest vertex of the limiting triangles at the
    /// radius, then the smallest slope that keeps every limiting triangle past it under the
    /// plane. Columns whose highest vertex cannot raise the slope are skipped untested.
    fn exact_cone<I: Iterator<Item = (usize, usize)>>(
        &self,
        i: usize,
        j: usize,
        r: usize,
        columns: usize,
        limiting_in: &dyn Fn(usize) -> I,
    ) -> (f64, f64) {
        let field = self.field();
        let at_radius: Vec<(usize, usize)> = limiting_in(r).collect();
        let vertices = |cj: usize, k: usize, m: usize| field.cell_triangles(i + m, cj)[k];
        let z_c = at_radius
            .iter()
            .flat_map(|&(cj, k)| vertices(cj, k, r))
            .filter(|v| v.x == (i + r) as f64)
            .map(|v| v.z)
            .fold(f64::NEG_INFINITY, f64::max);
        let mut slope = f64::NEG_INFINITY;
        let raise = |cj: usize, k: usize, m: usize, slope: &mut f64| {
            for v in vertices(cj, k, m) {
                let dx = v.x - (i + r) as f64;
                if dx > 0.0 {
                    *slope = slope.max((v.z - z_c) / dx);
                }
            }
        };
        for &(cj, k) in &at_radius {
            raise(cj, k, r, &mut slope);
        }
        for m in r + 1..columns {
            let dx = (m - r) as f64;
            if self.slope_bound(i + m, z_c, m - r, columns - r) <= slope {
                break;
            }
            let column_top =
                self.reachable_max(i + m, j, m).max(self.reachable_max(i + m + 1, j, m));
            let rise = column_top - z_c;
            if rise / if rise >= 0.0 { dx } else { dx + 1.0 } <= slope {
                continue;
            }
            for cj in self.reachable_rows(j, m) {
                for k in 0..2 {
                    let tri = vertices(cj, k, m);
                    let best = tri
                        .iter()
                        .map(|v| (v.z - z_c) / (v.x - (i + r) as f64))
                        .fold(f64::NEG_INFINITY, f64::max);
                    if best > slope && self.test.is_limiting(i, j, i + m, cj, k) {
                        raise(cj, k, m, &mut slope);
                    }
                }
            }
        }
        cone_plane(z_c, r, slope)
    }
}

/// The cone plane `z0 + slope * x` through `(r, z_c)`; with no slope (nothing past the radius)
/// the plane is `-inf`, and any step within the reach is safe.
fn cone_plane(z_c: f64, r: usize, slope: f64) -> (f64, f64) {
    if slope.is_finite() {
        (z_c - r as f64 * slope, slope)
    } else {
        (f64::NEG_INFINITY, slope)
    }
}
