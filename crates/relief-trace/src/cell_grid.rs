//! The traversal grid of a surface and the exact ray test inside one of its cells.
//!
//! Both surfaces are traversed on a grid of unit cells in "cell space":
//! - `boxes`: a cell is a texel; cell space is grid space.
//! - `triangles`: a cell is the square between four samples (Baboud's inter-texel); cell space
//!   is grid space shifted by half a texel, so cell (i, j) spans `[i, i+1] x [j, j+1]` and has
//!   the samples (i, j), (i+1, j), (i, j+1), (i+1, j+1) at its corners.
//!
//! Every tracer walks cells in its own way but computes a cell's ray segment from the cell's
//! integer bounds ([`CellGrid::segment`]) and tests it with [`CellGrid::intersect_cell`], so two
//! tracers that reach the same cell compute bit-identical hits.

use crate::Hit;
use relief_core::{Aabb, BoxFace, Clip, DVec3, GridGeometry, HeightField, Ray, Surface};
use std::ops::Deref;

/// A ray in cell space with its reciprocal direction: every crossing parameter is then one
/// subtraction and one multiplication, computed the same way by every tracer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellRay {
    /// The ray in cell space.
    pub ray: Ray,
    /// Component-wise `1 / dir` (infinite where `dir` is zero).
    pub inv_dir: DVec3,
}

impl Deref for CellRay {
    type Target = Ray;
    fn deref(&self) -> &Ray {
        &self.ray
    }
}

/// How a ray enters the part of a cell it is tested against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Entry {
    /// The ray starts inside the cell (at its `t_min`).
    Start,
    /// The ray enters the solid's bounding box through a face perpendicular to `axis` (0, 1, 2).
    OuterFace(usize),
    /// The ray crosses from the neighbouring cell along `axis` (0 = x, 1 = y).
    Neighbour(usize),
}

/// A cell's part of a ray: `t_enter <= t <= t_exit`, entered as `entry`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Parameter where the ray enters the cell (within the clipped range).
    pub t_enter: f64,
    /// Parameter where the ray leaves the cell (within the clipped range).
    pub t_exit: f64,
    /// Parameter where the ray crosses the cell's far x boundary (may exceed the clip).
    pub t_next_x: f64,
    /// Parameter where the ray crosses the cell's far y boundary (may exceed the clip).
    pub t_next_y: f64,
    /// How the ray enters.
    pub entry: Entry,
    /// Height of the ray at `t_enter`, exact when it enters through the bottom or top face.
    pub z_enter: f64,
    /// Height of the ray at `t_exit`, exact when it leaves through the bottom or top face.
    pub z_exit: f64,
}

impl Segment {
    /// Whether the ray only touches the cell's footprint: it enters through a side and leaves
    /// through a side at the same parameter (a corner, or an edge crossed at a point).
    pub fn touches_side_only(&self) -> bool {
        let side_entry = matches!(self.entry, Entry::Neighbour(_) | Entry::OuterFace(0 | 1));
        let side_exit = self.t_exit == self.t_next_x || self.t_exit == self.t_next_y;
        self.t_enter == self.t_exit && side_entry && side_exit
    }
}

/// A surface of a height field seen as a grid of cells, with the exact per-cell ray test.
#[derive(Debug, Clone)]
pub struct CellGrid {
    surface: Surface,
    samples_width: usize,
    cells_x: usize,
    cells_y: usize,
    bounds: Aabb,
    /// Cells with no surface (over a hole of the field), row-major; `None` when there are none.
    empty_cells: Option<Vec<bool>>,
    /// Where the grid sits in the world.
    geometry: GridGeometry,
    /// Cell space minus grid space: half a texel for triangles, none for boxes.
    shift: DVec3,
    /// The geometry's [`GridGeometry::grid_scale`], computed once.
    grid_scale: DVec3,
}

impl CellGrid {
    /// The cell grid of `surface` over `field`.
    pub fn new(field: &HeightField, surface: Surface) -> Self {
        let (w, h) = (field.width(), field.height());
        let (cells_x, cells_y, shift) = match surface {
            Surface::Boxes => (w, h, 0.0),
            Surface::Triangles => (w - 1, h - 1, 0.5),
        };
        let bounds = Aabb::new(
            DVec3::new(0.0, 0.0, field.min_sample() as f64),
            DVec3::new(cells_x as f64, cells_y as f64, field.max_sample() as f64),
        );
        let empty_cells = field.holes().map(|holes| match surface {
            Surface::Boxes => holes.to_vec(),
            Surface::Triangles => (0..cells_x * cells_y)
                .map(|k| {
                    let i = k % cells_x + (k / cells_x) * w;
                    holes[i] || holes[i + 1] || holes[i + w] || holes[i + w + 1]
                })
                .collect(),
        });
        let (geometry, shift) = (*field.geometry(), DVec3::new(shift, shift, 0.0));
        CellGrid {
            surface,
            samples_width: w,
            cells_x,
            cells_y,
            bounds,
            empty_cells,
            geometry,
            shift,
            grid_scale: geometry.grid_scale(),
        }
    }

