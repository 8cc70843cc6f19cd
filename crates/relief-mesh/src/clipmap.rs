//! Geometry clipmaps (Losasso & Hoppe 2004; Asirvatham & Hoppe, GPU Gems 2 ch. 2): nested
//! square grids around the viewer, each twice as coarse as the one inside it, with their heights
//! from a 2x2-averaging pyramid and geomorphed to the coarser level near their outer border;
//! the comparison renderer of the hybrid paper's section 5.2, triangulated per frame into an
//! [`IndexedMesh`] the rasterizer draws.

use crate::mesh_builder::MeshBuilder;
use crate::{HeightPyramid, IndexedMesh, MeshError};
use rayon::prelude::*;
use relief_core::{Camera, DVec3, GridGeometry, HeightField, SampleRegion};

/// The parameters of a [`Clipmap`]; the default is the paper's: n = 511, 11 levels,
/// transition n / 10.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClipmapParams {
    /// Vertices per side of every level's grid, `2^k - 1` and at least 15.
    pub ring_vertices: usize,
    /// Number of levels (level `l` has a vertex every `2^l` samples), 1..=24.
    pub levels: usize,
    /// Width in vertices of the transition region at each level's outer border, where heights
    /// morph to the coarser level's; at least 1 and less than `(ring_vertices - 1) / 2 - 2`.
    pub transition: usize,
}

impl Default for ClipmapParams {
    fn default() -> Self {
        ClipmapParams { ring_vertices: 511, levels: 11, transition: 511 / 10 }
    }
}

impl ClipmapParams {
    /// Checks the parameters (see the fields).
    pub fn validate(&self) -> Result<(), MeshError> {
        let n = self.ring_vertices;
        let bad = |name, reason: String| Err(MeshError::Parameter { name, reason });
        if n < 15 || !(n + 1).is_power_of_two() {
            return bad("clipmap ring size", format!("{n} vertices is not 2^k - 1 >= 15"));
        }
        if !(1..=24).contains(&self.levels) {
            return bad("clipmap levels", format!("{} is outside 1..=24", self.levels));
        }
        if self.transition == 0 || self.transition + 2 >= (n - 1) / 2 {
            return bad(
                "clipmap transition",
                format!("{} vertices is outside 1..{}", self.transition, (n - 1) / 2 - 2),
            );
        }
        Ok(())
    }
}

/// Geometry clipmaps of a height field: the pyramid its levels sample, and the per-frame mesh.
///
/// Level 0 is the `triangles` surface itself (vertices at the samples, split along the lower
/// diagonal); level `l` has a vertex every `2^l` samples with the height of the pyramid's
/// level `l` there, its origin snapped to the coarser level's grid (a multiple of `2^(l+1)`)
/// so that its border lies on the coarser level's vertices. Near its outer border a level's
/// heights morph linearly to the coarser level's surface (fully at the border), and zero-area
/// triangles along each border join the two levels' edges, so the mesh has no crack. The
/// clipmap covers the samples' footprint of the field (as the `triangles` surface), squares
/// across its border clipped to it, as far as its coarsest level reaches:
/// `(ring_vertices - 1) 2^(levels - 1)` samples around the viewer (522 240 with the
/// defaults). Holes are not honoured (their stored value is the lowest sample). It has no
/// walls or bottom: it is meant to be seen from above.
///
/// ```
/// use relief_core::{Camera, DVec3, GridGeometry, HeightField};
/// use relief_mesh::{Clipmap, ClipmapParams};
/// let field = HeightField::new(64, 64, vec![1.0; 64 * 64], GridGeometry::unit()).unwrap();
/// let params = ClipmapParams { ring_vertices: 15, levels: 4, transition: 3 };
/// let clipmap = Clipmap::new(&field, params).unwrap();
/// let camera = Camera::look_at(DVec3::new(10.0, 10.0, 20.0), DVec3::new(40.0, 40.0, 0.0),
///     DVec3::Z, 60.0, 64, 48).unwrap();
/// let mesh = clipmap.mesh(&camera);
/// assert!(mesh.triangle_count() > 0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Clipmap {
    params: ClipmapParams,
    pyramid: HeightPyramid,
    geometry: GridGeometry,
    width: usize,
    height: usize,
}

/// One level of a frame: its origin (sample coordinates of vertex (0, 0)), spacing, and the
/// final heights of its `n x n` vertices.
struct Level {
    origin: [i64; 2],
    spacing: i64,
    heights: Vec<f64>,
}

