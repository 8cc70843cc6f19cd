//! The resolve of a rasterized frame: each pixel's triangle id (a [`RasterTarget`]) turned
//! into a G-buffer pixel, in one parallel pass over strips of rows: the exact hit of the
//! pixel's camera ray with the triangle's plane, the mesh's smooth normal and colour
//! interpolated there.

use crate::render::HitEncoder;
use crate::{GBuffer, GBufferPixel};
use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec3, Ray};
use relief_mesh::{IndexedMesh, RasterTarget};
use relief_trace::Hit;

/// The side of the square blocks of pixels resolved together.
const BLOCK: usize = 32;

/// Meshes of colour (3 floats) then normal (3 floats) attributes a vertex, drawn into one
/// target one after the other: mesh `m`'s triangle `k` has id `first_ids[m] + k`.
pub(crate) struct DrawnMeshes<'a> {
    /// The meshes.
    pub meshes: &'a [IndexedMesh],
    /// The first id of each mesh, increasing.
    pub first_ids: &'a [u32],
}

impl DrawnMeshes<'_> {
    /// The mesh and triangle of id `id`.
    #[inline]
    fn triangle(&self, id: u32) -> (&IndexedMesh, u32) {
        let m = self.first_ids.iter().rposition(|&first| first <= id).unwrap_or(0);
        (&self.meshes[m], id - self.first_ids[m])
    }
}

/// Writes every pixel of `gbuffer` from `target` (the same size): a pixel that shows no
/// triangle is a miss; one that shows a triangle gets the hit of its camera ray with the
/// triangle's plane (distance, position, texture coordinates over `bounds`, footprint), the
/// mesh's smooth normal interpolated there (the geometric one where the smooth normal is
/// degenerate or faces away from the ray) and its colour as material weights `[r, g, b, 1]`.
pub(crate) fn resolve_triangles(
    gbuffer: &mut GBuffer,
    camera: &Camera,
    bounds: &Aabb,
    target: &RasterTarget,
    drawn: &DrawnMeshes,
) {
    let width = gbuffer.width;
    let encoder = HitEncoder::new(bounds, camera);
    let screen_x: Vec<f64> = (0..width as u32).map(|i| camera.screen_x(i)).collect();
    // Block by block: the triangles of a block of pixels stay in the processor's caches.
    gbuffer.strips_mut(BLOCK).enumerate().for_each(|(s, mut strip)| {
        let rows = strip.len() / width;
        let mut setup = PlaneSetup::NONE;
        for left in (0..width).step_by(BLOCK) {
            for r in 0..rows {
                let j = s * BLOCK + r;
                let sy = camera.screen_y(j as u32);
                for i in left..(left + BLOCK).min(width) {
                    let k = r * width + i;
                    let id = target.triangle[j * width + i];
                    if id == RasterTarget::NO_TRIANGLE {
                        strip.set(k, &GBufferPixel::MISS);
                        continue;
                    }
                    if setup.id != id {
                        setup = PlaneSetup::new(drawn, id);
                    }
                    match setup.hit(camera.ray_through(screen_x[i], sy)) {
                        None => strip.set(k, &GBufferPixel::MISS),
                        Some((hit, colour)) => {
                            let mut pixel = encoder.g_buffer_pixel(Some(hit));
                            pixel.material = [colour[0], colour[1], colour[2], 1.0];
                            strip.set(k, &pixel);
                        }
                    }
                }
            }
        }
    });
}

/// What the resolve needs of one triangle, made once for the run of pixels that show it.
struct PlaneSetup {
    /// The triangle's id ([`RasterTarget::NO_TRIANGLE`]: none).
    id: u32,
    /// Whether the triangle has an area and colour and normal attributes.
    valid: bool,
    /// Its first corner.
    p0: DVec3,
    /// Its normal `(p1 - p0) x (p2 - p0)`, and that normal made unit.
    n: DVec3,
    unit: DVec3,
    /// `(p2 - p0) x n / |n|^2` and `n x (p1 - p0) / |n|^2`: a point's barycentrics of
    /// corners 1 and 2 are its offset from `p0` dotted with them.
    to_b1: DVec3,
    to_b2: DVec3,
    /// The corners' colour and normal attributes.
    attributes: [[f32; 6]; 3],
}

