//! The exact horizon along one compass direction from one sample: a march along the line
//! through the cells of the `triangles` surface that skips, with a [`CellPyramid`], every block
//! of cells too low to raise the horizon found so far.

use super::cell_pyramid::CellPyramid;

/// `x` rounded down, without a call into the maths library.
#[inline(always)]
fn floor(x: f64) -> isize {
    let truncated = x as isize;
    truncated - isize::from((truncated as f64) > x)
}

/// The nearest a hint may lie, in cells: nearer, it would be the sample's own point.
const HINT_NEAREST: f64 = 1e-6;

/// How near a line's end in a cell must come to a corner, in cells, to pass through it.
const VERTEX_TOLERANCE: f64 = 1e-9;

/// Mean radius of the earth in metres (IUGG).
pub(crate) const EARTH_RADIUS: f64 = 6_371_008.8;

/// A height field's `triangles` surface as the march reads it: its samples times a sign (the
/// terrain itself, or upside down for negative openness), in world units, with the split
/// diagonal of each cell chosen from the samples as they are (so both signs share one
/// triangulation).
pub(crate) struct MarchTerrain<'a> {
    /// The samples, row-major, row 0 south.
    pub samples: &'a [f32],
    /// Samples per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// +1, or -1 for the terrain upside down.
    pub sign: f64,
    /// World metres per sample unit.
    pub z_scale: f64,
    /// World metres between samples along x and y.
    pub dx: f64,
    /// See `dx`.
    pub dy: f64,
    /// Maxima of the signed samples over blocks of cells.
    pub pyramid: CellPyramid,
    /// The holes of the height field, if any.
    pub holes: Option<&'a [bool]>,
    /// With holes, which samples are points of the surface (not a hole, and a corner of a
    /// cell without holes); `None` without holes.
    pub on_surface: Option<Vec<bool>>,
}

/// The four corners of a cell in signed world heights, and its split.
pub(crate) struct Corners {
    pub z00: f64,
    pub z10: f64,
    pub z01: f64,
    pub z11: f64,
    /// Split along (0,0)-(1,1), else along (1,0)-(0,1).
    pub main_diagonal: bool,
}

impl Corners {
    /// The surface's height at local coordinates (`s`, `q`) in `[0, 1]^2`.
    #[inline(always)]
    pub(crate) fn height_at(&self, s: f64, q: f64) -> f64 {
        let Corners { z00, z10, z01, z11, main_diagonal } = *self;
        if main_diagonal {
            if s >= q {
                z00 + s * (z10 - z00) + q * (z11 - z10)
            } else {
                z00 + q * (z01 - z00) + s * (z11 - z01)
            }
        } else if s + q <= 1.0 {
            z00 + s * (z10 - z00) + q * (z01 - z00)
        } else {
            z11 + (1.0 - s) * (z01 - z11) + (1.0 - q) * (z10 - z11)
        }
    }

    /// Where a point at local (`s`, `q`) lies with respect to the split diagonal: the sign
    /// changes where a line crosses it.
    #[inline(always)]
    fn side(&self, s: f64, q: f64) -> f64 {
        if self.main_diagonal {
            s - q
        } else {
            s + q - 1.0
        }
    }
}

impl MarchTerrain<'_> {
    /// Whether cell (`c`, `r`) has a surface (no corner is a hole).
    #[inline(always)]
    fn has_surface(&self, c: usize, r: usize) -> bool {
        match &self.on_surface {
            None => true,
            Some(_) => self.cell_is_whole(c, r),
        }
    }

    /// Whether no corner of cell (`c`, `r`) is a hole (with holes).
    pub(crate) fn cell_is_whole(&self, c: usize, r: usize) -> bool {
        let (w, k) = (self.width, c + r * self.width);
        self.holes_at(k) + self.holes_at(k + 1) + self.holes_at(k + w) + self.holes_at(k + w + 1)
            == 0
    }

    fn holes_at(&self, k: usize) -> u8 {
        self.holes.is_some_and(|h| h[k]) as u8
    }

    fn corners(&self, c: usize, r: usize) -> Corners {
        let w = self.width;
        let k = c + r * w;
        let (h00, h10, h01, h11) =
            (self.samples[k], self.samples[k + 1], self.samples[k + w], self.samples[k + w + 1]);
        let scale = self.sign * self.z_scale;
        Corners {
            z00: h00 as f64 * scale,
            z10: h10 as f64 * scale,
            z01: h01 as f64 * scale,
            z11: h11 as f64 * scale,
            main_diagonal: h00 + h11 <= h10 + h01,
        }
    }
}

