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
        for left in (0..width).step_by(BLOCK) {
            for r in 0..rows {
                let j = s * BLOCK + r;
                let sy = camera.screen_y(j as u32);
                for i in left..(left + BLOCK).min(width) {
                    let k = r * width + i;
                    let id = target.triangle[j * width + i];
                    let surface = (id != RasterTarget::NO_TRIANGLE)
                        .then(|| {
                            let (mesh, triangle) = drawn.triangle(id);
                            surface_hit(mesh, triangle, &camera.ray_through(screen_x[i], sy))
                        })
                        .flatten();
                    match surface {
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

/// Where `ray` meets the plane of `triangle` of `mesh` (as [`IndexedMesh::hit`] finds it),
/// with the smooth normal facing the ray (else the geometric one) and the colour there, the
/// attributes interpolated with the barycentrics clamped to the triangle (as
/// [`IndexedMesh::interpolate_attributes`] does). `None` for a degenerate triangle or a ray
/// along its plane.
#[inline]
fn surface_hit(mesh: &IndexedMesh, triangle: u32, ray: &Ray) -> Option<(Hit, [f32; 3])> {
    let h = mesh.hit(triangle, ray)?;
    let tri = mesh.triangles()[triangle as usize];
    let attributes = mesh.attributes();
    let clamped = h.barycentrics.map(|b| if b.is_finite() { b.clamp(0.0, 1.0) } else { 0.0 });
    let sum: f64 = clamped.iter().sum();
    let weights = if sum > 0.0 { clamped.map(|b| b / sum) } else { [1.0 / 3.0; 3] };
    let mut a = [0f64; 6];
    for (&v, w) in tri.iter().zip(weights) {
        let vertex = attributes.get(v as usize * 6..v as usize * 6 + 6)?;
        for (sum, &value) in a.iter_mut().zip(vertex) {
            *sum += w * value as f64;
        }
    }
    let a = a.map(|x| x as f32);
    let smooth = DVec3::new(a[3] as f64, a[4] as f64, a[5] as f64);
    let normal = match smooth.try_normalize() {
        Some(n) if n.dot(ray.dir) < 0.0 => n,
        _ => h.normal,
    };
    Some((Hit { t: h.t, position: h.position, normal }, [a[0], a[1], a[2]]))
}
