//! The points where one direction's line crosses the edges and split diagonals of the
//! `triangles` surface, found once for the line from a sample and the same for every sample
//! (translated): the horizon of a sample is the steepest slope to one of them.
//!
//! The line runs in a frame where it advances at least as fast along x as along y: one
//! column per *step*. Step `k` holds the points past column `k - 1` up to column `k`: the
//! crossing of column `k`'s vertical edge, of a row's horizontal edge between the two, and
//! of the split diagonal of each cell in between (which diagonal is the split depends on the
//! cell's samples, so both candidates are kept and each sample's cell chooses).

/// A point on the edge from sample `a` to sample `b` (offsets from the line's sample in a
/// padded grid), the fraction `w` of the way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct EdgePoint {
    pub a: isize,
    pub b: isize,
    pub w: f32,
    /// `w` in f64, for the exact slope.
    pub w64: f64,
    pub coefficients: Coefficients,
}

impl EdgePoint {
    /// No point (its slope is -infinity).
    const NONE: EdgePoint =
        EdgePoint { a: 0, b: 0, w: 0.0, w64: 0.0, coefficients: Coefficients::NONE };
}

/// A point on the split diagonal of the cell whose corner (0, 0) is `corner`: at `main`
/// along the diagonal from (0, 0) to (1, 1) if that is the split, at `anti` along the one
/// from (0, 1) to (1, 0) if that is. A diagonal the line does not cross has
/// [`Coefficients::NONE`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DiagonalPoint {
    pub corner: isize,
    pub main: f64,
    pub main_coefficients: Coefficients,
    pub anti: f64,
    pub anti_coefficients: Coefficients,
}

impl DiagonalPoint {
    /// No point.
    const NONE: DiagonalPoint = DiagonalPoint {
        corner: 0,
        main: 0.0,
        main_coefficients: Coefficients::NONE,
        anti: 0.0,
        anti_coefficients: Coefficients::NONE,
    };
}

/// The end of a line cut at a radius: inside the cell whose corner (0, 0) is `corner`, at
/// local (`s`, `q`), in step `step`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RadiusEnd {
    pub step: usize,
    pub corner: isize,
    pub s: f64,
    pub q: f64,
    pub coefficients: Coefficients,
}

/// What turns a point's height above the sample into the slope from the observer at its
/// distance `t`: `slope = rise * scale - lift`, with `scale = z_scale / t` and
/// `lift = observer_height / t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Coefficients {
    pub scale: f32,
    pub lift: f32,
    /// A bound on how far above the exact slope the f32 slope of a point at this distance
    /// may lie, but for [`F32_ERROR`] times its own magnitude: [`F32_ERROR`] times the
    /// largest magnitude of its other terms (heights differing by at most the frame's range).
    pub error: f32,
    /// The same in f64, for the exact slope.
    pub scale64: f64,
    pub lift64: f64,
}

impl Coefficients {
    /// The coefficients of a point that is not there: every slope to it is -infinity.
    pub const NONE: Coefficients = Coefficients {
        scale: 0.0,
        lift: f32::INFINITY,
        error: 0.0,
        scale64: 0.0,
        lift64: f64::INFINITY,
    };
}

/// A bound on the error of a slope computed in f32 by the lanes, relative to the sum of the
/// magnitudes it is made of (each of the six roundings costs at most half an f32 epsilon
/// of those; twice that for safety).
pub(crate) const F32_ERROR: f32 = 6.0 * f32::EPSILON;

/// The points of one step: the crossings of column `k` and of a row (each may be
/// [`EdgePoint::NONE`]), and of the split diagonals of the (up to two) cells between.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Step {
    pub edges: [EdgePoint; 2],
    pub diagonals: [DiagonalPoint; 2],
    /// Where the footprint of the step's points starts, from the line's sample: the lowest
    /// of the (up to three) rows they read, at the first column of the lanes' (see
    /// `LaneFrame::footprints`).
    pub footprint: isize,
    /// The distance in metres at which the step ends.
    pub distance: f32,
}