    /// Whether some cell has no surface (the field has holes).
    #[inline]
    pub(crate) fn has_empty_cells(&self) -> bool {
        self.empty_cells.is_some()
    }

    /// Samples per row of the field.
    #[inline]
    pub(crate) fn samples_width(&self) -> usize {
        self.samples_width
    }

    /// Whether cell (cx, cy) has no surface (it lies over a hole of the field).
    #[inline(always)]
    pub fn is_empty_cell(&self, cx: usize, cy: usize) -> bool {
        self.empty_cells.as_ref().is_some_and(|e| e[cx + cy * self.cells_x])
    }

    /// The surface this grid stands for.
    pub fn surface(&self) -> Surface {
        self.surface
    }

    /// Number of cells along x.
    pub fn cells_x(&self) -> usize {
        self.cells_x
    }

    /// Number of cells along y.
    pub fn cells_y(&self) -> usize {
        self.cells_y
    }

    /// Whether the grid has no cells (a `triangles` surface of a single row or column).
    pub fn is_empty(&self) -> bool {
        self.cells_x == 0 || self.cells_y == 0
    }

    /// The solid's bounds in cell space.
    pub fn bounds(&self) -> &Aabb {
        &self.bounds
    }

    /// The solid's bounds in world space: [`CellGrid::bounds`] carried out of cell space.
    pub fn world_bounds(&self) -> Aabb {
        let to_world = |p: DVec3| self.geometry.point_to_world(p + self.shift);
        Aabb::new(to_world(self.bounds.min), to_world(self.bounds.max))
    }

    /// Highest point of the surface over cell (cx, cy): the texel for boxes, the highest of the
    /// four corners for triangles; minus infinity over a hole.
    #[inline]
    pub fn cell_max(&self, samples: &[f32], cx: usize, cy: usize) -> f32 {
        let [a, b, c, d] = self.corners(samples, cx, cy);
        a.max(b).max(c).max(d)
    }

    /// The heights at the corners of cell (cx, cy): lower left, lower right, upper left,
    /// upper right for triangles, the texel's height four times for boxes; minus infinity
    /// over a hole.
    #[inline(always)]
    fn corners(&self, samples: &[f32], cx: usize, cy: usize) -> [f32; 4] {
        if self.is_empty_cell(cx, cy) {
            return [f32::NEG_INFINITY; 4];
        }
        let w = self.samples_width;
        let i = cx + cy * w;
        match self.surface {
            Surface::Boxes => [samples[i]; 4],
            Surface::Triangles => [samples[i], samples[i + 1], samples[i + w], samples[i + w + 1]],
        }
    }