/// The samples along x and y per horizontal metre towards `azimuth_deg` (clockwise from north)
/// on a grid of spacings `dx`, `dy`: exact on the axes, so that lines due north, east, south
/// or west run along the grid's lines.
pub(crate) fn unit_steps(azimuth_deg: f64, dx: f64, dy: f64) -> (f64, f64) {
    let (sin, cos) = match azimuth_deg.rem_euclid(360.0) {
        0.0 => (0.0, 1.0),
        90.0 => (1.0, 0.0),
        180.0 => (0.0, -1.0),
        270.0 => (-1.0, 0.0),
        other => other.to_radians().sin_cos(),
    };
    (sin / dx, cos / dy)
}

/// The horizon from one sample in one direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Horizon {
    /// Elevation angle in radians.
    pub angle: f64,
    /// Horizontal distance in metres to the point that sets it (NaN if none).
    pub distance: f64,
}

/// One compass direction's march: the line's step per metre in samples, and the limits.
pub(crate) struct DirectionMarch<'a> {
    terrain: &'a MarchTerrain<'a>,
    /// Samples along x and y per horizontal metre.
    a: f64,
    b: f64,
    inv_a: f64,
    inv_b: f64,
    /// The observer's height above each sample, metres.
    observer_height: f64,
    /// The march stops at this horizontal distance, metres.
    t_end: f64,
    /// The apparent drop of the terrain per square metre of distance (curvature less
    /// refraction), 0 without.
    drop: f64,
}

impl<'a> DirectionMarch<'a> {
    /// The march towards `azimuth_deg` (clockwise from north) over `terrain`.
    pub(crate) fn new(
        terrain: &'a MarchTerrain<'a>,
        azimuth_deg: f64,
        observer_height: f64,
        radius: Option<f64>,
        refraction: Option<f64>,
    ) -> Self {
        let (a, b) = unit_steps(azimuth_deg, terrain.dx, terrain.dy);
        DirectionMarch {
            terrain,
            a,
            b,
            inv_a: 1.0 / a,
            inv_b: 1.0 / b,
            observer_height,
            t_end: radius.unwrap_or(f64::INFINITY),
            drop: refraction.map_or(0.0, |k| (1.0 - k) / (2.0 * EARTH_RADIUS)),
        }
    }

