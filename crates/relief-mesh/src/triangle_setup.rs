//! One triangle seen by one camera: its homogeneous screen projection, the edge functions that
//! decide which pixel centres it covers (watertight, top-left rule), and the exact ray-plane
//! distance of each covered pixel.
//!
//! Coverage is decided in 2D homogeneous coordinates (Olano & Greer 1997): a vertex at camera
//! coordinates (x, y, z) becomes `V = (W/2 z + f x, H/2 z - f y, z)` (pinhole; `f` the focal
//! length in pixels) or `(W/2 + f x, H/2 - f y, 1)` (orthographic), and pixel centre
//! `P = (i + 0.5, j + 0.5, 1)` is seen through the triangle in front of the eye exactly when the
//! three edge functions `E_k . P`, with `E_0 = V_1 x V_2`, `E_1 = V_2 x V_0`, `E_2 = V_0 x V_1`,
//! all have the sign of `det(V_0, V_1, V_2)` (a camera sampling its pixels off their centres,
//! [`Camera::pixel_offset`], moves `V` by the offset the other way). No triangle is clipped,
//! so triangles reaching behind the eye (low cameras over terrain) are covered exactly.
//!
//! Watertightness: an edge function depends on its edge's two vertices only, and IEEE
//! arithmetic is symmetric under negation, so the two triangles sharing an edge evaluate
//! exactly opposite values at every pixel (`fl(-a * x + -b) = -fl(a * x + b)`): a pixel centre
//! is strictly inside one of them, or exactly on the edge, where the top-left rule (the edge's
//! normalized `(e.x, e.y)` is `e.x > 0 || (e.x == 0 && e.y > 0)`) gives it to exactly one.

use relief_core::{Camera, DVec3, Projection};

/// The camera seen as a projection to pixel coordinates, with the per-column and per-row ray
/// parts of every pixel.
#[derive(Debug, Clone)]
pub(crate) struct ScreenProjection {
    eye: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    /// Pixels per unit of screen coordinate: `H / (2 s)`.
    focal: f64,
    half_width: f64,
    half_height: f64,
    pub(crate) perspective: bool,
    pub(crate) width: usize,
    pub(crate) height: usize,
    /// `sx` of every column ([`Camera::screen_x`]), then [`BLOCK_SIDE`] zeros (a block of
    /// pixels may reach past the image; its lanes there are never written).
    pub(crate) sx: Vec<f64>,
    /// `sy` of every row ([`Camera::screen_y`]), then [`BLOCK_SIDE`] zeros.
    pub(crate) sy: Vec<f64>,
}

impl ScreenProjection {
    pub(crate) fn new(camera: &Camera) -> Self {
        let (width, height) = (camera.width() as usize, camera.height() as usize);
        ScreenProjection {
            eye: camera.eye(),
            right: camera.right(),
            up: camera.image_up(),
            forward: camera.forward(),
            focal: height as f64 / (2.0 * camera.half_height()),
            // A camera sampling its pixels off their centres moves the image the other way.
            half_width: width as f64 / 2.0 - camera.pixel_offset()[0],
            half_height: height as f64 / 2.0 - camera.pixel_offset()[1],
            perspective: matches!(camera.projection(), Projection::Perspective { .. }),
            width,
            height,
            sx: (0..width as u32).map(|i| camera.screen_x(i)).chain([0.0; BLOCK_SIDE]).collect(),
            sy: (0..height as u32).map(|j| camera.screen_y(j)).chain([0.0; BLOCK_SIDE]).collect(),
        }
    }

    /// Homogeneous pixel coordinates `(X, Y, z)` of a world point, `z` its depth along the
    /// view direction (the homogeneous weight of a pinhole; an orthographic weight is 1).
    #[inline]
    pub(crate) fn project(&self, p: DVec3) -> [f64; 3] {
        let v = p - self.eye;
        let (x, y, z) = (v.dot(self.right), v.dot(self.up), v.dot(self.forward));
        if self.perspective {
            [self.half_width * z + self.focal * x, self.half_height * z - self.focal * y, z]
        } else {
            [self.half_width + self.focal * x, self.half_height - self.focal * y, z]
        }
    }