impl Clipmap {
    /// The clipmap of `field` with `params` (its pyramid built here).
    pub fn new(field: &HeightField, params: ClipmapParams) -> Result<Self, MeshError> {
        params.validate()?;
        Ok(Clipmap {
            params,
            pyramid: HeightPyramid::new(field, params.levels),
            geometry: *field.geometry(),
            width: field.width(),
            height: field.height(),
        })
    }

    /// Takes the samples of `region` from `field` again after an edit (the pyramid above them
    /// is updated). Fails when the field's size differs from the clipmap's.
    pub fn update(&mut self, field: &HeightField, region: SampleRegion) -> Result<(), MeshError> {
        if (field.width(), field.height()) != (self.width, self.height) {
            return Err(MeshError::Parameter {
                name: "field",
                reason: format!(
                    "{}x{} differs from the clipmap's {}x{}",
                    field.width(),
                    field.height(),
                    self.width,
                    self.height
                ),
            });
        }
        self.geometry = *field.geometry();
        self.pyramid.update(field, region);
        Ok(())
    }

    /// The parameters.
    pub fn params(&self) -> ClipmapParams {
        self.params
    }

    /// The height pyramid the levels sample.
    pub fn pyramid(&self) -> &HeightPyramid {
        &self.pyramid
    }

    /// The frame's mesh for `camera`: the rings centred on the eye's ground position.
    pub fn mesh(&self, camera: &Camera) -> IndexedMesh {
        let eye = camera.eye();
        let g = &self.geometry;
        let x = (eye.x - g.origin.x) / g.dx - 0.5;
        let y = (eye.y - g.origin.y) / g.dy - 0.5;
        self.mesh_around(x, y)
    }

    /// The mesh of the rings centred on sample coordinates `(x, y)` (sample (c, r) at
    /// `(c, r)`), in world coordinates.
    pub fn mesh_around(&self, x: f64, y: f64) -> IndexedMesh {
        let n = self.params.ring_vertices;
        let half = ((n - 1) / 2) as i64;
        let (w, h) = (self.width as i64, self.height as i64);
        let centre = [x.clamp(-1e9, 1e9), y.clamp(-1e9, 1e9)];
        // Levels up to the first whose grid covers the whole field: coarser ones add nothing.
        let mut origins = Vec::new();
        for l in 0..self.params.levels {
            let s = 1i64 << l;
            let snap = |v: f64| ((v - (half * s) as f64) / (2 * s) as f64).floor() as i64 * 2 * s;
            let origin = [snap(centre[0]), snap(centre[1])];
            origins.push(origin);
            let end = [origin[0] + 2 * half * s, origin[1] + 2 * half * s];
            if origin[0] <= 0 && origin[1] <= 0 && end[0] >= w - 1 && end[1] >= h - 1 {
                break;
            }
        }
        let levels = self.level_heights(&origins, centre);
        // Each level's triangles apart (in parallel), then concatenated in level order.
        let parts: Vec<MeshBuilder> = (0..levels.len())
            .into_par_iter()
            .map(|l| {
                let mut part = MeshBuilder::default();
                let finer = l.checked_sub(1).map(|f| &levels[f]);
                self.triangulate(&mut part, &levels[l], finer);
                if let Some(finer) = finer {
                    self.join(&mut part, finer);
                }
                part
            })
            .collect();
        let mut mesh = MeshBuilder::default();
        for part in parts {
            let base = mesh.positions.len() as u32;
            mesh.positions.extend_from_slice(&part.positions);
            mesh.triangles.extend(part.triangles.iter().map(|t| t.map(|v| v + base)));
        }
        mesh.finish()
    }

    /// Every level's final heights, coarsest first computed, each finer level morphed to the
    /// next coarser one near its border.
    fn level_heights(&self, origins: &[[i64; 2]], centre: [f64; 2]) -> Vec<Level> {
        let n = self.params.ring_vertices;
        let half = ((n - 1) / 2) as f64;
        let transition = self.params.transition as f64;
        let mut levels: Vec<Level> = Vec::with_capacity(origins.len());
        for (l, &origin) in origins.iter().enumerate().rev() {
            let s = 1i64 << l;
            let coarser = levels.last();
            let mut heights = vec![0.0; n * n];
            heights.par_chunks_mut(n).enumerate().for_each(|(j, row)| {
                for (i, height) in row.iter_mut().enumerate() {
                    let (x, y) = (origin[0] + i as i64 * s, origin[1] + j as i64 * s);
                    let (cx, cy) = self.clamp(x, y);
                    let fine = self.pyramid.height_at(l, cx as f64, cy as f64);
                    let Some(coarse_level) = coarser else {
                        *height = fine;
                        continue;
                    };
                    let morph = |v: i64, c: f64| {
                        let d = ((v as f64 - c) / s as f64).abs();
                        ((d - (half - transition - 2.0)) / transition).clamp(0.0, 1.0)
                    };
                    let border = i == 0 || j == 0 || i == n - 1 || j == n - 1;
                    let alpha =
                        if border { 1.0 } else { morph(x, centre[0]).max(morph(y, centre[1])) };
                    *height = if alpha <= 0.0 {
                        fine
                    } else {
                        let coarse = coarse_level.surface(n, x, y);
                        if alpha >= 1.0 {
                            coarse
                        } else {
                            (1.0 - alpha) * fine + alpha * coarse
                        }
                    };
                }
            });
            levels.push(Level { origin, spacing: s, heights });
        }
        levels.reverse();
        levels
    }

