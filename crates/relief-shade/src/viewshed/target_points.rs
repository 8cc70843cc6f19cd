//! The target points of a viewshed's samples: each sample point raised by the target height and
//! by the lift every shade-map ray starts with ([`crate::shade_map::SURFACE_LIFT`]), made from
//! what the samples share (their columns' x, their rows' y, the field's lift) for every
//! observer and every run of a row, with the same bits as
//! [`crate::shade_map::surface_origin`] plus the target height.

use super::unit_runs::{prefetch_run, ROWS_AHEAD};
use super::ViewshedParams;
use crate::shade_map::surface_ray::{inward, SurfaceLift};
use relief_core::{DVec3, HeightField};

/// The target points of a field's samples for one viewshed's parameters.
pub(crate) struct TargetPoints<'a> {
    field: &'a HeightField,
    void: Option<&'a [bool]>,
    lift: SurfaceLift,
    target_height: f64,
    radius: Option<f64>,
    /// Per column, the sample points' world x; per row, their world y.
    xs: Vec<f64>,
    ys: Vec<f64>,
    /// Per column and per row, which way the border's lift moves a target inward: 1, -1 or
    /// 0 times the lift (see [`inward`]).
    col_inward: Vec<f64>,
    row_inward: Vec<f64>,
}

impl<'a> TargetPoints<'a> {
    /// The target points of `field`'s samples (none on its holes and on the samples `void`
    /// flags) for `params`'s target height and radius.
    pub(crate) fn new(
        field: &'a HeightField,
        void: Option<&'a [bool]>,
        params: &ViewshedParams,
    ) -> TargetPoints<'a> {
        let g = field.geometry();
        // As `GridGeometry::point_to_world` places them.
        let xs = (0..field.width()).map(|c| (c as f64 + 0.5) * g.dx + g.origin.x).collect();
        let ys = (0..field.height()).map(|r| (r as f64 + 0.5) * g.dy + g.origin.y).collect();
        let sides = |n: usize| (0..n).map(|k| inward(k, n, 1.0)).collect();
        TargetPoints {
            col_inward: sides(field.width()),
            row_inward: sides(field.height()),
            field,
            void,
            lift: SurfaceLift::new(field, [field.min_sample(), field.max_sample()]),
            target_height: params.target_height,
            radius: params.radius,
            xs,
            ys,
        }
    }

    /// Whether sample (`col`, `row`) is a hole or flagged void.
    #[inline(always)]
    fn is_gap(&self, col: usize, row: usize) -> bool {
        self.field.is_hole(col, row) || self.void.is_some_and(|v| v[col + row * self.field.width()])
    }

    /// Whether a target `x` east and `y` north of the eye lies beyond the radius.
    #[inline(always)]
    fn beyond(&self, x: f64, y: f64) -> bool {
        self.radius.is_some_and(|r| x.hypot(y) > r)
    }

    /// The target point of sample (`col`, `row`) seen from `eye`, or `None` where the sample
    /// is a gap or lies beyond the radius.
    pub(crate) fn point(&self, col: usize, row: usize, eye: DVec3) -> Option<DVec3> {
        if self.is_gap(col, row) {
            return None;
        }
        let target =
            self.lift.origin(self.field, col, row) + DVec3::new(0.0, 0.0, self.target_height);
        (!self.beyond(target.x - eye.x, target.y - eye.y)).then_some(target)
    }

    /// Appends to `x`, `y` and `z` the target points of the samples of row `row` in `cols`
    /// less `eye`: NaN in `z` where [`TargetPoints::point`] gives none.
    #[inline(always)]
    pub(crate) fn run(
        &self,
        row: usize,
        cols: std::ops::Range<usize>,
        eye: DVec3,
        [x, y, z]: [&mut Vec<f64>; 3],
    ) {
        if cols.is_empty() {
            return;
        }
        let field = self.field;
        prefetch_run(field.samples(), field.width(), row + ROWS_AHEAD, cols.clone());
        let (n, start) = (cols.len(), z.len());
        for v in [&mut *x, &mut *y, &mut *z] {
            v.resize(start + n, 0.0);
        }
        let samples = &field.samples()[row * field.width()..][cols.clone()];
        let (xs, sides) = (&self.xs[cols.clone()], &self.col_inward[cols.clone()]);
        let (py, row_side) = (self.ys[row], self.row_inward[row]);
        let (zs, th) = (field.geometry().z_scale, self.target_height);
        let (x, y, z) = (&mut x[start..], &mut y[start..], &mut z[start..]);
        // `SurfaceLift::origin` raised by the target height, in a loop without branches: a
        // side's factor times the lift is the lift, its opposite or 0, as `inward` gives them.
        for i in 0..n {
            let (px, pz) = (xs[i], samples[i] as f64 * zs + 0.0);
            let larger = |a: f64, b: f64| if a > b { a } else { b };
            let lift = self.lift.at_largest(larger(px.abs(), larger(py.abs(), pz.abs())));
            x[i] = (px + sides[i] * lift) - eye.x;
            y[i] = (py + row_side * lift) - eye.y;
            z[i] = ((pz + lift) + th) - eye.z;
        }
        let gaps = field.holes().is_some() || self.void.is_some();
        if gaps || self.radius.is_some() {
            for (i, col) in cols.enumerate() {
                if (gaps && self.is_gap(col, row)) || self.beyond(x[i], y[i]) {
                    z[i] = f64::NAN;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade_map::surface_origin;
    use crate::viewshed::Observer;
    use relief_core::{DVec2, GridGeometry};

    /// A run's points are `point`'s, which are `surface_origin`'s raised by the target height,
    /// bit for bit: on the borders, far from the origin, beside holes, voids and a radius.
    #[test]
    fn runs_and_points_are_surface_origins_raised() {
        let (w, h) = (23, 17);
        let samples = (0..w * h).map(|i| ((i * 37) % 101) as f32 * 0.73 - 20.0).collect();
        let origin = DVec2::new(512_345.25, 4_101_007.5);
        let geometry = GridGeometry { dx: 1.7, dy: 2.3, z_scale: 1.5, origin };
        let holes = (0..w * h).map(|i| i % 29 == 3).collect();
        let field = HeightField::new(w, h, samples, geometry).unwrap().with_holes(holes).unwrap();
        let void: Vec<bool> = (0..w * h).map(|i| i % 31 == 5).collect();
        let eye = DVec3::new(origin.x + 11.1, origin.y + 13.3, 40.0);
        for radius in [None, Some(20.0)] {
            let params = ViewshedParams {
                observers: vec![Observer::new(eye.x, eye.y, 1.0)],
                target_height: 0.37,
                radius,
            };
            let targets = TargetPoints::new(&field, Some(&void), &params);
            for row in 0..h {
                let (mut x, mut y, mut z) = (Vec::new(), Vec::new(), Vec::new());
                targets.run(row, 2..w, eye, [&mut x, &mut y, &mut z]);
                for col in 0..w {
                    let index = col + row * w;
                    let wanted = !field.is_hole(col, row) && !void[index];
                    let expected = wanted
                        .then(|| surface_origin(&field, col, row) + DVec3::new(0.0, 0.0, 0.37))
                        .filter(|t| radius.is_none_or(|r| (t.x - eye.x).hypot(t.y - eye.y) <= r));
                    assert_eq!(targets.point(col, row, eye), expected, "({col}, {row})");
                    if col < 2 {
                        continue;
                    }
                    let i = col - 2;
                    match expected {
                        Some(t) => {
                            let got = [x[i], y[i], z[i]].map(f64::to_bits);
                            let want = [t.x - eye.x, t.y - eye.y, t.z - eye.z].map(f64::to_bits);
                            assert_eq!(got, want, "run at ({col}, {row})");
                        }
                        None => assert!(z[i].is_nan(), "({col}, {row}) is not a target"),
                    }
                }
            }
        }
    }
}