    /// The screen coordinates of the `width x height` pixels from `origin` on, to turn depth
    /// keys into distances and back there.
    pub(crate) fn tile_rays(
        &self,
        [x, y]: [usize; 2],
        width: usize,
        height: usize,
    ) -> TileRays<'_> {
        TileRays {
            sx: &self.sx[x..x + width],
            sy: &self.sy[y..y + height],
            perspective: self.perspective,
        }
    }

    /// Which of the view's bounding half-spaces the projected point `v` lies outside of, one
    /// bit each: left of the first pixel column, right of the last, above the first row, below
    /// the last (each with a pixel of margin), and behind the eye. A triangle whose three
    /// corners share a bit is invisible: the half-spaces are linear in homogeneous coordinates,
    /// so its every point lies outside too.
    #[inline]
    pub(crate) fn outcode(&self, v: [f64; 3]) -> u8 {
        let (w, z) = if self.perspective { (v[2], v[2]) } else { (1.0, v[2]) };
        let (width, height) = (self.width as f64, self.height as f64);
        (v[0] < -w) as u8
            | ((v[0] > (width + 1.0) * w) as u8) << 1
            | ((v[1] < -w) as u8) << 2
            | ((v[1] > (height + 1.0) * w) as u8) << 3
            | ((z <= 0.0) as u8) << 4
    }

    /// The pixels `[x0, x1] x [y0, y1]` (inclusive) whose centres the projected triangle may
    /// cover, or `None` when it covers none (behind the eye, off screen, or between centres).
    ///
    /// A triangle reaching behind a pinhole is bounded by its part at depth at least
    /// `1e-9` times its farthest vertex's: hits closer to the eye than that are not drawn.
    pub(crate) fn pixel_bounds(&self, v: &[[f64; 3]; 3]) -> Option<[usize; 4]> {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut add = |x: f64, y: f64| {
            lo = [lo[0].min(x), lo[1].min(y)];
            hi = [hi[0].max(x), hi[1].max(y)];
        };
        let z_max = v[0][2].max(v[1][2]).max(v[2][2]);
        if z_max.is_nan() || z_max <= 0.0 {
            return None;
        }
        if !self.perspective {
            v.iter().for_each(|p| add(p[0], p[1]));
        } else {
            let near = z_max * 1e-9;
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                if a[2] >= near {
                    add(a[0] / a[2], a[1] / a[2]);
                }
                if (a[2] >= near) != (b[2] >= near) {
                    // The edge crosses the near depth: add the crossing point.
                    let s = (a[2] - near) / (a[2] - b[2]);
                    let c = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
                    add(c[0] / near, c[1] / near);
                }
            }
        }
        // Pixel i's centre is i + 0.5; widen a little for the rounding of the projection.
        let (w, h) = (self.width as f64, self.height as f64);
        let first = |l: f64, n: f64| ceil((l - 0.5 - 1e-7 * (1.0 + l.abs())).clamp(-1.0, n));
        let last = |h: f64, n: f64| floor((h - 0.5 + 1e-7 * (1.0 + h.abs())).clamp(-1.0, n));
        let x0 = first(lo[0], w).max(0.0);
        let y0 = first(lo[1], h).max(0.0);
        let x1 = last(hi[0], w).min(w - 1.0);
        let y1 = last(hi[1], h).min(h - 1.0);
        if !(x0 <= x1 && y0 <= y1) {
            return None;
        }
        Some([x0 as usize, y0 as usize, x1 as usize, y1 as usize])
    }
}

/// The screen coordinates of one tile's pixels (see [`ScreenProjection::tile_rays`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct TileRays<'a> {
    sx: &'a [f64],
    sy: &'a [f64],
    perspective: bool,
}

impl TileRays<'_> {
    /// The distance along the tile's pixel (i, j)'s unit ray of the point of depth key `key`
    /// (see [`TriangleSetup::scan`]), rounded to `f32`.
    #[inline(always)]
    pub(crate) fn distance(&self, i: usize, j: usize, key: f64) -> f32 {
        if self.perspective {
            (self.ray_length(i, j) / key) as f32
        } else {
            (-key) as f32
        }
    }

    /// The length of a pinhole's ray `forward + sx right + sy up'` through pixel (i, j).
    #[inline(always)]
    fn ray_length(&self, i: usize, j: usize) -> f64 {
        (1.0 + self.sy[j] * self.sy[j] + self.sx[i] * self.sx[i]).sqrt()
    }

    /// The depth key of the point at `distance` along the tile's pixel (i, j)'s unit ray
    /// (`-inf`, the farthest, for an infinite distance).
    #[inline(always)]
    pub(crate) fn key(&self, i: usize, j: usize, distance: f32) -> f64 {
        if !distance.is_finite() {
            f64::NEG_INFINITY
        } else if self.perspective {
            self.ray_length(i, j) / distance as f64
        } else {
            -(distance as f64)
        }
    }
}

/// Whether the triangle with projected corners `v` faces away from the camera (see
/// [`TriangleSetup::new`]) or is degenerate on screen.
#[inline]
pub(crate) fn is_back_face(projection: &ScreenProjection, v: &[[f64; 3]; 3]) -> bool {
    let w = |k: usize| if projection.perspective { v[k][2] } else { 1.0 };
    let h = |k: usize| [v[k][0], v[k][1], w(k)];
    let e0 = cross(h(1), h(2));
    let det = h(0)[0] * e0[0] + h(0)[1] * e0[1] + h(0)[2] * e0[2];
    det.is_nan() || det >= 0.0
}