impl PlaneSetup {
    /// No triangle.
    const NONE: PlaneSetup = PlaneSetup {
        id: RasterTarget::NO_TRIANGLE,
        valid: false,
        p0: DVec3::ZERO,
        n: DVec3::ZERO,
        unit: DVec3::ZERO,
        to_b1: DVec3::ZERO,
        to_b2: DVec3::ZERO,
        attributes: [[0.0; 6]; 3],
    };

    /// The set-up of the triangle of id `id` (one the target holds).
    #[inline]
    fn new(drawn: &DrawnMeshes, id: u32) -> PlaneSetup {
        let (mesh, triangle) = drawn.triangle(id);
        let none = PlaneSetup { id, ..PlaneSetup::NONE };
        let Some(&tri) = mesh.triangles().get(triangle as usize) else {
            return none;
        };
        let positions = mesh.positions();
        let (p0, p1, p2) =
            (positions[tri[0] as usize], positions[tri[1] as usize], positions[tri[2] as usize]);
        let mut attributes = [[0f32; 6]; 3];
        for (out, &v) in attributes.iter_mut().zip(tri.iter()) {
            match mesh.attributes().get(v as usize * 6..v as usize * 6 + 6) {
                Some(values) => out.copy_from_slice(values),
                None => return none,
            }
        }
        let (e1, e2) = (p1 - p0, p2 - p0);
        let n = e1.cross(e2);
        let area2 = n.length_squared();
        if area2 == 0.0 || !area2.is_finite() {
            return none;
        }
        PlaneSetup {
            id,
            valid: true,
            p0,
            n,
            unit: n / area2.sqrt(),
            to_b1: e2.cross(n) / area2,
            to_b2: n.cross(e1) / area2,
            attributes,
        }
    }

    /// Where `ray` meets the triangle's plane, with the smooth normal facing the ray (else the
    /// geometric one) and the colour there, the attributes interpolated with the barycentrics
    /// clamped to the triangle. `None` for a degenerate triangle or a ray along its plane.
    #[inline(always)]
    fn hit(&self, ray: Ray) -> Option<(Hit, [f32; 3])> {
        if !self.valid {
            return None;
        }
        let t = self.n.dot(self.p0 - ray.origin) / self.n.dot(ray.dir);
        if !t.is_finite() {
            return None;
        }
        let position = ray.origin + ray.dir * t;
        let offset = position - self.p0;
        let (b1, b2) = (offset.dot(self.to_b1), offset.dot(self.to_b2));
        let clamped = [1.0 - b1 - b2, b1, b2].map(|b| b.clamp(0.0, 1.0));
        let sum: f64 = clamped[0] + clamped[1] + clamped[2];
        let weights = if sum > 0.0 {
            let inverse = 1.0 / sum;
            clamped.map(|b| b * inverse)
        } else {
            [1.0 / 3.0; 3]
        };
        let mut a = [0f64; 6];
        for (corner, w) in self.attributes.iter().zip(weights) {
            for (sum, &value) in a.iter_mut().zip(corner) {
                *sum += w * value as f64;
            }
        }
        let geometric = if self.unit.dot(ray.dir) > 0.0 { -self.unit } else { self.unit };
        let smooth = DVec3::new(a[3], a[4], a[5]);
        let normal = match smooth.try_normalize() {
            Some(n) if n.dot(ray.dir) < 0.0 => n,
            _ => geometric,
        };
        Some((Hit { t, position, normal }, [a[0] as f32, a[1] as f32, a[2] as f32]))
    }
}
