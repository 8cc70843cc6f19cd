//! Sets of 2D lines as unions of convex polygons in dual space (Baboud et al., 6.2.2-6.2.4).
//!
//! In a ray class's local frame every line of interest is `y = u + (v - u) (x - x_ref)`: it
//! passes through `(x_ref, u)` and `(x_ref + 1, v)`, so it is the point `(u, v)` of the dual
//! plane. The lines passing on one side of a primal point form a dual half-plane, the lines
//! crossing a segment form a double wedge, the rays of class `x+` (`|v - u| <= 1`) a strip:
//! every visibility question of the precomputation becomes clipping convex polygons by
//! half-planes. Clipping keeps a small margin, so sets only err on the large side, and slivers
//! of no area (sets of lines of measure zero, such as lines through one vertex) are dropped.

/// Below this dual area a polygon is a sliver: a measure-zero set of lines.
const SLIVER_AREA: f64 = 1e-12;
/// Margin by which clipping keeps points just outside a half-plane.
const CLIP_MARGIN: f64 = 1e-10;
/// More pieces than this and a set stops being refined (it only stays larger than exact).
const MAX_PIECES: usize = 64;

/// The dual half-plane `a u + b v + c >= 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfPlane {
    a: f64,
    b: f64,
    c: f64,
}

impl HalfPlane {
    /// `a u + b v + c >= 0`.
    pub fn new(a: f64, b: f64, c: f64) -> Self {
        HalfPlane { a, b, c }
    }

    /// The opposite closed half-plane.
    pub fn flipped(self) -> Self {
        HalfPlane { a: -self.a, b: -self.b, c: -self.c }
    }

    #[inline]
    fn eval(&self, p: [f64; 2]) -> f64 {
        self.a * p[0] + self.b * p[1] + self.c
    }
}

/// The linear form of a line's `y` at abscissa `x`: `y(x) = (1 - s) u + s v`, `s = x - x_ref`.
#[inline]
fn y_form(x_ref: f64, x: f64) -> (f64, f64) {
    let s = x - x_ref;
    (1.0 - s, s)
}

/// Most vertices a polygon keeps; a clip that would exceed it is skipped (the set then only
/// stays larger than exact).
const MAX_VERTICES: usize = 12;

/// A convex polygon of the dual plane (either orientation), stored inline.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Polygon {
    len: usize,
    vertices: [[f64; 2]; MAX_VERTICES],
}

impl Polygon {
    fn new() -> Self {
        Polygon { len: 0, vertices: [[0.0; 2]; MAX_VERTICES] }
    }

    fn from_slice(points: &[[f64; 2]]) -> Self {
        let mut p = Polygon::new();
        for &q in points {
            p.push(q);
        }
        p
    }

    #[inline]
    fn push(&mut self, q: [f64; 2]) {
        self.vertices[self.len] = q;
        self.len += 1;
    }

    #[inline]
    fn points(&self) -> &[[f64; 2]] {
        &self.vertices[..self.len]
    }
}

/// A set of lines: the union of convex dual polygons, for lines referred to `x_ref`.
#[derive(Debug, Clone, PartialEq)]
pub struct LineSet {
    x_ref: f64,
    pieces: Vec<Polygon>,
}

impl LineSet {
    /// The lines with `u` in `u_range` and `v` in `v_range`.
    pub fn rectangle(x_ref: f64, u_range: (f64, f64), v_range: (f64, f64)) -> Self {
        let (u0, u1) = u_range;
        let (v0, v1) = v_range;
        let corners = [[u0, v0], [u1, v0], [u1, v1], [u0, v1]];
        LineSet { x_ref, pieces: vec![Polygon::from_slice(&corners)] }
    }

    /// The empty set.
    pub fn empty(x_ref: f64) -> Self {
        LineSet { x_ref, pieces: Vec::new() }
    }

