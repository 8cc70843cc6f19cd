//! Property test of the mipmap tracer's coherent traversal (a tile of camera rays traced as
//! one batch, in packets) against its single-ray traversal, pixel for pixel and bit for bit,
//! over random terrains (with holes and cliffs) and random cameras of every awkward kind:
//! rolled, looking up, with the eye inside the solid, and with the eye outside the domain.

mod common;

use common::scenes::terrain;
use proptest::prelude::*;
use relief_core::{Camera, DVec3, HeightField, Ray, Surface};
use relief_trace::{Hit, MipmapTracer, Simd, Tracer};
use std::sync::Arc;

/// Image size: four tiles, the last ones cut short, as at an image's edges.
const IMAGE: (u32, u32) = (27, 21);
/// Side of the square tiles traced as one batch each, as the render pass traces them.
const TILE: u32 = 16;

/// Where a random camera's eye is.
#[derive(Debug, Clone, Copy)]
enum Eye {
    /// Above the terrain's box, over its footprint.
    Above,
    /// Beside the terrain's box, outside its footprint, at any height.
    Outside,
    /// Inside the solid: under the surface, over its footprint.
    InsideSolid,
    /// Inside the box, anywhere over the footprint and below the box's top.
    InsideBox,
}

/// The pixels of a tile at (x0, y0) in Morton order (the order the render pass hands over),
/// leaving out those beyond the image.
fn morton_tile(x0: u32, y0: u32, (width, height): (u32, u32)) -> Vec<(u32, u32)> {
    (0..TILE * TILE)
        .map(|m| {
            let bits = |m: u32| (0..4).map(|b| ((m >> (2 * b)) & 1) << b).sum::<u32>();
            (x0 + bits(m), y0 + bits(m >> 1))
        })
        .filter(|&(i, j)| i < width && j < height)
        .collect()
}

/// A camera of `kind` over `field`'s solid, from the random numbers `u`: the eye placed as
/// `kind` says, looking anywhere (up included), rolled by any angle, with any field of view.
fn camera(field: &HeightField, surface: Surface, kind: Eye, u: [f64; 8]) -> Option<Camera> {
    let b = field.world_bounds(surface);
    let size = b.max - b.min;
    let span = size.x.max(size.y).max(size.z).max(1.0);
    let lerp = |lo: f64, hi: f64, t: f64| lo + (hi - lo) * t;
    let (x, y) = (lerp(b.min.x, b.max.x, u[0]), lerp(b.min.y, b.max.y, u[1]));
    let eye = match kind {
        Eye::Above => DVec3::new(x, y, b.max.z + lerp(0.01, 2.0, u[2]) * span),
        Eye::Outside => {
            let angle = u[2] * std::f64::consts::TAU;
            let centre = (b.min + b.max) / 2.0;
            let reach = 0.5 * size.x.hypot(size.y) + lerp(0.01, 1.0, u[3]) * span;
            let z = lerp(b.min.z - 0.5 * span, b.max.z + 0.5 * span, u[4]);
            DVec3::new(centre.x + reach * angle.cos(), centre.y + reach * angle.sin(), z)
        }
        Eye::InsideSolid => DVec3::new(x, y, lerp(b.min.z, b.max.z, 0.05 * u[2])),
        Eye::InsideBox => DVec3::new(x, y, lerp(b.min.z, b.max.z, u[2])),
    };
    // Towards the terrain's middle, or anywhere, up included.
    let target = if u[5] < 0.5 {
        let centre = (b.min + b.max) / 2.0;
        let jitter = DVec3::new(u[6] - 0.5, u[7] - 0.5, u[3] - 0.5) * size;
        centre + jitter
    } else {
        let (azimuth, elevation) = (u[6] * std::f64::consts::TAU, (u[7] - 0.5) * 3.0);
        let dir = DVec3::new(
            azimuth.cos() * elevation.cos(),
            azimuth.sin() * elevation.cos(),
            elevation.sin(),
        );
        eye + dir * span
    };
    let forward = (target - eye).normalize_or_zero();
    // Rolled: the up vector turned about the view by any angle.
    let roll = u[4] * std::f64::consts::TAU;
    let side = forward.any_orthonormal_vector();
    let up = side * roll.cos() + forward.cross(side) * roll.sin();
    let fov = lerp(10.0, 120.0, u[3]);
    Camera::look_at(eye, target, up, fov, IMAGE.0, IMAGE.1).ok()
}

/// The bits of a hit, to compare hits bit for bit.
fn bits(hit: &Option<Hit>) -> Option<[u64; 7]> {
    hit.map(|h| {
        let (p, n) = (h.position, h.normal);
        [h.t, p.x, p.y, p.z, n.x, n.y, n.z].map(f64::to_bits)
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Every tile of a random camera's image, traced as one batch, gets exactly the single-ray
    /// traversal's hit at every pixel, with both SIMD kernels and both surfaces.
    #[test]
    fn coherent_tiles_equal_single_rays(
        field in terrain(),
        kind in prop_oneof![
            Just(Eye::Above), Just(Eye::Outside), Just(Eye::InsideSolid), Just(Eye::InsideBox)
        ],
        u in prop::array::uniform8(0.0f64..1.0),
    ) {
        let field = Arc::new(field);
        for surface in Surface::ALL {
            let Some(camera) = camera(&field, surface, kind, u) else { continue };
            for simd in [Simd::Avx2, Simd::Portable] {
                let tracer = MipmapTracer::new(field.clone(), surface).with_simd(simd);
                for y0 in (0..IMAGE.1).step_by(TILE as usize) {
                    for x0 in (0..IMAGE.0).step_by(TILE as usize) {
                        let pixels = morton_tile(x0, y0, IMAGE);
                        let rays: Vec<Ray> =
                            pixels.iter().map(|&(i, j)| camera.ray(i, j)).collect();
                        let mut hits = vec![None; rays.len()];
                        let mut steps = vec![0; rays.len()];
                        tracer.intersect_batch(&rays, &mut hits, &mut steps);
                        for ((&(i, j), ray), hit) in pixels.iter().zip(&rays).zip(&hits) {
                            let single = tracer.intersect(ray);
                            prop_assert_eq!(
                                bits(hit), bits(&single),
                                "{} {} {:?} pixel ({}, {}): batch {:?} single {:?}",
                                surface, simd, kind, i, j, hit, single
                            );
                        }
                    }
                }
            }
        }
    }
}
