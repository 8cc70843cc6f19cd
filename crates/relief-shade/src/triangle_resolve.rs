//! The resolve of a rasterized frame: each pixel's triangle id, distance and barycentrics (a
//! [`RasterTarget`] that keeps them) turned into a G-buffer pixel, block by block in
//! parallel: the mesh's smooth normal and colour interpolated where the pixel's ray meets the
//! triangle, the distance the rasterizer found there.

use crate::gbuffer::GBufferRows;
use crate::render::HitEncoder;
#[cfg(target_arch = "x86_64")]
use crate::resolve_lanes;
use crate::{GBuffer, GBufferPixel};
use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec3, Projection};
use relief_mesh::{IndexedMesh, RasterTarget};
use relief_trace::Hit;

/// The side of the square blocks of pixels resolved together (their triangles stay in the
/// processor's caches).
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

/// Which G-buffer channels a resolve writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ResolvedChannels {
    /// Every channel.
    All,
    /// What the deferred shading of the colours reads: distance, normal and material (the
    /// others left as they were).
    Shading,
}

/// Writes the pixels of `gbuffer` from `target` (the same size, keeping barycentrics): a pixel
/// that shows no triangle is a miss; one that shows a triangle gets the rasterizer's distance
/// (and the position there, texture coordinates over `bounds` and footprint with
/// [`ResolvedChannels::All`]), the mesh's smooth normal interpolated there (the geometric one,
/// turned to face the ray, where the smooth normal is degenerate or faces away from the ray)
/// and its colour as material weights `[r, g, b, 1]`.
pub(crate) fn resolve_triangles(
    gbuffer: &mut GBuffer,
    camera: &Camera,
    bounds: &Aabb,
    target: &RasterTarget,
    drawn: &DrawnMeshes,
    channels: ResolvedChannels,
) {
    RowsResolve::for_frame(camera, bounds, target, drawn, channels).resolve_into(gbuffer);
}

/// Whether the lanes resolve this frame: where the processor has them, for the shading's
/// channels of meshes they can read.
fn lanes_for(target: &RasterTarget, drawn: &DrawnMeshes, channels: ResolvedChannels) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        channels == ResolvedChannels::Shading
            && !target.barycentrics.is_empty()
            && crate::LaneWidth::Avx512.is_available()
            && resolve_lanes::can_resolve(drawn)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (target, drawn, channels);
        false
    }
}

/// What resolving rows of a frame reads (see [`resolve_triangles`]), to resolve them strip by
/// strip.
pub(crate) struct RowsResolve<'a> {
    target: &'a RasterTarget,
    drawn: &'a DrawnMeshes<'a>,
    channels: ResolvedChannels,
    lanes: bool,
    encoder: HitEncoder<'a>,
    rays: RayParts,
}

impl<'a> RowsResolve<'a> {
    /// The resolve of `target`'s pixels as [`resolve_triangles`] makes them.
    pub(crate) fn for_frame(
        camera: &'a Camera,
        bounds: &Aabb,
        target: &'a RasterTarget,
        drawn: &'a DrawnMeshes<'a>,
        channels: ResolvedChannels,
    ) -> Self {
        Self::new(camera, bounds, target, drawn, channels, lanes_for(target, drawn, channels))
    }

    /// The resolve of `target`'s pixels, the shading's channels sixteen pixels at a time with
    /// `lanes` (see [`lanes_for`]), else pixel by pixel.
    fn new(
        camera: &'a Camera,
        bounds: &Aabb,
        target: &'a RasterTarget,
        drawn: &'a DrawnMeshes<'a>,
        channels: ResolvedChannels,
        lanes: bool,
    ) -> Self {
        #[cfg(not(target_arch = "x86_64"))]
        let lanes = {
            let _ = lanes;
            false
        };
        let (encoder, rays) = (HitEncoder::new(bounds, camera), RayParts::new(camera));
        RowsResolve { target, drawn, channels, lanes, encoder, rays }
    }

    /// Resolves every pixel into `gbuffer` (the target's size), strips of rows in parallel.
    fn resolve_into(&self, gbuffer: &mut GBuffer) {
        gbuffer.strips_mut(BLOCK).enumerate().for_each(|(s, mut strip)| {
            self.resolve(s * BLOCK, &mut strip);
        });
    }