    /// Sample coordinates clamped into the field.
    fn clamp(&self, x: i64, y: i64) -> (i64, i64) {
        (x.clamp(0, self.width as i64 - 1), y.clamp(0, self.height as i64 - 1))
    }

    /// The world vertex of sample coordinates (x, y) at height `z` (sample units).
    fn world(&self, x: i64, y: i64, z: f64) -> DVec3 {
        self.world_at(DVec3::new(x as f64, y as f64, z))
    }

    /// The world point of sample coordinates `p` (x, y in samples, z in sample units).
    fn world_at(&self, p: DVec3) -> DVec3 {
        self.geometry.point_to_world(DVec3::new(p.x + 0.5, p.y + 0.5, p.z))
    }

    /// The part of triangle `corners` (sample coordinates) over the samples' footprint
    /// `[0, w - 1] x [0, h - 1]`, as a fan. Points on an edge are computed from its endpoints
    /// in a fixed order, so the two triangles sharing an edge clip it to the same point.
    fn clipped_triangle(&self, mesh: &mut MeshBuilder, corners: [DVec3; 3]) {
        let limits = [
            (0, 0.0, false),
            (0, (self.width - 1) as f64, true),
            (1, 0.0, false),
            (1, (self.height - 1) as f64, true),
        ];
        let mut polygon: Vec<DVec3> = corners.to_vec();
        for (axis, value, upper) in limits {
            let inside = |p: &DVec3| if upper { p[axis] <= value } else { p[axis] >= value };
            let mut clipped = Vec::with_capacity(polygon.len() + 1);
            for k in 0..polygon.len() {
                let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                if inside(&a) {
                    clipped.push(a);
                }
                if inside(&a) != inside(&b) {
                    let (p, q) = if (a.x, a.y) < (b.x, b.y) { (a, b) } else { (b, a) };
                    let t = (value - p[axis]) / (q[axis] - p[axis]);
                    let mut point = p + t * (q - p);
                    point[axis] = value;
                    clipped.push(point);
                }
            }
            polygon = clipped;
            if polygon.len() < 3 {
                return;
            }
        }
        let ids: Vec<u32> = polygon.iter().map(|&p| mesh.vertex(self.world_at(p))).collect();
        for k in 1..ids.len() - 1 {
            mesh.triangle(ids[0], ids[k], ids[k + 1]);
        }
    }