    /// The horizon seen from sample (`col`, `row`) raised by the observer's height: the
    /// steepest slope up (or least steep down) to any point of the surface along the direction,
    /// to the edge of the data or the radius, as an elevation angle in radians (0 where no
    /// surface lies ahead), and the horizontal distance to the point that sets it.
    ///
    /// `hints` are distances along the line where the horizon may lie (where a neighbouring
    /// sample's is): the surface's slope there is a lower bound that lets the march skip more
    /// from the start. They change how fast the answer is found, never the answer.
    ///
    /// With `at_least_level`, the horizon is wanted only where it is above the horizontal:
    /// the answer is `max(angle, 0)`, and the march skips everything below the observer.
    pub(crate) fn horizon(
        &self,
        col: usize,
        row: usize,
        hints: &[f64],
        at_least_level: bool,
    ) -> Horizon {
        let terrain = self.terrain;
        let (cells_x, cells_y) = (terrain.width as isize - 1, terrain.height as isize - 1);
        let none = Horizon { angle: 0.0, distance: f64::NAN };
        if cells_x < 1 || cells_y < 1 {
            return none;
        }
        let (u0, v0) = (col as f64, row as f64);
        let z0 = terrain.samples[col + row * terrain.width] as f64 * terrain.sign * terrain.z_scale
            + self.observer_height;
        let lowest = if at_least_level { 0.0 } else { f64::NEG_INFINITY };
        let mut best = lowest;
        let mut distance = f64::NAN;
        let nearest = HINT_NEAREST * terrain.dx.min(terrain.dy);
        for &t in hints {
            if t >= nearest && t <= self.t_end {
                if let Some(z) = self.surface_at(u0 + self.a * t, v0 + self.b * t) {
                    let slope = (z - z0) / t - self.drop * t;
                    if slope > best {
                        (best, distance) = (slope, t);
                    }
                }
            }
        }
        // The cell the line starts in; along a grid line, either neighbour (the profile on
        // their shared edge is the same).
        let start = |p: usize, step: f64, cells: isize| -> isize {
            let p = p as isize;
            if step > 0.0 || (step == 0.0 && p < cells) {
                p
            } else {
                p - 1
            }
        };
        let (mut c, mut r) = (start(col, self.a, cells_x), start(row, self.b, cells_y));
        let pyramid = &terrain.pyramid;
        let top = pyramid.top();
        let mut t = 0.0f64;
        let mut level = 0usize;
        while (0..cells_x).contains(&c) && (0..cells_y).contains(&r) && t < self.t_end {
            let (nx, ny) = ((c >> level) as usize, (r >> level) as usize);
            let size = 1isize << level;
            let (u_lo, u_hi) = (nx as isize * size, ((nx as isize + 1) * size).min(cells_x));
            let (v_lo, v_hi) = (ny as isize * size, ((ny as isize + 1) * size).min(cells_y));
            let t_u = if self.a > 0.0 {
                (u_hi as f64 - u0) * self.inv_a
            } else if self.a < 0.0 {
                (u_lo as f64 - u0) * self.inv_a
            } else {
                f64::INFINITY
            };
            let t_v = if self.b > 0.0 {
                (v_hi as f64 - v0) * self.inv_b
            } else if self.b < 0.0 {
                (v_lo as f64 - v0) * self.inv_b
            } else {
                f64::INFINITY
            };
            let t_exit = t_u.min(t_v);
            // The node cannot raise the horizon if its highest point, at the nearest distance
            // (or the farthest, below the observer), is no steeper than the best so far.
            let highest = pyramid.get(level, nx, ny) as f64 * terrain.z_scale - z0;
            let lowest_line = best + self.drop * t;
            let skip = if highest >= 0.0 {
                highest <= lowest_line * t
            } else {
                highest <= lowest_line * t_exit
            };
            if !skip {
                if level > 0 {
                    level -= 1;
                    continue;
                }
                let end = t_exit.min(self.t_end);
                if let Some(at) = self.cell(c as usize, r as usize, t, end, u0, v0, z0, &mut best) {
                    distance = at;
                }
            }
            if t_exit >= self.t_end {
                break;
            }
            // Step into the next node: across the face the line leaves by, and along the
            // other axis to where the line is then (inside the node, never backwards).
            let along = |p0: f64, step: f64, lo: isize, hi: isize, now: isize| -> isize {
                let p = floor(p0 + step * t_exit).clamp(lo, hi - 1);
                if step > 0.0 {
                    p.max(now)
                } else if step < 0.0 {
                    p.min(now)
                } else {
                    now
                }
            };
            let (next_c, next_r) = if t_u < t_v {
                let next_c = if self.a > 0.0 { u_hi } else { u_lo - 1 };
                (next_c, along(v0, self.b, v_lo, v_hi, r))
            } else if t_v < t_u {
                let next_r = if self.b > 0.0 { v_hi } else { v_lo - 1 };
                (along(u0, self.a, u_lo, u_hi, c), next_r)
            } else {
                (
                    if self.a > 0.0 { u_hi } else { u_lo - 1 },
                    if self.b > 0.0 { v_hi } else { v_lo - 1 },
                )
            };
            // Up to the largest node the line has just entered.
            while level < top
                && ((next_c >> (level + 1)) != (c >> (level + 1))
                    || (next_r >> (level + 1)) != (r >> (level + 1)))
            {
                level += 1;
            }
            c = next_c;
            r = next_r;
            t = t.max(t_exit);
        }
        if best == f64::NEG_INFINITY || distance.is_nan() {
            none
        } else {
            Horizon { angle: best.atan(), distance }
        }
    }

    /// The surface's height at grid point (`u`, `v`), if a whole cell holds it.
    fn surface_at(&self, u: f64, v: f64) -> Option<f64> {
        let terrain = self.terrain;
        let (cells_x, cells_y) = (terrain.width - 1, terrain.height - 1);
        if !(u >= 0.0 && v >= 0.0 && u <= cells_x as f64 && v <= cells_y as f64) {
            return None;
        }
        let (c, r) = ((u as usize).min(cells_x - 1), (v as usize).min(cells_y - 1));
        if !terrain.has_surface(c, r) {
            return None;
        }
        Some(terrain.corners(c, r).height_at(u - c as f64, v - r as f64))
    }