/// `x.floor()` for a small finite `x`, without a library call (x86-64 has no rounding
/// instruction before SSE 4.1).
#[inline(always)]
fn floor(x: f64) -> f64 {
    let t = x as i64 as f64;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// `x.ceil()` for a small finite `x` (see [`floor`]).
#[inline(always)]
fn ceil(x: f64) -> f64 {
    let t = x as i64 as f64;
    if t < x {
        t + 1.0
    } else {
        t
    }
}

/// Rectangles narrower than this many pixels are scanned without computing each row's span
/// (three divisions a row cost more than testing the few pixels).
const NARROW: usize = 4;

/// A triangle ready to be scanned: oriented edge functions and its plane in camera terms.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TriangleSetup {
    /// Edge functions `(a, b, c)`, oriented so that covered pixels are positive.
    pub(crate) edges: [[f64; 3]; 3],
    /// Whether a pixel exactly on each edge belongs to this triangle (top-left rule).
    pub(crate) top_left: [bool; 3],
    /// The depth key at a pixel is `key_row + key_up sy + key_across sx` (see
    /// [`TriangleSetup::scan`]).
    pub(crate) key_row: f64,
    pub(crate) key_up: f64,
    pub(crate) key_across: f64,
}

#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

impl TriangleSetup {
    /// Sets up the triangle with projected corners `v` and world corners `p`; `None` when it
    /// is degenerate on screen (zero area, or its plane through a pinhole's eye).
    ///
    /// With `cull_back_faces`, a triangle whose normal `(p1 - p0) x (p2 - p0)` does not face
    /// the camera's rays (counter-clockwise is the front, seen from outside) is `None` too.
    ///
    /// The homogeneous determinant is `f^2 dot(n, p0 - eye)` for a pinhole and
    /// `f^2 dot(n, forward)` for an orthographic camera (the camera's basis right, up',
    /// forward is left-handed and the pixel rows run down), so a front face has a negative
    /// determinant.
    #[inline]
    pub(crate) fn new(
        projection: &ScreenProjection,
        v: &[[f64; 3]; 3],
        p: &[DVec3; 3],
        cull_back_faces: bool,
    ) -> Option<Self> {
        let homogeneous = |k: usize| {
            if projection.perspective {
                v[k]
            } else {
                [v[k][0], v[k][1], 1.0]
            }
        };
        let (h0, h1, h2) = (homogeneous(0), homogeneous(1), homogeneous(2));
        let mut edges = [cross(h1, h2), cross(h2, h0), cross(h0, h1)];
        let det = h0[0] * edges[0][0] + h0[1] * edges[0][1] + h0[2] * edges[0][2];
        if det == 0.0 || !det.is_finite() || (cull_back_faces && det > 0.0) {
            return None;
        }
        if det < 0.0 {
            // Exact: the opposite triangle's edge functions stay exact negations.
            edges = edges.map(|e| e.map(|c| -c));
        }
        let top_left = edges.map(|e| e[0] > 0.0 || (e[0] == 0.0 && e[1] > 0.0));
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let numerator = n.dot(p[0] - projection.eye);
        let (n_forward, n_right, n_up) =
            (n.dot(projection.forward), n.dot(projection.right), n.dot(projection.up));
        // A pinhole's key is `dot(n, ray) / numerator`, the ray `forward + sx right + sy up'`;
        // an orthographic camera's is the distance `(numerator - sx n_right - sy n_up) /
        // n_forward` negated.
        let (key_row, key_up, key_across) = if projection.perspective {
            let factor = 1.0 / numerator;
            (n_forward * factor, n_up * factor, n_right * factor)
        } else {
            let factor = -1.0 / n_forward;
            (numerator * factor, -n_up * factor, -n_right * factor)
        };
        Some(TriangleSetup { edges, top_left, key_row, key_up, key_across })
    }

    /// Whether no pixel centre of `[x0, x1] x [y0, y1]` can be covered: one edge function is
    /// negative, by more than its rounding, at the rectangle's four corner centres (the
    /// function is linear, so it is then negative on every centre between them).
    pub(crate) fn misses_rect(&self, [x0, y0, x1, y1]: [usize; 4]) -> bool {
        let xs = [x0 as f64 + 0.5, x1 as f64 + 0.5];
        let ys = [y0 as f64 + 0.5, y1 as f64 + 0.5];
        self.edges.iter().any(|e| {
            xs.iter().all(|&px| {
                ys.iter().all(|&py| {
                    let value = e[0] * px + (e[1] * py + e[2]);
                    let scale = e[0].abs() * px + e[1].abs() * py + e[2].abs();
                    value < -1e-12 * scale
                })
            })
        })
    }