    /// Whether the set has no lines (up to slivers).
    pub fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }

    /// The abscissa lines are referred to.
    pub fn x_ref(&self) -> f64 {
        self.x_ref
    }

    /// Number of convex pieces.
    pub fn piece_count(&self) -> usize {
        self.pieces.len()
    }

    /// Half-plane of lines passing at or below the primal point (x, y).
    pub fn below_point(&self, x: f64, y: f64) -> HalfPlane {
        let (a, b) = y_form(self.x_ref, x);
        HalfPlane::new(-a, -b, y)
    }

    /// Half-plane of lines whose `y` at abscissa `x` is at least `y_min`.
    pub fn y_at_least(&self, x: f64, y_min: f64) -> HalfPlane {
        let (a, b) = y_form(self.x_ref, x);
        HalfPlane::new(a, b, -y_min)
    }

    /// Half-plane of lines whose `y` at abscissa `x` is at most `y_max`.
    pub fn y_at_most(&self, x: f64, y_max: f64) -> HalfPlane {
        self.y_at_least(x, y_max).flipped()
    }

    /// Half-plane `k * y(x) + c >= 0` on the lines' `y` at abscissa `x`.
    pub fn y_linear(&self, x: f64, k: f64, c: f64) -> HalfPlane {
        let (a, b) = y_form(self.x_ref, x);
        HalfPlane::new(k * a, k * b, c)
    }

    /// Half-plane of lines whose slope `dy/dx = v - u` is at least `w`.
    pub fn slope_at_least(&self, w: f64) -> HalfPlane {
        HalfPlane::new(-1.0, 1.0, -w)
    }

    /// Half-plane of lines whose slope `dy/dx` is at most `w`.
    pub fn slope_at_most(&self, w: f64) -> HalfPlane {
        self.slope_at_least(w).flipped()
    }

    /// Keeps the lines in `h`.
    pub fn clip(&mut self, h: HalfPlane) {
        self.pieces.retain_mut(|p| match non_sliver(clip_polygon(p, h)) {
            Some(q) => {
                *p = q;
                true
            }
            None => false,
        });
    }

    /// Keeps the lines in every half-plane of `hs`.
    pub fn clip_all(&mut self, hs: &[HalfPlane]) {
        for &h in hs {
            self.clip(h);
        }
    }

    /// The union of this set clipped by each of `alternatives` (each a list of half-planes).
    pub fn split(&self, alternatives: &[&[HalfPlane]]) -> LineSet {
        let mut out = LineSet::empty(self.x_ref);
        for hs in alternatives {
            let mut part = self.clone();
            part.clip_all(hs);
            out.pieces.extend(part.pieces);
        }
        out
    }

    /// Whether some line of the set also lies in every half-plane of `hs`.
    pub fn meets(&self, hs: &[HalfPlane]) -> bool {
        self.pieces.iter().any(|p| {
            let mut poly = *p;
            for &h in hs {
                match non_sliver(clip_polygon(&poly, h)) {
                    Some(q) => poly = q,
                    None => return false,
                }
            }
            true
        })
    }

    /// Removes the lines crossing the convex primal polygon `region` (given by its vertices):
    /// what is left passes wholly above or wholly below it.
    pub fn subtract_region(&mut self, region: &[[f64; 2]]) {
        if self.pieces.len() > MAX_PIECES || region.len() > 4 {
            return;
        }
        let mut sides = [HalfPlane::new(0.0, 0.0, 0.0); 4];
        for (side, q) in sides.iter_mut().zip(region) {
            *side = self.below_point(q[0], q[1]);
        }
        let sides = &sides[..region.len()];
        let clip_chain = |piece: &Polygon, flip: bool| {
            let mut poly = *piece;
            for &h in sides {
                poly = non_sliver(clip_polygon(&poly, if flip { h.flipped() } else { h }))?;
            }
            Some(poly)
        };
        let count = self.pieces.len();
        for k in 0..count {
            let piece = &self.pieces[k];
            // A piece wholly on one side of the region (all its corner lines pass below every
            // region point, or above every one) keeps all its lines: the sides are convex.
            let side_of = |l: [f64; 2]| {
                let (mut below, mut above) = (true, true);
                for h in sides {
                    let f = h.eval(l);
                    below &= f >= 0.0;
                    above &= f <= 0.0;
                }
                (below, above)
            };
            let (mut all_below, mut all_above) = (true, true);
            for &l in piece.points() {
                let (b, a) = side_of(l);
                all_below &= b;
                all_above &= a;
            }
            if all_below || all_above {
                continue;
            }
            let (below, above) = (clip_chain(piece, false), clip_chain(piece, true));
            match (below, above) {
                (Some(b), Some(a)) => {
                    self.pieces[k] = b;
                    self.pieces.push(a);
                }
                (Some(p), None) | (None, Some(p)) => self.pieces[k] = p,
                (None, None) => self.pieces[k].len = 0,
            }
        }
        self.pieces.retain(|p| p.len > 0);
    }

    /// The smallest and largest `y` of the set's lines over abscissas `x0..=x1`.
    pub fn y_range(&self, x0: f64, x1: f64) -> Option<(f64, f64)> {
        let mut range: Option<(f64, f64)> = None;
        for p in self.pieces.iter().flat_map(|p| p.points()) {
            for x in [x0, x1] {
                let (a, b) = y_form(self.x_ref, x);
                let y = a * p[0] + b * p[1];
                range = Some(range.map_or((y, y), |(lo, hi)| (lo.min(y), hi.max(y))));
            }
        }
        range
    }

    /// The vertices of every piece, as lines `(u, v)`.
    pub fn vertices(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        self.pieces.iter().flat_map(|p| p.points()).copied()
    }

    /// The line `(u, v)`'s `y` at abscissa `x`.
    pub fn y_of(&self, line: [f64; 2], x: f64) -> f64 {
        let (a, b) = y_form(self.x_ref, x);
        a * line[0] + b * line[1]
    }
}

