//! Smooth shading normals of the `triangles` surface: a normal per sample from the height
//! field's gradient, interpolated over each triangle as a DEM viewer shades it.
//!
//! The exact surface stays the triangles' (its facets' normals are what tracers return and
//! what depth and normal outputs hold); these normals only change how light falls on it.

use crate::{splits_along_ad, HeightField};
use glam::DVec3;

/// A surface that gives a smooth shading normal at a point on it, as the `triangles` surface
/// of a height field does ([`HeightField::smooth_normal_at`]); a tiled terrain answers with
/// the tile drawn there.
pub trait SmoothNormals: Send + Sync {
    /// The unit smooth shading normal at the world point `position` on the surface (its x
    /// and y place it; z is not read), or `None` where there is none: outside the surface's
    /// footprint, over a hole, or where a sample has no neighbour to take a gradient from.
    fn smooth_normal(&self, position: DVec3) -> Option<DVec3>;
}

impl SmoothNormals for HeightField {
    fn smooth_normal(&self, position: DVec3) -> Option<DVec3> {
        self.smooth_normal_at(position.x, position.y)
    }
}

/// How far (in texels) outside the triangles' footprint a point may lie and still be taken
/// as on its edge: a hit on the border sample line rebuilt from an `f32` distance.
const EDGE_TOLERANCE: f64 = 1e-3;

impl HeightField {
    /// The unit normal of the height field at sample (col, row) from its gradient in world
    /// units: central differences of the neighbours' heights (`z_scale` times the samples)
    /// over the spacing `dx` or `dy`, one-sided where a neighbour is off the grid or a hole.
    /// `None` when the sample is a hole or off the grid, or has no valid neighbour along x or
    /// along y (a sample in a one-sample-wide strip between holes).
    pub fn sample_normal(&self, col: usize, row: usize) -> Option<DVec3> {
        let (w, h) = (self.width(), self.height());
        if col >= w || row >= h || self.is_hole(col, row) {
            return None;
        }
        if self.holes().is_none() && w >= 2 && h >= 2 {
            return Some(self.normal_without_holes(col, row));
        }
        let g = self.geometry();
        let valid = |c: usize, r: usize| !self.is_hole(c, r);
        let z = |c: usize, r: usize| self.sample(c, r) as f64 * g.z_scale;
        // The difference between the two neighbours along one axis that exist, over their
        // distance in world units.
        let slope = |lo: Option<(usize, usize)>, hi: Option<(usize, usize)>, spacing: f64| {
            let lo = lo.filter(|&(c, r)| valid(c, r));
            let hi = hi.filter(|&(c, r)| valid(c, r));
            match (lo, hi) {
                (Some(l), Some(u)) => Some((z(u.0, u.1) - z(l.0, l.1)) / (2.0 * spacing)),
                (Some(l), None) => Some((z(col, row) - z(l.0, l.1)) / spacing),
                (None, Some(u)) => Some((z(u.0, u.1) - z(col, row)) / spacing),
                (None, None) => None,
            }
        };
        let west = col.checked_sub(1).map(|c| (c, row));
        let east = (col + 1 < w).then_some((col + 1, row));
        let south = row.checked_sub(1).map(|r| (col, r));
        let north = (row + 1 < h).then_some((col, row + 1));
        let gx = slope(west, east, g.dx)?;
        let gy = slope(south, north, g.dy)?;
        let n = DVec3::new(-gx, -gy, 1.0).normalize();
        n.is_finite().then_some(n)
    }

    /// [`HeightField::sample_normal`] of a field without holes, at least two samples a side:
    /// the same differences without looking for holes (the shading's hot path).
    #[inline]
    fn normal_without_holes(&self, col: usize, row: usize) -> DVec3 {
        let (w, h, s, g) = (self.width(), self.height(), self.samples(), self.geometry());
        let z = |k: usize| s[k] as f64 * g.z_scale;
        let (west, east) = (col.saturating_sub(1), (col + 1).min(w - 1));
        let (south, north) = (row.saturating_sub(1), (row + 1).min(h - 1));
        let gx = (z(east + row * w) - z(west + row * w)) / ((east - west) as f64 * g.dx);
        let gy = (z(col + north * w) - z(col + south * w)) / ((north - south) as f64 * g.dy);
        DVec3::new(-gx, -gy, 1.0).normalize()
    }