    /// Calls `write(i, j, key)` for every pixel of `[x0, x1] x [y0, y1]` whose centre the
    /// triangle covers and whose ray meets its plane in front of the eye.
    ///
    /// `key` is the pixel's depth key there: larger is nearer along the pixel's ray, and
    /// `TileRays::distance` turns it into the distance. A pinhole's key is the inverse of the
    /// depth along the view direction, an orthographic camera's the distance negated: both
    /// are affine in the screen coordinates, so that a covered pixel costs no square root or
    /// division. Returns the number of pixels written.
    #[inline(always)]
    pub(crate) fn scan(
        &self,
        projection: &ScreenProjection,
        [x0, y0, x1, y1]: [usize; 4],
        mut write: impl FnMut(usize, usize, f64),
    ) -> usize {
        let mut written = 0;
        let [e0, e1, e2] = self.edges;
        let key_sign = if projection.perspective { 1.0 } else { -1.0 };
        for j in y0..=y1 {
            let py = j as f64 + 0.5;
            let rows = [e0[1] * py + e0[2], e1[1] * py + e1[2], e2[1] * py + e2[2]];
            // A narrow rectangle is tested pixel by pixel; a wider one only over the span of
            // the row where every edge function is non-negative, widened by a pixel on both
            // sides. The exact test below decides.
            let (i_start, i_end) = if x1 - x0 < NARROW {
                (x0, x1)
            } else {
                let (mut lo, mut hi) = (x0 as f64 - 1.0, x1 as f64 + 1.0);
                let mut empty = false;
                for (e, r) in self.edges.iter().zip(rows) {
                    if e[0] > 0.0 {
                        lo = lo.max(-r / e[0] - 0.5);
                    } else if e[0] < 0.0 {
                        hi = hi.min(-r / e[0] - 0.5);
                    } else if r < 0.0 {
                        empty = true;
                    }
                }
                if empty || lo.is_nan() || hi.is_nan() || lo > hi {
                    continue;
                }
                // lo >= x0 - 1 and hi <= x1 + 1, so truncation is the floor but between -1
                // and 0, which the clamp to x0 >= 0 absorbs; a pixel more on each side covers
                // the division's rounding, far below a pixel.
                ((lo as i64 - 1).max(x0 as i64) as usize, (hi as i64 + 1).min(x1 as i64) as usize)
            };
            let key_row = self.key_row + projection.sy[j] * self.key_up;
            for i in i_start..=i_end {
                let px = i as f64 + 0.5;
                let values = [e0[0] * px + rows[0], e1[0] * px + rows[1], e2[0] * px + rows[2]];
                let key = key_row + projection.sx[i] * self.key_across;
                if self.covers(values, key, key_sign) {
                    write(i, j, key);
                    written += 1;
                }
            }
        }
        written
    }

    /// The three edge functions at pixel (i, j)'s centre, as the scans compute them there
    /// (non-negative, not all zero where the triangle covers it): each over their sum is the
    /// barycentric coordinate of a corner of the point the pixel's ray meets (the edge
    /// function of corner `k` is `det / s` times its barycentric, the same factor for all
    /// three).
    #[inline(always)]
    pub(crate) fn edges_at(&self, i: usize, j: usize) -> [f64; 3] {
        let (px, py) = (i as f64 + 0.5, j as f64 + 0.5);
        self.edges.map(|e| e[0] * px + (e[1] * py + e[2]))
    }

    /// Whether a pixel centre with edge functions `v` and depth key `key` is drawn: inside
    /// the triangle (or on an edge the top-left rule gives it) and in front of the eye
    /// (`key_sign`: 1 for a pinhole, whose keys in front are positive, -1 for an
    /// orthographic camera).
    #[inline(always)]
    fn covers(&self, v: [f64; 3], key: f64, key_sign: f64) -> bool {
        // The same tests as the block scan's lanes (`block_scan.rs`). A key in front of the
        // eye times `key_sign` (exact) is positive and finite.
        let [t0, t1, t2] = self.top_left;
        let ahead = key * key_sign;
        ((v[0] > 0.0) | ((v[0] == 0.0) & t0))
            & ((v[1] > 0.0) | ((v[1] == 0.0) & t1))
            & ((v[2] > 0.0) | ((v[2] == 0.0) & t2))
            & (ahead > 0.0)
            & (ahead < f64::INFINITY)
    }
}

/// The side of the blocks of pixels the AVX-512 scan tests at once (`block_scan.rs`).
pub(crate) const BLOCK_SIDE: usize = 4;

/// The pixels of a block.
pub(crate) const BLOCK_LANES: usize = BLOCK_SIDE * BLOCK_SIDE;