    /// Resolves the image rows from `top` on into `strip` (whole rows of the image's width).
    #[allow(unsafe_code)]
    pub(crate) fn resolve(&self, top: usize, strip: &mut GBufferRows) {
        let (target, drawn, channels, rays) = (self.target, self.drawn, self.channels, &self.rays);
        let width = target.width;
        let rows = strip.len() / width;
        let mut setup = TriangleAttributes::NONE;
        // Pixel (i, j), at `k` in the strip, pixel by pixel.
        let mut pixel = |i: usize, j: usize, k: usize, strip: &mut GBufferRows| {
            let index = j * width + i;
            let id = target.triangle[index];
            if id == RasterTarget::NO_TRIANGLE {
                match channels {
                    ResolvedChannels::Shading => {
                        strip.distance[k] = GBufferPixel::MISS.distance;
                        strip.normal[k] = GBufferPixel::MISS.normal;
                        strip.material[k] = GBufferPixel::MISS.material;
                    }
                    ResolvedChannels::All => strip.set(k, &GBufferPixel::MISS),
                }
                return;
            }
            if setup.id != id {
                setup = TriangleAttributes::new(drawn, id);
            }
            let along = rays.direction(i, j);
            let (normal, colour) = setup.at(target.barycentrics[index], along);
            let distance = target.distance[index];
            match channels {
                ResolvedChannels::Shading => {
                    strip.distance[k] = distance;
                    strip.normal[k] = normal;
                    strip.material[k] = [colour[0], colour[1], colour[2], 1.0];
                }
                ResolvedChannels::All => {
                    let t = distance as f64;
                    let position = rays.origin(i, j) + along.normalize() * t;
                    let normal = DVec3::from(normal.map(f64::from));
                    let mut pixel = self.encoder.g_buffer_pixel(Some(Hit { t, position, normal }));
                    pixel.distance = distance;
                    pixel.material = [colour[0], colour[1], colour[2], 1.0];
                    strip.set(k, &pixel);
                }
            }
        };
        #[cfg(target_arch = "x86_64")]
        if self.lanes {
            // Whole rows, streams the processor fetches ahead; the pixels the lanes leave
            // pixel by pixel.
            for r in 0..rows {
                let j = top + r;
                for start in (0..width).step_by(resolve_lanes::LANES) {
                    let n = resolve_lanes::LANES.min(width - start);
                    let (k, index) = (r * width + start, j * width + start);
                    // SAFETY: `lanes_for` checked the processor, the meshes and the target;
                    // the run lies in the row.
                    let rest = unsafe {
                        resolve_lanes::resolve_run(
                            target,
                            drawn,
                            rays,
                            [start, j],
                            index,
                            n,
                            strip,
                            k,
                        )
                    };
                    for l in (0..n).filter(|l| rest >> l & 1 == 1) {
                        pixel(start + l, j, k + l, strip);
                    }
                }
            }
            return;
        }
        // Blocks of columns, whose triangles stay in the caches.
        for left in (0..width).step_by(BLOCK) {
            for r in 0..rows {
                let j = top + r;
                for i in left..(left + BLOCK).min(width) {
                    pixel(i, j, r * width + i, strip);
                }
            }
        }
    }
}

/// The parts of the camera's rays by column and row: a pixel's ray runs from `origin(i, j)`
/// along `direction(i, j)` (not unit: `forward + sx right + sy up'` for a pinhole). Stored
/// component by component, for the lanes too (`resolve_lanes.rs`).
pub(crate) struct RayParts {
    eye: DVec3,
    pub(crate) forward: DVec3,
    /// `sx right` of every column, then [`COLUMN_PADDING`] zeros.
    pub(crate) across: [Vec<f64>; 3],
    /// `sy up'` of every row.
    pub(crate) up: [Vec<f64>; 3],
    pub(crate) perspective: bool,
}

/// Zeros past the last column of [`RayParts::across`]: the lanes read a run of sixteen
/// columns from any column.
const COLUMN_PADDING: usize = 16;

