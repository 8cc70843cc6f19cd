//! The reference the suite holds every tracer against: the ray tested directly against every
//! face of the solid in world space, densely, with no traversal, no cell space and nothing
//! shared with relief-trace's tracers. Boxes are slab-tested texel by texel; the `triangles`
//! surface is each square's two triangles (split as [`relief_core::splits_along_ad`] says)
//! with Möller-Trumbore, its walls along the edges no square lies beyond, and its floor.

use relief_core::{splits_along_ad, DVec2, DVec3, HeightField, Ray, Surface};

/// How far down the solid of a height field reaches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Floor {
    /// Down to the field's lowest sample ([`HeightField::min_sample`]), as a height field's
    /// tracers clip it.
    LowestSample,
    /// Down forever, as an MLHM's lowest columns (only with [`Surface::Boxes`]).
    Unbounded,
}

/// The reference's first hit of a ray.
#[derive(Debug, Clone, PartialEq)]
pub struct Expected {
    /// The smallest parameter in the ray's range inside the solid.
    pub t: f64,
    /// The unit normals of every face the ray meets at `t` (more than one at an edge or a
    /// corner), facing against the ray; the reversed ray direction when it starts inside.
    pub normals: Vec<DVec3>,
}

/// The reference first hit of `ray` with the solid of `surface` over `field` reaching down to
/// `floor`, with every face grown outwards by `margin` world units (shrunk when negative): a
/// ray that grazes an edge within `|margin|` hits with a positive margin and misses with a
/// negative one.
pub fn first_hit(
    field: &HeightField,
    surface: Surface,
    floor: Floor,
    ray: &Ray,
    margin: f64,
) -> Option<Expected> {
    let floor_z = match floor {
        Floor::LowestSample => field.min_sample() as f64 * field.geometry().z_scale,
        Floor::Unbounded => f64::NEG_INFINITY,
    };
    let mut faces = Faces::default();
    match surface {
        Surface::Boxes => boxes(field, floor_z, ray, margin, &mut faces),
        Surface::Triangles => triangles(field, floor_z, ray, margin, &mut faces),
    }
    faces.first()
}

/// The faces met so far: parameter and normal.
#[derive(Default)]
struct Faces(Vec<(f64, DVec3)>);

impl Faces {
    /// The face met at `t` with `normal`, turned against the ray's direction `dir`.
    fn met(&mut self, t: f64, normal: DVec3, dir: DVec3) {
        let n = normal.normalize();
        self.0.push((t, if n.dot(dir) > 0.0 { -n } else { n }));
    }

    /// The ray starts inside at `t_min`.
    fn inside(&mut self, ray: &Ray) {
        self.0.push((ray.t_min, -ray.dir.normalize()));
    }

    /// The smallest parameter with the normals of every face within a rounding tie of it.
    fn first(self) -> Option<Expected> {
        let t = self.0.iter().map(|f| f.0).fold(f64::INFINITY, f64::min);
        let tie = 1e-9 * (1.0 + t.abs());
        let normals = self.0.iter().filter(|f| f.0 <= t + tie).map(|f| f.1).collect();
        t.is_finite().then_some(Expected { t, normals })
    }
}

/// Every texel's box from `floor_z` up to its height.
fn boxes(field: &HeightField, floor_z: f64, ray: &Ray, margin: f64, faces: &mut Faces) {
    let g = field.geometry();
    for row in 0..field.height() {
        for col in 0..field.width() {
            if field.is_hole(col, row) {
                continue;
            }
            let lo =
                DVec3::new(g.origin.x + col as f64 * g.dx, g.origin.y + row as f64 * g.dy, floor_z);
            let hi = DVec3::new(
                g.origin.x + (col + 1) as f64 * g.dx,
                g.origin.y + (row + 1) as f64 * g.dy,
                field.sample(col, row) as f64 * g.z_scale,
            );
            slab(lo - margin, hi + margin, ray, faces);
        }
    }
}

/// The ray against the box `[lo, hi]`: where it enters, through which faces, or that it starts
/// inside.
fn slab(lo: DVec3, hi: DVec3, ray: &Ray, faces: &mut Faces) {
    if (0..3).any(|a| lo[a] > hi[a]) {
        return;
    }
    let (mut t0, mut t1) = (ray.t_min, ray.t_max);
    let mut entered: Vec<usize> = Vec::new();
    for a in 0..3 {
        let (o, d) = (ray.origin[a], ray.dir[a]);
        if d == 0.0 {
            if o < lo[a] || o > hi[a] {
                return;
            }
            continue;
        }
        let (p, q) = ((lo[a] - o) / d, (hi[a] - o) / d);
        let near = p.min(q);
        if near > t0 {
            t0 = near;
            entered.clear();
            entered.push(a);
        } else if near == t0 {
            // Through an edge, or from a point on the face: either face is the one entered.
            entered.push(a);
        }
        t1 = t1.min(p.max(q));
    }
    if t0 > t1 {
        return;
    }
    if entered.is_empty() || t0 == ray.t_min {
        faces.inside(ray);
    }
    for a in entered {
        faces.met(t0, -DVec3::AXES[a], ray.dir);
    }
}