/// A direction's line in the lanes' frame, and its points step by step.
#[derive(Debug, Clone)]
pub(crate) struct Stencil {
    /// +1 if the line advances towards growing x, -1 otherwise.
    pub step_x: isize,
    /// Rows the line advances per step (at most 1 in magnitude).
    pub rows_per_step: f64,
    /// The steps from 1; `steps[0]` has no points and ends at distance 0.
    pub steps: Vec<Step>,
    /// Where a radius cuts the line.
    pub end: Option<RadiusEnd>,
}

/// How near to a grid line a crossing must come, in cells, to be on it.
const ON_GRID: f64 = 1e-9;

/// A direction's line in the lanes' frame, from which any step's points follow: the same
/// arithmetic whether the steps are kept in a [`Stencil`] or made one at a time (the far field
/// of a window, `far_field.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StencilLine {
    /// +1 if the line advances towards growing x, -1 otherwise.
    pub step_x: isize,
    /// Rows the line advances per step (at most 1 in magnitude).
    pub rows_per_step: f64,
    /// Horizontal metres per step.
    pub metres_per_step: f64,
    /// Samples a row of the grid the offsets index (a column where `column_major`).
    pub stride: usize,
    /// Whether the grid holds its columns one after the other (the lanes' frame) rather than
    /// its rows (the far field's).
    pub column_major: bool,
    /// Where a radius cuts the line, in steps.
    pub radius_steps: Option<f64>,
    pub z_scale: f64,
    pub observer_height: f64,
    /// The highest sample of the grid minus its lowest (for the f32 slopes' error bound).
    pub height_range: f64,
}

impl StencilLine {
    /// The coefficients of a point at `kappa` steps.
    fn coefficients(&self, kappa: f64) -> Coefficients {
        let t = kappa * self.metres_per_step;
        let (scale64, lift64) = (self.z_scale / t, self.observer_height / t);
        let others = self.height_range * scale64.abs() + lift64.abs();
        let error = (others * f64::from(F32_ERROR) * (1.0 + 1e-6)) as f32;
        Coefficients { scale: scale64 as f32, lift: lift64 as f32, error, scale64, lift64 }
    }

