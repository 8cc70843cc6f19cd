//! The approximate ray casting of the hybrid renderer inside one cell's proxy box (Ammann et
//! al. 2010, section 3, after Policarpo et al. 2005): a linear search with a fixed number of
//! steps from the box's entry to its exit, then a fixed number of binary search halvings.

use super::{HybridCells, LopSteps};
use crate::cell_grid::triangle_plane;
use crate::Hit;
use relief_core::{BoxFace, DVec3, HeightField, Ray};

/// Where a world ray enters and leaves the proxy box of cell `index` within its range, as ray
/// parameters; `None` when it misses the box or the cell has no surface. The entry is the
/// lower bound `t0` the exact far field ([`super::exact_far_hit`]) starts from.
pub fn box_entry(
    cells: &HybridCells,
    field: &HeightField,
    index: usize,
    ray: &Ray,
) -> Option<(f64, f64)> {
    let grid_ray = field.geometry().ray_to_grid(ray);
    let clip = cells.grid_box(index)?.clip(&grid_ray)?;
    Some((clip.t_enter, clip.t_exit))
}

/// Casts `ray` (world space) into the proxy box of cell `index` with `steps`: approximate, as
/// the paper's shader.
///
/// The linear search tests `steps.linear + 1` evenly spaced points (`linear` at least 1)
/// from the box's entry to its exit (both included) for the first one below or on the
/// surface; the binary search then halves the interval between the last point above and that
/// one `steps.binary` times, and the hit is the middle of the last interval. The surface's
/// height at a point is the surface's own interpolation (the triangle under the point for
/// `triangles`, the texel's value for `boxes`); holes and points off the grid have none. A
/// ray already below the surface at the entry hits there (an outer wall, or the solid the ray
/// started in).
///
/// The normal is that of the face met: the triangle's plane, a texel's top, or a side (a
/// texel's side, or the wall of a hole or of the grid's edge) when the ray reached the cell
/// of the point found below the surface already below it; the reversed ray direction when the
/// ray starts inside the solid. Thin crests between two points of the linear search are
/// missed, more often with fewer steps (the paper's section 4.1); a ray can miss in the box.
///
/// `cells` must have been measured from `field` (see [`HybridCells::update`]).
pub fn lop_cast(
    field: &HeightField,
    cells: &HybridCells,
    index: usize,
    ray: &Ray,
    steps: LopSteps,
) -> Option<Hit> {
    let geometry = field.geometry();
    let g = geometry.ray_to_grid(ray);
    let clip = cells.grid_box(index)?.clip(&g)?;
    let surface = SampledSurface::of(cells.surface(), field);
    let below = |t: f64| {
        let p = g.at(t);
        surface.height(p.x, p.y).is_some_and(|h| p.z <= h)
    };
    let n = steps.linear.max(1);
    let span = clip.t_exit - clip.t_enter;
    let at =
        |i: u32| if i == n { clip.t_exit } else { clip.t_enter + span * (i as f64 / n as f64) };
    let first = (0..=n).find(|&i| below(at(i)))?;
    if first == 0 {
        let t = clip.t_enter;
        let p = g.at(t);
        let normal = match clip.face {
            BoxFace::Inside => {
                return Some(Hit { t, position: ray.at(t), normal: -ray.dir.normalize() })
            }
            BoxFace::X => side_normal(0, &g),
            BoxFace::Y => side_normal(1, &g),
            // Through the top onto the surface, or from below through the solid's bottom.
            BoxFace::Z if g.dir.z > 0.0 => -DVec3::Z,
            BoxFace::Z => surface.normal_at(p.x, p.y),
        };
        return Some(Hit { t, position: ray.at(t), normal: geometry.normal_to_world(normal) });
    }
    let (mut above_t, mut below_t) = (at(first - 1), at(first));
    for _ in 0..steps.binary {
        let mid = 0.5 * (above_t + below_t);
        if below(mid) {
            below_t = mid;
        } else {
            above_t = mid;
        }
    }
    let t = 0.5 * (above_t + below_t);
    let normal = surface.face_normal(&g, above_t, below_t);
    Some(Hit { t, position: ray.at(t), normal: geometry.normal_to_world(normal) })
}