impl RayParts {
    fn new(camera: &Camera) -> Self {
        let across: Vec<DVec3> =
            (0..camera.width()).map(|i| camera.screen_x(i) * camera.right()).collect();
        let up: Vec<DVec3> =
            (0..camera.height()).map(|j| camera.screen_y(j) * camera.image_up()).collect();
        let component = |v: &[DVec3], c: usize, padding: usize| -> Vec<f64> {
            v.iter().map(|p| p[c]).chain(std::iter::repeat_n(0.0, padding)).collect()
        };
        RayParts {
            eye: camera.eye(),
            forward: camera.forward(),
            across: std::array::from_fn(|c| component(&across, c, COLUMN_PADDING)),
            up: std::array::from_fn(|c| component(&up, c, 0)),
            perspective: matches!(camera.projection(), Projection::Perspective { .. }),
        }
    }

    /// `sx right` of column `i` plus `sy up'` of row `j`, each added as a vector.
    #[inline(always)]
    fn across_up(&self, i: usize, j: usize) -> (DVec3, DVec3) {
        let across = DVec3::new(self.across[0][i], self.across[1][i], self.across[2][i]);
        (across, DVec3::new(self.up[0][j], self.up[1][j], self.up[2][j]))
    }

    /// The direction of pixel (i, j)'s ray, not unit.
    #[inline(always)]
    fn direction(&self, i: usize, j: usize) -> DVec3 {
        if self.perspective {
            let (across, up) = self.across_up(i, j);
            self.forward + across + up
        } else {
            self.forward
        }
    }

    /// The origin of pixel (i, j)'s ray.
    #[inline(always)]
    fn origin(&self, i: usize, j: usize) -> DVec3 {
        if self.perspective {
            self.eye
        } else {
            let (across, up) = self.across_up(i, j);
            self.eye + across + up
        }
    }
}

/// What the resolve needs of one triangle, made once for the run of pixels that show it.
struct TriangleAttributes {
    /// The triangle's id ([`RasterTarget::NO_TRIANGLE`]: none).
    id: u32,
    /// Its unit geometric normal (zero for a degenerate triangle).
    unit: DVec3,
    /// The corners' colour and normal attributes (zeros where the mesh has none).
    attributes: [[f32; 6]; 3],
}

impl TriangleAttributes {
    /// No triangle.
    const NONE: TriangleAttributes = TriangleAttributes {
        id: RasterTarget::NO_TRIANGLE,
        unit: DVec3::ZERO,
        attributes: [[0.0; 6]; 3],
    };

    /// The attributes of the triangle of id `id`.
    #[inline]
    fn new(drawn: &DrawnMeshes, id: u32) -> TriangleAttributes {
        let (mesh, triangle) = drawn.triangle(id);
        let none = TriangleAttributes { id, ..TriangleAttributes::NONE };
        let Some(&tri) = mesh.triangles().get(triangle as usize) else {
            return none;
        };
        let mut attributes = [[0f32; 6]; 3];
        for (out, &v) in attributes.iter_mut().zip(tri.iter()) {
            if let Some(values) = mesh.attributes().get(v as usize * 6..v as usize * 6 + 6) {
                out.copy_from_slice(values);
            }
        }
        let positions = mesh.positions();
        let (p0, p1, p2) =
            (positions[tri[0] as usize], positions[tri[1] as usize], positions[tri[2] as usize]);
        TriangleAttributes { id, unit: (p1 - p0).cross(p2 - p0).normalize_or_zero(), attributes }
    }