/// Sutherland-Hodgman clipping of a convex polygon by one half-plane, with a small margin. A
/// clip that would need more vertices than a polygon holds is skipped.
fn clip_polygon(poly: &Polygon, h: HalfPlane) -> Polygon {
    let n = poly.len;
    let mut out = Polygon::new();
    if n == 0 {
        return out;
    }
    let scale = h.a.abs() + h.b.abs() + 1.0;
    let margin = CLIP_MARGIN * scale;
    let pts = poly.points();
    for k in 0..n {
        let (p, q) = (pts[k], pts[(k + 1) % n]);
        let (fp, fq) = (h.eval(p) + margin, h.eval(q) + margin);
        if out.len + 2 > MAX_VERTICES {
            return *poly;
        }
        if fp >= 0.0 {
            out.push(p);
        }
        if (fp >= 0.0) != (fq >= 0.0) {
            let t = fp / (fp - fq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

/// `Some(poly)` unless it is a sliver (no area).
fn non_sliver(poly: Polygon) -> Option<Polygon> {
    (poly.len >= 3 && area(poly.points()) > SLIVER_AREA).then_some(poly)
}

fn area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    let twice: f64 = (0..n)
        .map(|k| {
            let (p, q) = (poly[k], poly[(k + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum();
    twice.abs() / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lines through the vertical segment x = 0, y in [0, 1] with slopes in [-1, 1].
    fn through_unit_segment() -> LineSet {
        let mut set = LineSet::rectangle(0.0, (-10.0, 10.0), (-10.0, 10.0));
        let (lo, hi) = (set.y_at_least(0.0, 0.0), set.y_at_most(0.0, 1.0));
        let (s0, s1) = (set.slope_at_least(-1.0), set.slope_at_most(1.0));
        set.clip_all(&[lo, hi, s0, s1]);
        set
    }

    #[test]
    fn a_wall_in_front_blocks_everything_and_a_gap_lets_some_through() {
        // A vertical wall at x = 2 from y = -5 to y = 5: every line through the segment crosses it.
        let mut set = through_unit_segment();
        set.subtract_region(&[[2.0, -5.0], [2.1, -5.0], [2.1, 5.0], [2.0, 5.0]]);
        assert!(set.is_empty());
        // A wall with a gap y in [0.4, 0.6]: horizontal lines through the gap remain.
        let mut set = through_unit_segment();
        set.subtract_region(&[[2.0, -5.0], [2.1, -5.0], [2.1, 0.4], [2.0, 0.4]]);
        set.subtract_region(&[[2.0, 0.6], [2.1, 0.6], [2.1, 5.0], [2.0, 5.0]]);
        assert!(!set.is_empty());
        for line in set.vertices() {
            let y = set.y_of(line, 2.05);
            assert!((0.4 - 1e-6..=0.6 + 1e-6).contains(&y), "{y}");
        }
    }

    #[test]
    fn lines_through_a_single_point_are_a_sliver() {
        // Two walls meeting at (2, 0.5): only lines through that point pass, a measure-zero set.
        let mut set = through_unit_segment();
        set.subtract_region(&[[2.0, -5.0], [2.0, 0.5], [2.1, 0.5], [2.1, -5.0]]);
        set.subtract_region(&[[2.0, 0.5], [2.0, 5.0], [2.1, 5.0], [2.1, 0.5]]);
        assert!(set.is_empty());
    }

    #[test]
    fn meets_tests_without_changing_the_set() {
        let set = through_unit_segment();
        assert!(set.meets(&[set.y_at_least(4.0, 3.5)]));
        assert!(!set.meets(&[set.y_at_least(4.0, 5.5)]));
        assert_eq!(set.piece_count(), 1);
    }
}