/// The grid-space normal of a side perpendicular to `axis` facing the ray.
fn side_normal(axis: usize, g: &Ray) -> DVec3 {
    let mut n = DVec3::ZERO;
    n[axis] = -g.dir[axis].signum();
    n
}

/// A surface of a height field sampled at grid-space points, with what every lookup needs at
/// hand.
struct SampledSurface<'a> {
    triangles: bool,
    samples: &'a [f32],
    holes: Option<&'a [bool]>,
    /// Samples per row.
    width: usize,
    /// Surface cells along x and y (texels, or squares between four samples).
    cells_x: usize,
    cells_y: usize,
    /// Grid-space offset of the cells: half a texel for triangles.
    shift: f64,
}

impl<'a> SampledSurface<'a> {
    fn of(kind: relief_core::Surface, field: &'a HeightField) -> Self {
        let (w, h) = (field.width(), field.height());
        let triangles = kind == relief_core::Surface::Triangles;
        let (cells_x, cells_y, shift) = if triangles { (w - 1, h - 1, 0.5) } else { (w, h, 0.0) };
        SampledSurface {
            triangles,
            samples: field.samples(),
            holes: field.holes(),
            width: w,
            cells_x,
            cells_y,
            shift,
        }
    }

    /// Cell-space offset of the surface's cells: texels for boxes, the squares between four
    /// samples (their corners at sample centres) for triangles.
    #[inline(always)]
    fn shift(&self) -> f64 {
        self.shift
    }

    /// The surface cell under grid point (x, y), if it lies on the surface's footprint (its
    /// closed far edges belong to the last cells).
    #[inline(always)]
    fn cell_at(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let (u, v) = (x - self.shift, y - self.shift);
        let inside = |c: f64, n: usize| n > 0 && c >= 0.0 && c <= n as f64;
        if !(inside(u, self.cells_x) && inside(v, self.cells_y)) {
            return None;
        }
        Some(((u as usize).min(self.cells_x - 1), (v as usize).min(self.cells_y - 1)))
    }

    /// Whether surface cell (cx, cy) is over a hole.
    #[inline(always)]
    fn is_hole(&self, cx: usize, cy: usize) -> bool {
        let Some(holes) = self.holes else { return false };
        let i = cx + cy * self.width;
        if self.triangles {
            holes[i] || holes[i + 1] || holes[i + self.width] || holes[i + self.width + 1]
        } else {
            holes[i]
        }
    }

    /// The plane `z = z0 + pu u + pv v` (local coordinates of the cell) over point (u, v) of
    /// surface cell (cx, cy): the texel's flat top, or the triangle holding the point.
    #[inline(always)]
    fn plane(&self, cx: usize, cy: usize, u: f64, v: f64) -> (f64, f64, f64) {
        let i = cx + cy * self.width;
        if !self.triangles {
            return (self.samples[i] as f64, 0.0, 0.0);
        }
        let w = self.width;
        let corners =
            [self.samples[i], self.samples[i + 1], self.samples[i + w], self.samples[i + w + 1]];
        triangle_plane(corners.map(f64::from), u, v)
    }

    /// The surface's height over grid point (x, y); `None` off the footprint or over a hole.
    #[inline(always)]
    fn height(&self, x: f64, y: f64) -> Option<f64> {
        let (cx, cy) = self.cell_at(x, y)?;
        if self.is_hole(cx, cy) {
            return None;
        }
        Some(self.height_in(cx, cy, x, y))
    }

    /// The height of surface cell (cx, cy)'s plane over grid point (x, y).
    #[inline(always)]
    fn height_in(&self, cx: usize, cy: usize, x: f64, y: f64) -> f64 {
        let (u, v) = (x - self.shift() - cx as f64, y - self.shift() - cy as f64);
        let (z0, pu, pv) = self.plane(cx, cy, u, v);
        z0 + pu * u + pv * v
    }