    /// The points of step `k` (from 1), and the line's end at the radius if it lies in it.
    pub(crate) fn step(&self, k: usize) -> (Step, Option<RadiusEnd>) {
        let (m, sx, step_x) = (self.rows_per_step, self.step_x as f64, self.step_x);
        let stride = self.stride as isize;
        let column_major = self.column_major;
        let at = |col: isize, row: isize| {
            if column_major {
                col * stride + row
            } else {
                col + row * stride
            }
        };
        let snap = |v: f64| -> f64 {
            let r = v.round();
            if (v - r).abs() < ON_GRID {
                r
            } else {
                v
            }
        };
        let (k0, k1) = ((k - 1) as f64, k as f64);
        let end = self.radius_steps.map_or(k1, |s| s.min(k1));
        let mut step = Step {
            edges: [EdgePoint::NONE; 2],
            diagonals: [DiagonalPoint::NONE; 2],
            footprint: 0,
            distance: 0.0,
        };
        let mut end_point = None;
        // A row crossing strictly inside (there is at most one, |m| <= 1).
        let mut breaks = [k0, 0.0, 0.0];
        let mut pieces = 1;
        if m != 0.0 {
            let (y0, y1) = (m * k0, m * end);
            let (lo, hi) = (snap(y0.min(y1)), snap(y0.max(y1)));
            let j = lo.floor() + 1.0;
            if j < hi {
                let kappa = j / m;
                if kappa > k0 && kappa < end {
                    let x = sx * kappa;
                    let col = x.floor() as isize;
                    step.edges[1] = EdgePoint {
                        a: at(col, j as isize),
                        b: at(col + 1, j as isize),
                        w: (x - x.floor()) as f32,
                        w64: x - x.floor(),
                        coefficients: self.coefficients(kappa),
                    };
                    breaks[pieces] = kappa;
                    pieces += 1;
                }
            }
        }
        breaks[pieces] = end;
        // Each piece between breakpoints lies in one cell: its split diagonal's crossing.
        for (piece, pair) in breaks[..=pieces].windows(2).enumerate() {
            let (a, b) = (pair[0], pair[1]);
            if b - a < ON_GRID {
                continue;
            }
            let mid = 0.5 * (a + b);
            let (xm, ym) = (sx * mid, m * mid);
            // Along a grid line the piece lies on an edge: no diagonal to cross, and the
            // cell above it stands for both (their surfaces agree on the edge).
            let on_grid_line = (ym - ym.round()).abs() < ON_GRID;
            let (cx, cy) = (xm.floor(), if on_grid_line { ym.round() } else { ym.floor() });
            let corner = at(cx as isize, cy as isize);
            let inside =
                |kappa: &f64| !on_grid_line && *kappa > a + ON_GRID && *kappa < b - ON_GRID;
            let candidate = |kappa: Option<f64>| {
                kappa.filter(inside).map_or((0.0, Coefficients::NONE), |kappa| {
                    (sx * kappa - cx, self.coefficients(kappa))
                })
            };
            let (main, main_coefficients) = candidate((sx != m).then(|| (cx - cy) / (sx - m)));
            let (anti, anti_coefficients) =
                candidate((sx != -m).then(|| (1.0 + cx + cy) / (sx + m)));
            step.diagonals[piece] =
                DiagonalPoint { corner, main, main_coefficients, anti, anti_coefficients };
            if b == end && end < k1 {
                end_point = Some(RadiusEnd {
                    step: k,
                    corner,
                    s: (sx * end - cx).clamp(0.0, 1.0),
                    q: (m * end - cy).clamp(0.0, 1.0),
                    coefficients: self.coefficients(end),
                });
            }
        }
        if end == k1 {
            // The vertical edge of column k.
            let y = snap(m * k1);
            let (row, col) = (y.floor() as isize, step_x * k as isize);
            step.edges[0] = EdgePoint {
                a: at(col, row),
                b: at(col, row + 1),
                w: (y - y.floor()) as f32,
                w64: y - y.floor(),
                coefficients: self.coefficients(k1),
            };
        }
        let low_row = snap(m * k0).min(snap(m * k1)).floor() as isize;
        let first_col = if step_x > 0 { k as isize - 1 } else { -(k as isize) };
        step.footprint = at(first_col, low_row);
        // Points that are not there read the footprint's samples (which a grid holding the
        // step's points holds), to no effect: their slopes are -infinity.
        for e in step.edges.iter_mut().filter(|e| e.coefficients == Coefficients::NONE) {
            (e.a, e.b) = (step.footprint, step.footprint);
        }
        let none = |d: &&mut DiagonalPoint| {
            d.main_coefficients == Coefficients::NONE && d.anti_coefficients == Coefficients::NONE
        };
        for d in step.diagonals.iter_mut().filter(none) {
            d.corner = step.footprint;
        }
        step.distance = (k1 * self.metres_per_step) as f32;
        (step, end_point)
    }

    /// The steps that reach the radius (the last holds the line's end at it), at most
    /// `steps`.
    fn last_step(&self, steps: usize) -> usize {
        self.radius_steps.map_or(steps, |s| (s.ceil() as usize).clamp(1, steps.max(1)))
    }
}

impl Stencil {
    /// The stencil of `line` for `steps` steps or to its radius, whichever is shorter.
    pub(crate) fn new(line: &StencilLine, steps: usize) -> Stencil {
        debug_assert!(line.rows_per_step.abs() <= 1.0 && (line.step_x == 1 || line.step_x == -1));
        let last = line.last_step(steps);
        let empty = Step {
            edges: [EdgePoint::NONE; 2],
            diagonals: [DiagonalPoint::NONE; 2],
            footprint: 0,
            distance: 0.0,
        };
        let mut all = Vec::with_capacity(last + 1);
        all.push(empty);
        let mut end_point = None;
        for k in 1..=last {
            let (step, end) = line.step(k);
            end_point = end_point.or(end);
            all.push(step);
        }
        Stencil {
            step_x: line.step_x,
            rows_per_step: line.rows_per_step,
            steps: all,
            end: end_point,
        }
    }

    /// The number of steps the stencil holds.
    pub(crate) fn len(&self) -> usize {
        self.steps.len() - 1
    }
}