    /// Where the sample at the lower left corner of cell (cx, cy) lives (for triangles; the
    /// texel itself for boxes), if there is one.
    #[inline(always)]
    pub(crate) fn sample_ref<'a>(
        &self,
        samples: &'a [f32],
        cx: usize,
        cy: usize,
    ) -> Option<&'a f32> {
        samples.get(cx + cy * self.samples_width)
    }

    /// The [`CellGrid::corners`] of the four cells of level-1 node (x, y): cell
    /// (2x + i, 2y + j) at `i + 2 j`; minus infinity for a cell outside the grid.
    #[inline(always)]
    pub(crate) fn quad_corners(&self, samples: &[f32], x: usize, y: usize) -> [[f32; 4]; 4] {
        let (cx, cy) = (2 * x, 2 * y);
        if self.surface == Surface::Triangles
            && self.empty_cells.is_none()
            && cx + 2 <= self.cells_x
            && cy + 2 <= self.cells_y
        {
            // All four cells inside and solid: their corners are a 3x3 block of samples.
            let w = self.samples_width;
            let row = |j: usize| -> [f32; 3] {
                let start = cx + (cy + j) * w;
                samples[start..start + 3].try_into().expect("three samples")
            };
            let [r0, r1, r2] = [row(0), row(1), row(2)];
            return [
                [r0[0], r0[1], r1[0], r1[1]],
                [r0[1], r0[2], r1[1], r1[2]],
                [r1[0], r1[1], r2[0], r2[1]],
                [r1[1], r1[2], r2[1], r2[2]],
            ];
        }
        let mut quad = [[f32::NEG_INFINITY; 4]; 4];
        for (k, corners) in quad.iter_mut().enumerate() {
            let (cx, cy) = (2 * x + (k & 1), 2 * y + (k >> 1));
            if cx < self.cells_x && cy < self.cells_y {
                *corners = self.corners(samples, cx, cy);
            }
        }
        quad
    }

    /// Maps a world ray into cell space (same parameter `t`).
    #[inline]
    pub fn to_cell_space(&self, world_ray: &Ray) -> CellRay {
        let grid_ray = self.geometry.ray_to_grid_scaled(world_ray, self.grid_scale);
        let ray = Ray { origin: grid_ray.origin - self.shift, ..grid_ray };
        CellRay { ray, inv_dir: DVec3::ONE / ray.dir }
    }

    /// [`CellGrid::to_cell_space`] without the reciprocal direction (left at zero), for a
    /// caller that knows it already: the same origin and direction, bit for bit.
    #[inline]
    pub(crate) fn to_cell_space_dir_only(&self, world_ray: &Ray) -> CellRay {
        let grid_ray = self.geometry.ray_to_grid_scaled(world_ray, self.grid_scale);
        let ray = Ray { origin: grid_ray.origin - self.shift, ..grid_ray };
        CellRay { ray, inv_dir: DVec3::ZERO }
    }

    /// The world hit for a cell-space hit at `t` with grid-space `normal` (zero: started inside).
    pub fn world_hit(&self, world_ray: &Ray, t: f64, normal: DVec3) -> Hit {
        let normal = if normal == DVec3::ZERO {
            -world_ray.dir.normalize()
        } else {
            self.geometry.normal_to_world(normal)
        };
        Hit { t, position: world_ray.at(t), normal }
    }

    /// Clips a cell-space ray to the solid's bounds; `None` if it misses them or the grid has
    /// no cells.
    #[inline]
    pub fn clip(&self, cell_ray: &CellRay) -> Option<Clip> {
        if self.is_empty() {
            return None;
        }
        self.bounds.clip_with_inverse(cell_ray, cell_ray.inv_dir)
    }

    /// The cell containing the ray's point at `t` (half-open cells, clamped into the grid).
    ///
    /// The index is chosen so that the cell's own integer bounds put `t` inside its span along
    /// the ray: a point that rounds onto a cell boundary goes to the cell whose segment holds it,
    /// so even a zero-length clip (a flat terrain hit from above) lands in a cell that tests it.
    pub fn cell_at(&self, ray: &CellRay, t: f64) -> (usize, usize) {
        (
            axis_cell(ray.origin.x, ray.dir.x, ray.inv_dir.x, t, self.cells_x),
            axis_cell(ray.origin.y, ray.dir.y, ray.inv_dir.y, t, self.cells_y),
        )
    }

    /// The part of the clipped ray inside cell (cx, cy), from the cell's integer bounds.
    #[inline]
    pub fn segment(&self, ray: &CellRay, clip: &Clip, cx: usize, cy: usize) -> Segment {
        let (x_in, x_out) = axis_span(ray.origin.x, ray.dir.x, ray.inv_dir.x, cx as f64);
        let (y_in, y_out) = axis_span(ray.origin.y, ray.dir.y, ray.inv_dir.y, cy as f64);
        let (mut t_enter, mut entry) = (clip.t_enter, outer_entry(clip.face));
        if x_in > t_enter {
            t_enter = x_in;
            entry = Entry::Neighbour(0);
        }
        if y_in > t_enter {
            t_enter = y_in;
            entry = Entry::Neighbour(1);
        }
        let z_enter = match entry {
            Entry::OuterFace(2) if ray.dir.z > 0.0 => self.bounds.min.z,
            Entry::OuterFace(2) => self.bounds.max.z,
            _ => ray.origin.z + t_enter * ray.dir.z,
        };
        let t_exit = clip.t_exit.min(x_out).min(y_out);
        // Where the ray leaves the box through its bottom or top, take that face's height
        // itself: a surface lying on the face (a flat floor) is then met, not missed by rounding.
        let z_face = if ray.dir.z < 0.0 { self.bounds.min.z } else { self.bounds.max.z };
        let z_exit = if ray.dir.z != 0.0 && t_exit == (z_face - ray.origin.z) * ray.inv_dir.z {
            z_face
        } else {
            ray.origin.z + t_exit * ray.dir.z
        };
        Segment { t_enter, t_exit, t_next_x: x_out, t_next_y: y_out, entry, z_enter, z_exit }
    }

    /// The exact first point of the cell-space `ray` inside the solid over cell (cx, cy), within
    /// `seg`. Returns the parameter and the normal in grid space (zero when the ray starts inside).
    /// A segment of no length between two of the cell's sides (a ray that only touches the
    /// footprint at a corner or along an edge) meets nothing: touching is not a hit, whichever
    /// cells a traversal visits there.
    #[inline]
    pub fn intersect_cell(
        &self,
        samples: &[f32],
        ray: &CellRay,
        cx: usize,
        cy: usize,
        seg: &Segment,
    ) -> Option<(f64, DVec3)> {
        if seg.t_enter > seg.t_exit || self.is_empty_cell(cx, cy) || seg.touches_side_only() {
            return None;
        }
        match self.surface {
            Surface::Boxes => {
                let top = samples[cx + cy * self.samples_width] as f64;
                box_column(ray, top, seg)
            }
            Surface::Triangles => self.two_triangles(samples, ray, cx, cy, seg),
        }
    }

    /// Grid-space normal of the `triangles` surface of cell (cx, cy) at cell-space point `p`
    /// (the plane of the triangle `p` lies over).
    pub fn triangle_normal(&self, samples: &[f32], cx: usize, cy: usize, p: DVec3) -> DVec3 {
        let w = self.samples_width;
        let i = cx + cy * w;
        let corners = [samples[i], samples[i + 1], samples[i + w], samples[i + w + 1]];
        let (_, pu, pv) = triangle_plane(corners.map(f64::from), p.x - cx as f64, p.y - cy as f64);
        DVec3::new(-pu, -pv, 1.0)
    }

    fn two_triangles(
        &self,
        samples: &[f32],
        ray: &CellRay,
        cx: usize,
        cy: usize,
        seg: &Segment,
    ) -> Option<(f64, DVec3)> {
        // The surface over the cell is the larger of the two triangles' planes, since the
        // split takes the lower diagonal. The solid is below both planes' maximum.
        let planes = triangle_planes(samples, self.samples_width, cx, cy);
        let (u0, v0) = (ray.origin.x - cx as f64, ray.origin.y - cy as f64);
        let local = |t: f64| (u0 + t * ray.dir.x, v0 + t * ray.dir.y);
        let ((u_in, v_in), (u_out, v_out)) = (local(seg.t_enter), local(seg.t_exit));
        // Height of the ray above each plane, linear along the ray, at both ends.
        let above = planes.map(|(p0, pu, pv)| {
            let f_enter = seg.z_enter - (p0 + pu * u_in + pv * v_in);
            let f_exit = seg.z_exit - (p0 + pu * u_out + pv * v_out);
            (f_enter, f_exit)
        });
        if above.iter().all(|&(f_enter, f_exit)| f_enter > 0.0 && f_exit > 0.0) {
            return None;
        }
        let mut best: Option<(f64, DVec3)> = None;
        for ((_, pu, pv), (f_enter, f_exit)) in planes.into_iter().zip(above) {
            let normal = DVec3::new(-pu, -pv, 1.0);
            let candidate = if f_enter <= 0.0 {
                // Below the surface on entry: through an outer wall, from the start, or past
                // the wall of a hole; from a solid neighbour only by rounding, on the surface.
                let n = match seg.entry {
                    Entry::Neighbour(axis) if !self.behind_is_empty(ray, cx, cy, axis) => normal,
                    entry => entry_normal(entry, ray),
                };
                Some((seg.t_enter, n))
            } else if f_exit <= 0.0 {
                let along = f_enter / (f_enter - f_exit);
                let t = seg.t_enter + along * (seg.t_exit - seg.t_enter);
                Some((t.clamp(seg.t_enter, seg.t_exit), normal))
            } else {
                None
            };
            if let Some(c) = candidate {
                if best.is_none_or(|b| c.0 < b.0) {
                    best = Some(c);
                }
            }
        }
        best
    }
}