    /// The smooth shading normal of the `triangles` surface at world `(x, y)`: the
    /// [`HeightField::sample_normal`]s of the three corners of the triangle over the point
    /// (the square's split as [`splits_along_ad`] decides), interpolated by the point's
    /// barycentric weights and normalized. On a plane it is the plane's normal; across every
    /// triangle edge it is continuous. `None` outside the triangles' footprint (the sample
    /// centres' rectangle), over a square with a hole at a corner, or where a corner has no
    /// normal.
    pub fn smooth_normal_at(&self, x: f64, y: f64) -> Option<DVec3> {
        let (w, h) = (self.width(), self.height());
        if w < 2 || h < 2 {
            return None;
        }
        let g = self.geometry();
        let u = (x - g.origin.x) / g.dx - 0.5;
        let v = (y - g.origin.y) / g.dy - 0.5;
        let (u_max, v_max) = ((w - 1) as f64, (h - 1) as f64);
        let outside = |t: f64, max: f64| !(-EDGE_TOLERANCE..=max + EDGE_TOLERANCE).contains(&t);
        if outside(u, u_max) || outside(v, v_max) {
            return None;
        }
        let c = u.floor().clamp(0.0, u_max - 1.0);
        let r = v.floor().clamp(0.0, v_max - 1.0);
        let (fu, fv) = ((u - c).clamp(0.0, 1.0), (v - r).clamp(0.0, 1.0));
        let (c, r) = (c as usize, r as usize);
        let corners = [(c, r), (c + 1, r), (c, r + 1), (c + 1, r + 1)];
        if self.holes().is_some() && corners.iter().any(|&(c, r)| self.is_hole(c, r)) {
            return None;
        }
        let s = corners.map(|(c, r)| self.sample(c, r) as f64);
        // Corners a (c, r), b (c+1, r), cc (c, r+1), d (c+1, r+1) and their weights.
        let weights: [(usize, f64); 3] = if splits_along_ad(s[0], s[1], s[2], s[3]) {
            if fu >= fv {
                [(0, 1.0 - fu), (1, fu - fv), (3, fv)]
            } else {
                [(0, 1.0 - fv), (2, fv - fu), (3, fu)]
            }
        } else if fu + fv <= 1.0 {
            [(0, 1.0 - fu - fv), (1, fu), (2, fv)]
        } else {
            [(1, 1.0 - fv), (2, 1.0 - fu), (3, fu + fv - 1.0)]
        };
        let mut n = DVec3::ZERO;
        for (corner, weight) in weights {
            let (cc, rr) = corners[corner];
            n += self.sample_normal(cc, rr)? * weight;
        }
        let n = n.normalize_or_zero();
        (n.z > 0.0).then_some(n)
    }
}

#[cfg(test)]
mod tests {
    use crate::{GridGeometry, HeightField};
    use glam::{DVec2, DVec3};

    fn field(
        w: usize,
        h: usize,
        geometry: GridGeometry,
        z: impl Fn(f64, f64) -> f64,
    ) -> HeightField {
        let samples = (0..w * h)
            .map(|k| {
                let (c, r) = ((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
                let (x, y) =
                    (geometry.origin.x + c * geometry.dx, geometry.origin.y + r * geometry.dy);
                (z(x, y) / geometry.z_scale) as f32
            })
            .collect();
        HeightField::new(w, h, samples, geometry).unwrap()
    }

    #[test]
    fn a_tilted_plane_has_its_own_normal_everywhere() {
        let geometry =
            GridGeometry { dx: 2.0, dy: 0.5, z_scale: 3.0, origin: DVec2::new(100.0, -40.0) };
        let f = field(9, 7, geometry, |x, y| 0.3 * x - 0.7 * y + 5.0);
        let want = DVec3::new(-0.3, 0.7, 1.0).normalize();
        for (c, r) in [(0, 0), (8, 6), (4, 3), (0, 6)] {
            assert!((f.sample_normal(c, r).unwrap() - want).length() < 1e-5, "sample {c},{r}");
        }
        for k in 0..50 {
            let (x, y) = (101.0 + 0.31 * k as f64 % 16.0, -39.75 + 0.057 * k as f64);
            let n = f.smooth_normal_at(x, y).unwrap();
            assert!((n - want).length() < 1e-5, "at {x}, {y}: {n}");
        }
    }

    #[test]
    fn holes_give_one_sided_differences_and_no_normal_over_them() {
        let geometry = GridGeometry::unit();
        let f = field(5, 3, geometry, |x, _| x * x);
        let mut holes = vec![false; 15];
        holes[3 + 5] = true; // (3, 1)
        let f = f.with_holes(holes).unwrap();
        // Sample (2, 1): east is a hole, so the west difference: (2.5^2 - 1.5^2) / 1.
        let n = f.sample_normal(2, 1).unwrap();
        let want = DVec3::new(-(2.5f64.powi(2) - 1.5f64.powi(2)), 0.0, 1.0).normalize();
        assert!((n - want).length() < 1e-6, "{n}");
        assert_eq!(f.sample_normal(3, 1), None);
        // Squares with the hole at a corner have no smooth normal; others do.
        assert_eq!(f.smooth_normal_at(3.2, 1.2), None);
        assert!(f.smooth_normal_at(1.2, 1.2).is_some());
        // Outside the sample centres' rectangle there is none.
        assert_eq!(f.smooth_normal_at(0.49, 1.0), None);
        assert!(f.smooth_normal_at(0.5, 1.0).is_some());
    }
}