    /// The unit normal and the colour at barycentrics `[b1, b2]` (of corners 1 and 2) for a
    /// ray along `along`: the smooth normal where it faces the ray, else the geometric one
    /// turned to face it.
    #[inline(always)]
    fn at(&self, [b1, b2]: [f32; 2], along: DVec3) -> ([f32; 3], [f32; 3]) {
        let b0 = (1.0 - b1 - b2).max(0.0);
        let [c0, c1, c2] = &self.attributes;
        let a: [f32; 6] = std::array::from_fn(|k| b0 * c0[k] + b1 * c1[k] + b2 * c2[k]);
        let smooth = [a[3], a[4], a[5]];
        let length = (smooth[0] * smooth[0] + smooth[1] * smooth[1] + smooth[2] * smooth[2]).sqrt();
        let facing =
            smooth[0] as f64 * along.x + smooth[1] as f64 * along.y + smooth[2] as f64 * along.z;
        let normal = if length > 0.0 && length.is_finite() && facing < 0.0 {
            let inverse = 1.0 / length;
            smooth.map(|c| c * inverse)
        } else if self.unit.dot(along) > 0.0 {
            (-self.unit).as_vec3().to_array()
        } else {
            self.unit.as_vec3().to_array()
        };
        (normal, [a[0], a[1], a[2]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_mesh::Rasterizer;

    /// A soup of `count` random triangles around the origin with random colours and normals
    /// (some facing away from the camera, some zero), from `seed`.
    fn soup(seed: u64, count: usize) -> IndexedMesh {
        let mut state = seed;
        let mut next = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut positions = Vec::new();
        let mut attributes = Vec::new();
        for _ in 0..count {
            let centre = DVec3::new(next() * 8.0 - 4.0, next() * 8.0 - 4.0, next() * 2.0);
            for _ in 0..3 {
                positions.push(centre + DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * 3.0);
                attributes.extend([next() as f32, next() as f32, next() as f32]);
                let normal = if next() < 0.05 {
                    [0.0; 3]
                } else {
                    [next() as f32 - 0.5, next() as f32 - 0.5, next() as f32 - 0.1]
                };
                attributes.extend(normal);
            }
        }
        let triangles = (0..count as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        IndexedMesh::new(positions, triangles).unwrap().with_attributes(6, attributes).unwrap()
    }

    /// The lanes resolve the shading's channels bit for bit as the pixel-by-pixel loop does,
    /// two meshes drawn into one target, cameras from several sides, rows not a multiple of
    /// the lanes wide.
    #[test]
    fn the_lanes_resolve_the_same_bits_as_each_pixel() {
        let meshes = [soup(1, 300), soup(2, 200)];
        let drawn = DrawnMeshes { meshes: &meshes, first_ids: &[0, 300] };
        if !lanes_for(&RasterTarget::with_barycentrics(1, 1), &drawn, ResolvedChannels::Shading) {
            eprintln!("skipped: this processor has no AVX-512 for the lanes");
            return;
        }
        let bounds = Aabb::new(DVec3::splat(-6.0), DVec3::splat(6.0));
        for (eye, size) in [
            (DVec3::new(-3.0, -9.0, 7.0), (77, 45)),
            (DVec3::new(8.0, 2.0, 3.0), (64, 48)),
            (DVec3::new(0.5, 0.2, 12.0), (33, 17)),
        ] {
            let camera = Camera::look_at(eye, DVec3::ZERO, DVec3::Z, 50.0, size.0, size.1).unwrap();
            let mut target = RasterTarget::with_barycentrics(size.0 as usize, size.1 as usize);
            for (mesh, &first) in meshes.iter().zip(drawn.first_ids) {
                Rasterizer::new().draw(&camera, mesh, first, &mut target).unwrap();
            }
            let hits = target.triangle.iter().filter(|&&t| t != RasterTarget::NO_TRIANGLE).count();
            assert!(hits > target.triangle.len() / 4, "{hits} pixels see a triangle");
            let resolve = |lanes: bool| {
                let mut gbuffer = GBuffer::new(size.0 as usize, size.1 as usize).unwrap();
                let channels = ResolvedChannels::Shading;
                RowsResolve::new(&camera, &bounds, &target, &drawn, channels, lanes)
                    .resolve_into(&mut gbuffer);
                gbuffer
            };
            let (each, lanes) = (resolve(false), resolve(true));
            let bits = |g: &GBuffer| -> Vec<u32> {
                g.distance
                    .iter()
                    .map(|d| d.to_bits())
                    .chain(g.normal.iter().flatten().map(|v| v.to_bits()))
                    .chain(g.material.iter().flatten().map(|v| v.to_bits()))
                    .collect()
            };
            assert!(bits(&each) == bits(&lanes), "the lanes differ from {eye}");
        }
    }
}