impl CellGrid {
    /// Whether the cell the ray comes from, across the boundary along `axis`, is empty.
    fn behind_is_empty(&self, ray: &Ray, cx: usize, cy: usize, axis: usize) -> bool {
        if self.empty_cells.is_none() {
            return false;
        }
        let back = |c: usize, d: f64, n: usize| {
            if d > 0.0 {
                c.checked_sub(1)
            } else {
                Some(c + 1).filter(|&c| c < n)
            }
        };
        match axis {
            0 => back(cx, ray.dir.x, self.cells_x).is_none_or(|bx| self.is_empty_cell(bx, cy)),
            _ => back(cy, ray.dir.y, self.cells_y).is_none_or(|by| self.is_empty_cell(cx, by)),
        }
    }
}

/// Exact test of a flat-topped column of height `top` over a segment.
#[inline]
fn box_column(ray: &CellRay, top: f64, seg: &Segment) -> Option<(f64, DVec3)> {
    if seg.z_enter <= top {
        return Some((seg.t_enter, entry_normal(seg.entry, ray)));
    }
    if ray.dir.z < 0.0 && seg.z_exit <= top {
        let t = (top - ray.origin.z) * ray.inv_dir.z;
        return Some((t.clamp(seg.t_enter, seg.t_exit), DVec3::Z));
    }
    None
}