    /// The level's squares that lie in the field and outside the finer level, two triangles
    /// each, split along the lower diagonal, counter-clockwise from above.
    fn triangulate(&self, mesh: &mut MeshBuilder, level: &Level, finer: Option<&Level>) {
        let n = self.params.ring_vertices;
        let (w, h) = (self.width as i64, self.height as i64);
        let s = level.spacing;
        let hole = finer.map(|f| {
            let size = (n as i64 - 1) * f.spacing;
            [f.origin[0], f.origin[1], f.origin[0] + size, f.origin[1] + size]
        });
        let mut index = vec![u32::MAX; n * n];
        let mut vertex = |mesh: &mut MeshBuilder, i: usize, j: usize| {
            let k = i + j * n;
            if index[k] == u32::MAX {
                let (x, y) = (level.origin[0] + i as i64 * s, level.origin[1] + j as i64 * s);
                index[k] = mesh.vertex(self.world(x, y, level.heights[k]));
            }
            index[k]
        };
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let (x0, y0) = (level.origin[0] + i as i64 * s, level.origin[1] + j as i64 * s);
                let (x1, y1) = (x0 + s, y0 + s);
                if x0 >= w - 1 || y0 >= h - 1 || x1 <= 0 || y1 <= 0 {
                    continue;
                }
                if hole.is_some_and(|[hx0, hy0, hx1, hy1]| {
                    x0 >= hx0 && x1 <= hx1 && y0 >= hy0 && y1 <= hy1
                }) {
                    continue;
                }
                let z = |di: usize, dj: usize| level.heights[i + di + (j + dj) * n];
                let lower = z(0, 0) + z(1, 1) <= z(1, 0) + z(0, 1);
                if x0 < 0 || y0 < 0 || x1 > w - 1 || y1 > h - 1 {
                    // Across the footprint's border: clipped to it.
                    let p = |di: usize, dj: usize| {
                        let (x, y) = (if di == 0 { x0 } else { x1 }, if dj == 0 { y0 } else { y1 });
                        DVec3::new(x as f64, y as f64, z(di, dj))
                    };
                    let (p00, p10, p01, p11) = (p(0, 0), p(1, 0), p(0, 1), p(1, 1));
                    let halves = if lower {
                        [[p00, p10, p11], [p00, p11, p01]]
                    } else {
                        [[p00, p10, p01], [p10, p11, p01]]
                    };
                    for corners in halves {
                        self.clipped_triangle(mesh, corners);
                    }
                    continue;
                }
                let [v00, v10, v01, v11] = [
                    vertex(mesh, i, j),
                    vertex(mesh, i + 1, j),
                    vertex(mesh, i, j + 1),
                    vertex(mesh, i + 1, j + 1),
                ];
                if lower {
                    mesh.triangle(v00, v10, v11);
                    mesh.triangle(v00, v11, v01);
                } else {
                    mesh.triangle(v00, v10, v01);
                    mesh.triangle(v10, v11, v01);
                }
            }
        }
    }

    /// Zero-area triangles (A, V, B) along the finer level's border, where its vertex V lies
    /// on the coarser level's edge A-B: the edges A-V and V-B of the finer level and A-B of the
    /// coarser one then close up exactly (no T-junction crack).
    fn join(&self, mesh: &mut MeshBuilder, finer: &Level) {
        let n = self.params.ring_vertices;
        let (w, h) = (self.width as i64, self.height as i64);
        let s = finer.spacing;
        let at = |mesh: &mut MeshBuilder, i: usize, j: usize| {
            let (x, y) = (finer.origin[0] + i as i64 * s, finer.origin[1] + j as i64 * s);
            mesh.vertex(self.world(x, y, finer.heights[i + j * n]))
        };
        let inside = |i: usize, j: usize| {
            let (x, y) = (finer.origin[0] + i as i64 * s, finer.origin[1] + j as i64 * s);
            (0..w).contains(&x) && (0..h).contains(&y)
        };
        for k in (0..n - 2).step_by(2) {
            for (a, v, b) in [
                ((k, 0), (k + 1, 0), (k + 2, 0)),
                ((n - 1, k), (n - 1, k + 1), (n - 1, k + 2)),
                ((k + 2, n - 1), (k + 1, n - 1), (k, n - 1)),
                ((0, k + 2), (0, k + 1), (0, k)),
            ] {
                if inside(v.0, v.1) {
                    let (a, v, b) = (at(mesh, a.0, a.1), at(mesh, v.0, v.1), at(mesh, b.0, b.1));
                    mesh.triangle(a, v, b);
                }
            }
        }
    }
}

impl Level {
    /// The level's surface at sample coordinates (x, y) inside it: a vertex's height, or
    /// the mean of the two vertices around a point halfway along an edge or a square's
    /// diagonal.
    fn surface(&self, n: usize, x: i64, y: i64) -> f64 {
        let s = self.spacing;
        let (dx, dy) = (x - self.origin[0], y - self.origin[1]);
        let (i, j) =
            ((dx.div_euclid(s)).clamp(0, n as i64 - 1), (dy.div_euclid(s)).clamp(0, n as i64 - 1));
        let (i, j) = (i as usize, j as usize);
        let (odd_x, odd_y) =
            (dx.rem_euclid(s) != 0 && i + 1 < n, dy.rem_euclid(s) != 0 && j + 1 < n);
        let z = |i: usize, j: usize| self.heights[i + j * n];
        match (odd_x, odd_y) {
            (false, false) => z(i, j),
            (true, false) => 0.5 * (z(i, j) + z(i + 1, j)),
            (false, true) => 0.5 * (z(i, j) + z(i, j + 1)),
            // The middle of a square lies on the diagonal its two triangles share.
            (true, true) => {
                let (a, b, c, d) = (z(i, j), z(i + 1, j), z(i, j + 1), z(i + 1, j + 1));
                if relief_core::splits_along_ad(a, b, c, d) {
                    0.5 * (a + d)
                } else {
                    0.5 * (b + c)
                }
            }
        }
    }
}