    /// The grid-space normal of the surface over (x, y) (up where there is none).
    fn normal_at(&self, x: f64, y: f64) -> DVec3 {
        match self.cell_at(x, y) {
            Some((cx, cy)) => {
                let (u, v) = (x - self.shift() - cx as f64, y - self.shift() - cy as f64);
                let (_, pu, pv) = self.plane(cx, cy, u, v);
                DVec3::new(-pu, -pv, 1.0)
            }
            None => DVec3::Z,
        }
    }

    /// The normal of the face the grid-space ray `g` met between `above_t` (a point above the
    /// surface or off it) and `below_t` (a point below it): when the two points lie over
    /// different surface cells, the side of the cell of the point below if the ray crossed
    /// into it (where it did, clamped to the interval) below the cell's surface; otherwise the
    /// surface itself at the point below.
    fn face_normal(&self, g: &Ray, above_t: f64, below_t: f64) -> DVec3 {
        let p = g.at(below_t);
        let Some((cx, cy)) = self.cell_at(p.x, p.y) else { return DVec3::Z };
        let a = g.at(above_t);
        let above_cell = self.cell_at(a.x, a.y);
        if above_cell == Some((cx, cy)) {
            return self.normal_at(p.x, p.y);
        }
        // The last crossing into the cell along an axis where the two cells differ.
        let cell = [cx, cy];
        let mut enter = (f64::NEG_INFINITY, 0);
        for (axis, c) in cell.into_iter().enumerate() {
            let d = g.dir[axis];
            let differs = above_cell.is_none_or(|ac| [ac.0, ac.1][axis] != c);
            if d != 0.0 && differs {
                let lo = c as f64 + self.shift();
                let boundary = if d > 0.0 { lo } else { lo + 1.0 };
                let t = (boundary - g.origin[axis]) / d;
                if t > enter.0 {
                    enter = (t, axis);
                }
            }
        }
        let (t_cross, axis) = enter;
        if t_cross.is_finite() {
            let q = g.at(t_cross.clamp(above_t, below_t));
            if q.z <= self.height_in(cx, cy, q.x, q.y) {
                return side_normal(axis, g);
            }
        }
        self.normal_at(p.x, p.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::GridGeometry;

    #[test]
    fn a_flat_cell_is_hit_where_the_ray_meets_it() {
        let field = HeightField::new(5, 5, vec![2.0; 25], GridGeometry::unit()).unwrap();
        for surface in relief_core::Surface::ALL {
            let cells = HybridCells::new(&field, surface, 5).unwrap();
            let ray = Ray::new(DVec3::new(2.2, 2.3, 6.0), DVec3::new(0.1, 0.0, -1.0).normalize());
            let exact = 4.0 * DVec3::new(0.1, 0.0, -1.0).length();
            let hit =
                lop_cast(&field, &cells, 0, &ray, LopSteps { linear: 4, binary: 20 }).unwrap();
            // The box is flat: its entry is on the surface.
            assert!((hit.t - exact).abs() < 1e-9, "{surface}: {hit:?}");
            assert!((hit.normal - DVec3::Z).length() < 1e-12);
        }
    }

    #[test]
    fn a_wall_at_the_grid_edge_is_hit_at_the_box_entry() {
        let mut samples = vec![0.0f32; 16];
        samples[4..8].fill(3.0);
        let field = HeightField::new(4, 4, samples, GridGeometry::unit()).unwrap();
        let cells = HybridCells::new(&field, relief_core::Surface::Boxes, 4).unwrap();
        let ray = Ray::new(DVec3::new(-2.0, 1.5, 1.0), DVec3::X);
        let hit = lop_cast(&field, &cells, 0, &ray, LopSteps { linear: 8, binary: 5 }).unwrap();
        assert_eq!((hit.t, hit.normal), (2.0, -DVec3::X));
        // Over row 2 (height 0) the ray passes above everything.
        let over = Ray::new(DVec3::new(-2.0, 2.5, 1.0), DVec3::X);
        assert!(lop_cast(&field, &cells, 0, &over, LopSteps { linear: 8, binary: 5 }).is_none());
    }
}