    /// A cell with a hole corner has no surface of its own, but where a line enters or leaves
    /// it on an edge of a whole neighbouring cell, or at a corner of one, it meets the surface
    /// there (a line along a grid line, or through a corner, beside the holes; or the end of
    /// the radius on such an edge).
    #[cold]
    fn hole_cell(
        &self,
        c: usize,
        r: usize,
        ends: [(f64, f64, f64); 2],
        z0: f64,
        best: &mut f64,
    ) -> Option<f64> {
        let terrain = self.terrain;
        let on_surface = terrain.on_surface.as_ref()?;
        let mut raised = None;
        let (w, h) = (terrain.width, terrain.height);
        let side = |x: f64| -> Option<usize> {
            if x.abs() < VERTEX_TOLERANCE {
                Some(0)
            } else if (x - 1.0).abs() < VERTEX_TOLERANCE {
                Some(1)
            } else {
                None
            }
        };
        let height = |k: usize| terrain.samples[k] as f64 * terrain.sign * terrain.z_scale;
        // Whether the cell across from (c, r) by (dc, dr) exists and is whole.
        let whole = |dc: isize, dr: isize| -> bool {
            let (nc, nr) = (c as isize + dc, r as isize + dr);
            nc >= 0
                && nr >= 0
                && (nc as usize) + 1 < w
                && (nr as usize) + 1 < h
                && terrain.cell_is_whole(nc as usize, nr as usize)
        };
        for (t, s, q) in ends {
            if t <= 0.0 {
                continue;
            }
            let g = match (side(s), side(q)) {
                (Some(dc), Some(dr)) => {
                    let k = c + dc + (r + dr) * w;
                    on_surface[k].then(|| height(k))
                }
                (Some(dc), None) => whole(2 * dc as isize - 1, 0).then(|| {
                    let k = c + dc + r * w;
                    height(k) + q * (height(k + w) - height(k))
                }),
                (None, Some(dr)) => whole(0, 2 * dr as isize - 1).then(|| {
                    let k = c + (r + dr) * w;
                    height(k) + s * (height(k + 1) - height(k))
                }),
                (None, None) => None,
            };
            if let Some(g) = g {
                let slope = (g - z0) / t - self.drop * t;
                if slope > *best {
                    *best = slope;
                    raised = Some(t);
                }
            }
        }
        raised
    }

    /// Raises `best` to the steepest slope of the surface of cell (`c`, `r`) between
    /// distances `t_in` and `t_out` along the line (where it enters and leaves the cell): the
    /// profile is linear but where it crosses the split diagonal, so the steepest slope is at
    /// an end or at the crossing (or, with the earth's curvature, where the slope's derivative
    /// vanishes inside a linear piece).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn cell(
        &self,
        c: usize,
        r: usize,
        t_in: f64,
        t_out: f64,
        u0: f64,
        v0: f64,
        z0: f64,
        best: &mut f64,
    ) -> Option<f64> {
        let local = |t: f64| -> (f64, f64) {
            let s = (u0 + self.a * t - c as f64).clamp(0.0, 1.0);
            let q = (v0 + self.b * t - r as f64).clamp(0.0, 1.0);
            (s, q)
        };
        let (s_in, q_in) = local(t_in);
        let (s_out, q_out) = local(t_out);
        if !self.terrain.has_surface(c, r) {
            return self.hole_cell(c, r, [(t_in, s_in, q_in), (t_out, s_out, q_out)], z0, best);
        }
        let corners = self.terrain.corners(c, r);
        let mut raised = None;
        let g_in = corners.height_at(s_in, q_in) - z0;
        let g_out = corners.height_at(s_out, q_out) - z0;
        let mut points = [(t_in, g_in), (t_out, g_out), (t_out, g_out)];
        let (side_in, side_out) = (corners.side(s_in, q_in), corners.side(s_out, q_out));
        if (side_in < 0.0 && side_out > 0.0) || (side_in > 0.0 && side_out < 0.0) {
            let f = side_in / (side_in - side_out);
            let t_cross = t_in + f * (t_out - t_in);
            let (s, q) = (s_in + f * (s_out - s_in), q_in + f * (q_out - q_in));
            points[1] = (t_cross, corners.height_at(s, q) - z0);
        }
        for &(t, g) in &points {
            if t > 0.0 {
                let slope = g / t - self.drop * t;
                if slope > *best {
                    *best = slope;
                    raised = Some(t);
                }
            }
        }
        if self.drop > 0.0 {
            // With the drop, the slope g/t - drop t of a linear piece g = A + B t peaks inside it
            // at t = sqrt(-A / drop) when A < 0.
            for pair in points.windows(2) {
                let ((t1, g1), (t2, g2)) = (pair[0], pair[1]);
                if t2 <= t1 {
                    continue;
                }
                let rate = (g2 - g1) / (t2 - t1);
                let at_zero = g1 - rate * t1;
                if at_zero < 0.0 {
                    let t_peak = (-at_zero / self.drop).sqrt();
                    if t_peak > t1 && t_peak < t2 {
                        let slope = rate - 2.0 * (-at_zero * self.drop).sqrt();
                        if slope > *best {
                            *best = slope;
                            raised = Some(t_peak);
                        }
                    }
                }
            }
        }
        raised
    }
}