/// The normal of the face crossed on entry (zero: the ray starts inside).
#[inline]
fn entry_normal(entry: Entry, ray: &Ray) -> DVec3 {
    let axis = match entry {
        Entry::Start => return DVec3::ZERO,
        Entry::OuterFace(axis) | Entry::Neighbour(axis) => axis,
    };
    let mut n = DVec3::ZERO;
    n[axis] = -ray.dir[axis].signum();
    n
}

fn outer_entry(face: BoxFace) -> Entry {
    match face {
        BoxFace::Inside => Entry::Start,
        BoxFace::X => Entry::OuterFace(0),
        BoxFace::Y => Entry::OuterFace(1),
        BoxFace::Z => Entry::OuterFace(2),
    }
}

/// The plane `z = z0 + pu u + pv v` of the `triangles` surface over local point (u, v) of a
/// cell whose corners are `[a, b, c, d]` (lower left, lower right, upper left, upper right):
/// the square splits along its lower diagonal ([`relief_core::splits_along_ad`]), and the
/// point takes the triangle it lies in (on the diagonal, the first).
#[inline(always)]
pub(crate) fn triangle_plane([a, b, c, d]: [f64; 4], u: f64, v: f64) -> (f64, f64, f64) {
    if relief_core::splits_along_ad(a, b, c, d) {
        if u >= v {
            (a, b - a, d - b)
        } else {
            (a, d - c, c - a)
        }
    } else if u + v <= 1.0 {
        (a, b - a, c - a)
    } else {
        (b + c - d, d - c, d - b)
    }
}

/// The index along one axis of the cell whose span along the ray holds `t`.
#[inline]
pub(crate) fn axis_cell(o: f64, d: f64, inv: f64, t: f64, cells: usize) -> usize {
    // Truncation is the floor for non-negative values; NaN and negatives go to cell 0.
    let v = o + t * d;
    let c = if v >= 0.0 { (v as usize).min(cells - 1) } else { 0 };
    let (t_in, t_out) = axis_span(o, d, inv, c as f64);
    let towards_low = if d > 0.0 { t_in > t } else { t_out < t };
    let towards_high = if d > 0.0 { t_out < t } else { t_in > t };
    if d != 0.0 && towards_low && c > 0 {
        c - 1
    } else if d != 0.0 && towards_high && c + 1 < cells {
        c + 1
    } else {
        c
    }
}

/// Parameters where a ray enters and leaves the slab `[lo, lo + 1]` along one axis: all of
/// the ray for a ray parallel to the slab inside it, none of it for one outside.
#[inline]
pub(crate) fn axis_span(o: f64, d: f64, inv: f64, lo: f64) -> (f64, f64) {
    if d > 0.0 {
        ((lo - o) * inv, (lo + 1.0 - o) * inv)
    } else if d < 0.0 {
        ((lo + 1.0 - o) * inv, (lo - o) * inv)
    } else if lo <= o && o <= lo + 1.0 {
        (f64::NEG_INFINITY, f64::INFINITY)
    } else {
        (f64::INFINITY, f64::NEG_INFINITY)
    }
}

/// The planes `z = p0 + pu u + pv v` (`u`, `v` local to the cell, 0 to 1) of the two
/// triangles of the `triangles` surface over cell `(cx, cy)` of `samples`, `width` samples a
/// row: the lower-sum diagonal's split. Chosen without a branch the processor could mispredict.
#[inline]
pub(crate) fn triangle_planes(
    samples: &[f32],
    width: usize,
    cx: usize,
    cy: usize,
) -> [(f64, f64, f64); 2] {
    let i = cx + cy * width;
    let (a, b) = (samples[i] as f64, samples[i + 1] as f64);
    let (c, d) = (samples[i + width] as f64, samples[i + width + 1] as f64);
    let ad = relief_core::splits_along_ad(a, b, c, d);
    [
        (a, b - a, if ad { d - b } else { c - a }),
        (if ad { a } else { b + c - d }, d - c, if ad { c - a } else { d - b }),
    ]
}