/// The `triangles` surface: the squares between sample centres, their walls and floor.
fn triangles(field: &HeightField, floor_z: f64, ray: &Ray, margin: f64, faces: &mut Faces) {
    let (w, h) = (field.width(), field.height());
    if w < 2 || h < 2 {
        return;
    }
    let g = field.geometry();
    let start = ray.at(ray.t_min);
    if let Some(top) = surface_height(field, start.truncate(), margin) {
        if start.z >= floor_z - margin && start.z <= top + margin {
            faces.inside(ray);
        }
    }
    // Barycentric slack for a margin in world units.
    let slack = margin / g.dx.min(g.dy);
    for r in 0..h - 1 {
        for c in 0..w - 1 {
            let (ci, ri) = (c as isize, r as isize);
            if !square_exists(field, ci, ri) {
                continue;
            }
            let square = square_triangles(field, c, r);
            for triangle in square {
                // Grown upwards, out of the solid, by the margin.
                let raised = triangle.map(|v| v + DVec3::Z * margin);
                moller_trumbore(&raised, ray, slack, faces);
            }
            if floor_z.is_finite() {
                floor_square(&square, floor_z, ray, margin, faces);
            }
            let v = |i: usize, j: usize| vertex(field, c + i, r + j);
            let edges = [
                ((-1, 0), v(0, 0), v(0, 1)),
                ((1, 0), v(1, 0), v(1, 1)),
                ((0, -1), v(0, 0), v(1, 0)),
                ((0, 1), v(0, 1), v(1, 1)),
            ];
            for ((di, dj), a, b) in edges {
                if !square_exists(field, ci + di, ri + dj) {
                    wall(a, b, floor_z, ray, margin, faces);
                }
            }
        }
    }
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

/// The two triangles over the square with lower-left sample (c, r).
fn square_triangles(field: &HeightField, c: usize, r: usize) -> [[DVec3; 3]; 2] {
    let (p00, p10) = (vertex(field, c, r), vertex(field, c + 1, r));
    let (p01, p11) = (vertex(field, c, r + 1), vertex(field, c + 1, r + 1));
    let samples = |x: usize, y: usize| field.sample(x, y) as f64;
    if splits_along_ad(samples(c, r), samples(c + 1, r), samples(c, r + 1), samples(c + 1, r + 1)) {
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

/// The highest surface height over world `p` within `margin` of it, if a square lies there.
fn surface_height(field: &HeightField, p: DVec2, margin: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for r in 0..field.height().saturating_sub(1) {
        for c in 0..field.width().saturating_sub(1) {
            if !square_exists(field, c as isize, r as isize) {
                continue;
            }
            if let Some(z) = height_in_square(&square_triangles(field, c, r), p, margin) {
                best = Some(best.map_or(z, |b: f64| b.max(z)));
            }
        }
    }
    best
}

/// The highest height of the triangles `square` over world `p` within `margin` of them.
fn height_in_square(square: &[[DVec3; 3]; 2], p: DVec2, margin: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for [a, b, d] in square {
        let det = (b.x - a.x) * (d.y - a.y) - (d.x - a.x) * (b.y - a.y);
        let l1 = ((p.x - a.x) * (d.y - a.y) - (d.x - a.x) * (p.y - a.y)) / det;
        let l2 = ((b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y)) / det;
        let l0 = 1.0 - l1 - l2;
        let slack = margin / (*b - *a).truncate().length().min((*d - *a).truncate().length());
        if l0 >= -slack && l1 >= -slack && l2 >= -slack {
            let z = l0 * a.z + l1 * b.z + l2 * d.z;
            best = Some(best.map_or(z, |b: f64| b.max(z)));
        }
    }
    best
}

/// The ray against a triangle, barycentric coordinates grown by `slack`.
fn moller_trumbore(tri: &[DVec3; 3], ray: &Ray, slack: f64, faces: &mut Faces) {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return;
    }
    let s = ray.origin - tri[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = ray.dir.dot(q) / det;
    if u < -slack || v < -slack || u + v > 1.0 + slack {
        return;
    }
    let t = e2.dot(q) / det;
    if t >= ray.t_min && t <= ray.t_max {
        faces.met(t, e1.cross(e2), ray.dir);
    }
}

/// The ray against the floor, lowered by `margin`, under the square of triangles `square`
/// (where the floor lies under the surface grown by `margin`).
fn floor_square(square: &[[DVec3; 3]; 2], floor_z: f64, ray: &Ray, margin: f64, faces: &mut Faces) {
    if ray.dir.z == 0.0 {
        return;
    }
    let t = (floor_z - margin - ray.origin.z) / ray.dir.z;
    let p = ray.at(t);
    if t < ray.t_min || t > ray.t_max {
        return;
    }
    if height_in_square(square, p.truncate(), margin).is_some_and(|top| p.z <= top + margin) {
        faces.met(t, DVec3::Z, ray.dir);
    }
}

/// The ray against the vertical wall under the edge from `a` to `b`, from `floor_z` up to the
/// edge.
fn wall(a: DVec3, b: DVec3, floor_z: f64, ray: &Ray, margin: f64, faces: &mut Faces) {
    let edge = (b - a).truncate();
    let normal = DVec2::new(edge.y, -edge.x);
    let across = normal.dot(ray.dir.truncate());
    if across == 0.0 {
        return;
    }
    let t = normal.dot((a - ray.origin).truncate()) / across;
    if t < ray.t_min || t > ray.t_max {
        return;
    }
    let p = ray.at(t);
    let s = (p.truncate() - a.truncate()).dot(edge) / edge.length_squared();
    let slack = margin / edge.length();
    if s < -slack || s > 1.0 + slack {
        return;
    }
    let top = a.z + s.clamp(0.0, 1.0) * (b.z - a.z);
    if p.z >= floor_z - margin && p.z <= top + margin {
        faces.met(t, normal.extend(0.0), ray.dir);
    }
}
