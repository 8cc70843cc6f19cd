//! An independent brute-force tracer: it intersects the ray with every face of the solid in
//! world space (slab tests for boxes, Möller-Trumbore for triangles and walls). It shares no
//! code with relief-trace's traversal and serves as the ground truth.

use relief_core::{DVec3, HeightField, Ray, Surface};

/// First parameter in the ray's range at which it is inside the solid of `surface`.
pub fn first_hit(field: &HeightField, surface: Surface, ray: &Ray) -> Option<f64> {
    match surface {
        Surface::Boxes => boxes(field, ray),
        Surface::Triangles => triangles(field, ray),
    }
}

fn boxes(field: &HeightField, ray: &Ray) -> Option<f64> {
    let g = field.geometry();
    let zmin = field.min_sample() as f64 * g.z_scale;
    let mut best: Option<f64> = None;
    for row in 0..field.height() {
        for col in 0..field.width() {
            if field.is_hole(col, row) {
                continue;
            }
            let lo =
                DVec3::new(g.origin.x + col as f64 * g.dx, g.origin.y + row as f64 * g.dy, zmin);
            let hi = DVec3::new(
                g.origin.x + (col + 1) as f64 * g.dx,
                g.origin.y + (row + 1) as f64 * g.dy,
                field.sample(col, row) as f64 * g.z_scale,
            );
            if let Some(t) = slab(lo, hi, ray) {
                best = Some(best.map_or(t, |b| b.min(t)));
            }
        }
    }
    best
}

fn slab(lo: DVec3, hi: DVec3, ray: &Ray) -> Option<f64> {
    let (mut t0, mut t1) = (ray.t_min, ray.t_max);
    for a in 0..3 {
        if ray.dir[a] == 0.0 {
            if ray.origin[a] < lo[a] || ray.origin[a] > hi[a] {
                return None;
            }
        } else {
            let (p, q) =
                ((lo[a] - ray.origin[a]) / ray.dir[a], (hi[a] - ray.origin[a]) / ray.dir[a]);
            t0 = t0.max(p.min(q));
            t1 = t1.min(p.max(q));
        }
    }
    (t0 <= t1).then_some(t0)
}

/// World vertex of sample (c, r).
fn vertex(field: &HeightField, c: usize, r: usize) -> DVec3 {
    let g = field.geometry();
    DVec3::new(
        g.origin.x + (c as f64 + 0.5) * g.dx,
        g.origin.y + (r as f64 + 0.5) * g.dy,
        field.sample(c, r) as f64 * g.z_scale,
    )
}

/// The two triangles over the square with lower-left sample (c, r), split on the lower diagonal.
fn square_triangles(field: &HeightField, c: usize, r: usize) -> [[DVec3; 3]; 2] {
    let (p00, p10) = (vertex(field, c, r), vertex(field, c + 1, r));
    let (p01, p11) = (vertex(field, c, r + 1), vertex(field, c + 1, r + 1));
    if p00.z + p11.z <= p10.z + p01.z {
        [[p00, p10, p11], [p00, p11, p01]]
    } else {
        [[p00, p10, p01], [p10, p11, p01]]
    }
}

/// Whether the square with lower-left sample (c, r) exists: inside the grid, no corner a hole.
fn square_exists(field: &HeightField, c: isize, r: isize) -> bool {
    let (w, h) = (field.width() as isize, field.height() as isize);
    c >= 0
        && r >= 0
        && c + 1 < w
        && r + 1 < h
        && [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .all(|(i, j)| !field.is_hole((c + i) as usize, (r + j) as usize))
}

/// Surface height above world (x, y) by barycentric interpolation in the triangle containing it.
fn surface_height(field: &HeightField, x: f64, y: f64) -> Option<f64> {
    let g = field.geometry();
    let (gx, gy) = ((x - g.origin.x) / g.dx - 0.5, (y - g.origin.y) / g.dy - 0.5);
    let (cells_x, cells_y) = (field.width() - 1, field.height() - 1);
    if !(gx >= 0.0 && gy >= 0.0 && gx <= cells_x as f64 && gy <= cells_y as f64) {
        return None;
    }
    let c = (gx.floor() as usize).min(cells_x - 1);
    let r = (gy.floor() as usize).min(cells_y - 1);
    if !square_exists(field, c as isize, r as isize) {
        return None;
    }
    let mut best: Option<f64> = None;
    for tri in square_triangles(field, c, r) {
        let [a, b, cc] = tri;
        let det = (b.x - a.x) * (cc.y - a.y) - (cc.x - a.x) * (b.y - a.y);
        let l1 = ((x - a.x) * (cc.y - a.y) - (cc.x - a.x) * (y - a.y)) / det;
        let l2 = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
        let l0 = 1.0 - l1 - l2;
        if l0 >= -1e-12 && l1 >= -1e-12 && l2 >= -1e-12 {
            let z = l0 * a.z + l1 * b.z + l2 * cc.z;
            best = Some(best.map_or(z, |b: f64| b.max(z)));
        }
    }
    best
}

fn triangles(field: &HeightField, ray: &Ray) -> Option<f64> {
    let (w, h) = (field.width(), field.height());
    if w < 2 || h < 2 {
        return None;
    }
    let zmin = field.min_sample() as f64 * field.geometry().z_scale;
    let start = ray.at(ray.t_min);
    if let Some(top) = surface_height(field, start.x, start.y) {
        if start.z >= zmin && start.z <= top {
            return Some(ray.t_min);
        }
    }
    let floor = |p: DVec3| DVec3::new(p.x, p.y, zmin);
    let mut tris: Vec<[DVec3; 3]> = Vec::new();
    for r in 0..h - 1 {
        for c in 0..w - 1 {
            let (ci, ri) = (c as isize, r as isize);
            if !square_exists(field, ci, ri) {
                continue;
            }
            tris.extend(square_triangles(field, c, r));
            let v = |i: usize, j: usize| vertex(field, c + i, r + j);
            // The bottom, and a wall under every edge with no square beyond it.
            tris.push([floor(v(0, 0)), floor(v(1, 0)), floor(v(1, 1))]);
            tris.push([floor(v(0, 0)), floor(v(1, 1)), floor(v(0, 1))]);
            let edges = [
                ((-1, 0), v(0, 0), v(0, 1)),
                ((1, 0), v(1, 0), v(1, 1)),
                ((0, -1), v(0, 0), v(1, 0)),
                ((0, 1), v(0, 1), v(1, 1)),
            ];
            for ((di, dj), a, b) in edges {
                if !square_exists(field, ci + di, ri + dj) {
                    tris.push([floor(a), floor(b), b]);
                    tris.push([floor(a), b, a]);
                }
            }
        }
    }
    tris.iter()
        .filter_map(|t| moller_trumbore(t, ray))
        .fold(None, |best: Option<f64>, t| Some(best.map_or(t, |b| b.min(t))))
}

fn moller_trumbore(tri: &[DVec3; 3], ray: &Ray) -> Option<f64> {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = ray.origin - tri[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = ray.dir.dot(q) / det;
    let eps = 1e-10;
    if u < -eps || v < -eps || u + v > 1.0 + eps {
        return None;
    }
    let t = e2.dot(q) / det;
    (t >= ray.t_min && t <= ray.t_max).then_some(t)
}
