//! Property tests of the max-mipmap tracer's batch path (coherent ray packets): on random
//! terrains, incoherent batches of rays of every kind and camera tiles get the hits and the
//! occlusion answers of the single-ray tracers and of an independent brute-force tracer, the
//! same with either SIMD kernel, and the batch interface keeps its contract on edge cases.

mod common;

use common::mlhm_reference::Rng;
use common::reference::first_hit;
use common::scenes::{agree, ray_for, terrain, RayKind, ALL_KINDS};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use relief_core::{Aabb, Camera, DVec2, DVec3, GridGeometry, HeightField, Ray, Surface};
use relief_trace::{Hit, MipmapTracer, NaiveTracer, Simd, Tracer};
use std::sync::Arc;

/// Rays of each kind in an incoherent batch: 192 in all, so that every sign class is there
/// and, in most batches, the most common one (vertical rays count as non-negative) fills a
/// 64-ray packet.
const RAYS_PER_KIND: usize = 24;

/// Both SIMD kernels (on a processor without AVX2 both run the portable one).
const KERNELS: [Simd; 2] = [Simd::Avx2, Simd::Portable];

/// Size of the camera images, and the side of the square tiles traced as one batch each.
const IMAGE: (u32, u32) = (48, 32);
const TILE: u32 = 16;

/// One random ray of a batch: its kind, the numbers [`ray_for`] makes it from, and the
/// fraction of the distance to its first hit that its shadow-ray version reaches.
type RayDraw = (RayKind, [f64; 8], f64);

/// An incoherent batch: [`RAYS_PER_KIND`] rays of every kind in random order, so that packets
/// mix kinds, with shadow ranges that end before or beyond the first hit.
fn incoherent_batch() -> impl Strategy<Value = Vec<RayDraw>> {
    let n = ALL_KINDS.len() * RAYS_PER_KIND;
    let kinds: Vec<RayKind> = (0..n).map(|i| ALL_KINDS[i % ALL_KINDS.len()]).collect();
    let numbers = prop::collection::vec(prop::array::uniform8(0.001f64..0.999), n);
    let fractions = prop::collection::vec(prop_oneof![0.05f64..0.95, 1.05f64..1.5], n);
    (Just(kinds).prop_shuffle(), numbers, fractions).prop_map(|(kinds, numbers, fractions)| {
        kinds.into_iter().zip(numbers).zip(fractions).map(|((k, u), f)| (k, u, f)).collect()
    })
}

/// The rays of `draws` for `field`.
fn rays_of(field: &HeightField, draws: &[RayDraw]) -> Vec<Ray> {
    draws.iter().map(|&(kind, u, _)| ray_for(field, kind, u)).collect()
}

/// Shadow-like versions of `rays` as agreement.rs builds them: each one's range ends at its
/// fraction (one per ray) of the distance to its brute-force first hit, or of 1 without one.
fn shadow_rays(
    field: &HeightField,
    surface: Surface,
    rays: &[Ray],
    fractions: impl IntoIterator<Item = f64>,
) -> Vec<Ray> {
    rays.iter()
        .zip(fractions)
        .map(|(ray, fraction)| {
            let reach = first_hit(field, surface, ray).unwrap_or(1.0).max(1e-3);
            ray.with_range(ray.t_min, reach * fraction)
        })
        .collect()
}

/// `tracer.intersect_batch` of `rays`, with each ray's steps. The hit slice starts out full
/// of a stale hit, which the batch must overwrite for the rays that miss as well.
fn batch_hits(tracer: &dyn Tracer, rays: &[Ray]) -> (Vec<Option<Hit>>, Vec<u32>) {
    let stale = Hit { t: -1.0, position: DVec3::NAN, normal: DVec3::NAN };
    let (mut hits, mut steps) = (vec![Some(stale); rays.len()], vec![0; rays.len()]);
    tracer.intersect_batch(rays, &mut hits, &mut steps);
    (hits, steps)
}

/// `tracer.occluded_batch` of `rays`. The answers start out all `true`, which the batch must
/// overwrite for the rays that are not blocked.
fn batch_occluded(tracer: &dyn Tracer, rays: &[Ray]) -> Vec<bool> {
    let (mut occluded, mut steps) = (vec![true; rays.len()], vec![0; rays.len()]);
    tracer.occluded_batch(rays, &mut occluded, &mut steps);
    occluded
}

/// The bits of a hit's parameter, position and normal, to compare hits bit for bit.
fn bits(hit: &Option<Hit>) -> Option<[u64; 7]> {
    hit.map(|h| {
        let (p, n) = (h.position, h.normal);
        [h.t, p.x, p.y, p.z, n.x, n.y, n.z].map(f64::to_bits)
    })
}

/// The box a ray must enter to take a traversal step: the solid's world bounds, grown by a
/// hair so that rays grazing its faces count as entering.
fn step_box(field: &HeightField, surface: Surface) -> Aabb {
    let b = field.world_bounds(surface);
    let margin = DVec3::splat(1e-6 * (1.0 + b.min.abs().max(b.max.abs()).max_element()));
    Aabb::new(b.min - margin, b.max + margin)
}

/// Checks the batch hits of `surface` of `field` for `rays` with both kernels, ray by ray,
/// against the naive tracer and the brute force: the same `t` to 1e-5 relative (both `None`
/// together), the naive tracer's normal where `t` is the same, the position `ray.at(t)`, and
/// traversal steps for a ray that hits but none for one that misses the solid's box.
fn check_batch_hits(
    field: &Arc<HeightField>,
    surface: Surface,
    rays: &[Ray],
) -> Result<(), TestCaseError> {
    let naive = NaiveTracer::new(field.clone(), surface);
    let expected: Vec<(Option<Hit>, Option<f64>)> =
        rays.iter().map(|ray| (naive.intersect(ray), first_hit(field, surface, ray))).collect();
    let step_box = step_box(field, surface);
    for simd in KERNELS {
        let mipmap = MipmapTracer::new(field.clone(), surface).with_simd(simd);
        let (hits, steps) = batch_hits(&mipmap, rays);
        for (k, (ray, &(n, b))) in rays.iter().zip(&expected).enumerate() {
            let m = hits[k];
            prop_assert!(
                agree(n.map(|h| h.t), m.map(|h| h.t), 1e-5),
                "{surface} {simd} ray {k} {ray:?}: naive {n:?} batch {m:?}"
            );
            prop_assert!(
                agree(m.map(|h| h.t), b, 1e-5),
                "{surface} {simd} ray {k} {ray:?}: batch {m:?} brute force {b:?}"
            );
            if let (Some(hn), Some(hm)) = (n, m) {
                prop_assert!(
                    hn.t != hm.t || (hn.normal - hm.normal).length() < 1e-6,
                    "{surface} {simd} ray {k}: normals differ for the same hit {hn:?} {hm:?}"
                );
            }
            if let Some(hm) = m {
                prop_assert_eq!(hm.position, ray.at(hm.t), "{} {} ray {}", surface, simd, k);
                prop_assert!(steps[k] > 0, "{surface} {simd} ray {k} hits in no step: {ray:?}");
            }
            if step_box.clip(ray).is_none() {
                prop_assert_eq!(
                    steps[k],
                    0,
                    "{} {} ray {} misses the box: {:?}",
                    surface,
                    simd,
                    k,
                    ray
                );
            }
        }
    }
    Ok(())
}

/// Checks `occluded_batch` of `surface` of `field` for `rays` with both kernels against the
/// brute force's first hit within each ray's range, and against the single-ray `occluded`.
fn check_batch_occlusion(
    field: &Arc<HeightField>,
    surface: Surface,
    rays: &[Ray],
) -> Result<(), TestCaseError> {
    let expected: Vec<bool> = rays.iter().map(|r| first_hit(field, surface, r).is_some()).collect();
    for simd in KERNELS {
        let mipmap = MipmapTracer::new(field.clone(), surface).with_simd(simd);
        let occluded = batch_occluded(&mipmap, rays);
        for (k, ray) in rays.iter().enumerate() {
            prop_assert_eq!(
                occluded[k],
                expected[k],
                "{} {} shadow ray {} {:?}",
                surface,
                simd,
                k,
                ray
            );
            prop_assert_eq!(
                occluded[k],
                mipmap.occluded(ray),
                "{} {} single ray {}",
                surface,
                simd,
                k
            );
        }
    }
    Ok(())
}

/// A ray parallel to a grid axis, or to the x-z or y-z plane, that starts a hair beside
/// the lines of cell boundaries: where the conservative node tests cannot tell the cells on
/// either side apart, so the exact test must.
#[derive(Debug, Clone, Copy)]
struct BoundaryDraw {
    /// Which boundary line along x and along y, as fractions of the lines.
    line: [f64; 2],
    /// Signed offsets off the lines, in cells (1e-9 to 1e-3 in magnitude).
    offset: [f64; 2],
    /// The start height, as a fraction of the span from half the box's height below it to
    /// half its height above it.
    height: f64,
    /// How far back along the direction the ray starts, as a fraction of the box's diagonal.
    back: f64,
    /// The direction: an index into [`parallel_direction`]'s choices, and the tilt of the
    /// slanted ones.
    direction: (usize, f64),
    /// As in [`RayDraw`], for its shadow version.
    fraction: f64,
}

/// Rays beside cell boundaries (see [`BoundaryDraw`]).
fn boundary_batch() -> impl Strategy<Value = Vec<BoundaryDraw>> {
    let offset = (any::<bool>(), 3.0f64..9.0)
        .prop_map(|(negative, e)| if negative { -1.0 } else { 1.0 } * 10f64.powf(-e));
    let draw = (
        prop::array::uniform2(0.0f64..1.0),
        prop::array::uniform2(offset),
        0.0f64..1.0,
        0.0f64..1.0,
        (0usize..8, -2.0f64..2.0),
        prop_oneof![0.05f64..0.95, 1.05f64..1.5],
    )
        .prop_map(|(line, offset, height, back, direction, fraction)| BoundaryDraw {
            line,
            offset,
            height,
            back,
            direction,
            fraction,
        });
    prop::collection::vec(draw, 128)
}

/// Direction `index` of eight with no x or no y component: down, up, the four horizontal
/// axes, and down with a `tilt` along y or along x only.
fn parallel_direction((index, tilt): (usize, f64)) -> DVec3 {
    let dirs = [
        -DVec3::Z,
        DVec3::Z,
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::new(0.0, tilt, -1.0),
        DVec3::new(tilt, 0.0, -1.0),
    ];
    dirs[index].normalize()
}

/// The ray of `draw` for `surface` of `field`: the cell boundaries of `boxes` lie on the
/// texel edges, those of `triangles` on the sample centres.
fn boundary_ray(field: &HeightField, surface: Surface, draw: &BoundaryDraw) -> Ray {
    let g = field.geometry();
    let b = field.world_bounds(surface);
    let inset = match surface {
        Surface::Boxes => 0.0,
        Surface::Triangles => 0.5,
    };
    let coordinate = |axis: usize, texels: usize, spacing: f64, origin: f64| {
        let lines = texels - (surface == Surface::Triangles) as usize;
        let k = ((draw.line[axis] * (lines + 1) as f64) as usize).min(lines);
        origin + (k as f64 + inset + draw.offset[axis]) * spacing
    };
    let size = b.max - b.min;
    let z = b.min.z - 0.5 * size.z - 0.1 + draw.height * (2.0 * size.z + 0.2);
    let start = DVec3::new(
        coordinate(0, field.width(), g.dx, g.origin.x),
        coordinate(1, field.height(), g.dy, g.origin.y),
        z,
    );
    let dir = parallel_direction(draw.direction);
    Ray::new(start - dir * draw.back * size.length(), dir)
}

/// The pixels of a `width x height` image tile by tile ([`TILE`] pixels square, the tiles
/// in row-major order), each tile's in row-major order.
fn tiles(width: u32, height: u32) -> impl Iterator<Item = Vec<(u32, u32)>> {
    (0..height / TILE).flat_map(move |ty| {
        (0..width / TILE).map(move |tx| {
            (0..TILE * TILE).map(|p| (tx * TILE + p % TILE, ty * TILE + p / TILE)).collect()
        })
    })
}

/// The shadow ray from `hit` towards `sun`: it starts a hair off the surface along the
/// normal, as a renderer's shadow pass starts it, so that it does not hit its own face.
fn sun_ray(hit: &Hit, sun: DVec3) -> Ray {
    let offset = 1e-5 * hit.t + 1e-12 * hit.position.abs().max_element();
    Ray::new(hit.position + hit.normal * offset, sun)
}

/// The unit vector towards a sun at `azimuth` (radians from +x) and `elevation` above the
/// horizon.
fn sun_direction(azimuth: f64, elevation: f64) -> DVec3 {
    DVec3::new(azimuth.cos() * elevation.cos(), azimuth.sin() * elevation.cos(), elevation.sin())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// Incoherent batches hit where the naive tracer and the brute force do.
    #[test]
    fn batch_hits_match_naive_and_brute_force(field in terrain(), draws in incoherent_batch()) {
        let field = Arc::new(field);
        let rays = rays_of(&field, &draws);
        for surface in Surface::ALL {
            check_batch_hits(&field, surface, &rays)?;
        }
    }

    /// Shadow rays with finite ranges are occluded exactly when the brute force finds a hit
    /// within their range.
    #[test]
    fn batch_occlusion_matches_brute_force(field in terrain(), draws in incoherent_batch()) {
        let field = Arc::new(field);
        let rays = rays_of(&field, &draws);
        for surface in Surface::ALL {
            let fractions = draws.iter().map(|&(_, _, fraction)| fraction);
            let shadows = shadow_rays(&field, surface, &rays, fractions);
            check_batch_occlusion(&field, surface, &shadows)?;
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Rays parallel to a grid axis a hair beside cell boundaries hit, and their shadow
    /// versions are blocked, where the naive tracer and the brute force say.
    #[test]
    fn axis_parallel_rays_beside_cell_boundaries(
        field in terrain(),
        draws in boundary_batch(),
    ) {
        let field = Arc::new(field);
        for surface in Surface::ALL {
            let rays: Vec<Ray> =
                draws.iter().map(|d| boundary_ray(&field, surface, d)).collect();
            check_batch_hits(&field, surface, &rays)?;
            let shadows = shadow_rays(&field, surface, &rays, draws.iter().map(|d| d.fraction));
            check_batch_occlusion(&field, surface, &shadows)?;
        }
    }

    /// The AVX2 and the portable node tests give bit-identical hits and the same occlusion
    /// answers, for first-hit rays and for their shadow versions.
    #[test]
    fn avx2_and_portable_kernels_agree_bit_for_bit(
        field in terrain(),
        draws in incoherent_batch(),
    ) {
        let field = Arc::new(field);
        let rays = rays_of(&field, &draws);
        for surface in Surface::ALL {
            let fractions = draws.iter().map(|&(_, _, fraction)| fraction);
            let shadows = shadow_rays(&field, surface, &rays, fractions);
            let [avx2, portable] =
                KERNELS.map(|simd| MipmapTracer::new(field.clone(), surface).with_simd(simd));
            let (avx2_hits, _) = batch_hits(&avx2, &rays);
            let (portable_hits, _) = batch_hits(&portable, &rays);
            for ((ray, a), p) in rays.iter().zip(&avx2_hits).zip(&portable_hits) {
                prop_assert_eq!(bits(a), bits(p), "{} {:?}: {:?} {:?}", surface, ray, a, p);
            }
            for batch in [&rays, &shadows] {
                let (a, p) = (batch_occluded(&avx2, batch), batch_occluded(&portable, batch));
                prop_assert_eq!(a, p, "{}", surface);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// A camera image traced tile by tile (each tile one batch, row-major inside the tile)
    /// gets, pixel by pixel, the single-ray path's hits, and agrees with the brute force to
    /// 1e-4 on every pixel but at most two grazing ties; the shadow rays from its hits
    /// towards a sun get the single-ray path's answers.
    #[test]
    fn camera_tiles_match_single_rays(
        field in terrain(),
        azimuth in 0.0f64..std::f64::consts::TAU,
        elevation in 0.1f64..1.4,
    ) {
        let field = Arc::new(field);
        let sun = sun_direction(azimuth, elevation);
        let (width, height) = IMAGE;
        for surface in Surface::ALL {
            let camera = Camera::frame(&field.world_bounds(surface), width, height).unwrap();
            let brute: Vec<Option<f64>> = (0..width * height)
                .map(|p| first_hit(&field, surface, &camera.ray(p % width, p / width)))
                .collect();
            for simd in KERNELS {
                let mipmap = MipmapTracer::new(field.clone(), surface).with_simd(simd);
                let mut wrong = Vec::new();
                for pixels in tiles(width, height) {
                    let rays: Vec<Ray> = pixels.iter().map(|&(i, j)| camera.ray(i, j)).collect();
                    let (hits, _) = batch_hits(&mipmap, &rays);
                    for ((&(i, j), ray), hit) in pixels.iter().zip(&rays).zip(&hits) {
                        let single = mipmap.intersect(ray);
                        prop_assert_eq!(*hit, single, "{} {} pixel ({}, {})", surface, simd, i, j);
                        let want = brute[(i + j * width) as usize];
                        if !agree(hit.map(|h| h.t as f32 as f64), want, 1e-4) {
                            wrong.push((i, j, *hit, want));
                        }
                    }
                    let shadows: Vec<Ray> =
                        hits.iter().flatten().map(|h| sun_ray(h, sun)).collect();
                    let occluded = batch_occluded(&mipmap, &shadows);
                    for (ray, blocked) in shadows.iter().zip(occluded) {
                        let single = mipmap.occluded(ray);
                        prop_assert_eq!(blocked, single, "{} {} sun ray {:?}", surface, simd, ray);
                    }
                }
                let (w, h) = (field.width(), field.height());
                prop_assert!(wrong.len() <= 2, "{surface} {simd} on {w}x{h}: {wrong:?}");
            }
        }
    }
}

/// A field of `w x h` samples from `f(col, row)` with a skewed, offset geometry.
fn field(w: usize, h: usize, f: impl Fn(usize, usize) -> f32) -> HeightField {
    let geometry = GridGeometry { dx: 0.75, dy: 1.5, z_scale: 0.6, origin: DVec2::new(-3.0, 2.0) };
    let samples = (0..w * h).map(|i| f(i % w, i / w)).collect();
    HeightField::new(w, h, samples, geometry).unwrap()
}

/// Heights that vary without pattern, in `[0, 8)`.
fn bumpy(col: usize, row: usize) -> f32 {
    ((col * 7 + row * 13) % 11) as f32 * 0.7 + ((col * row) % 3) as f32
}

/// `n` rays of every kind for `field`, in an order that mixes kinds, drawn from `seed`, with
/// shadow ranges as [`incoherent_batch`] draws them.
fn seeded_batch(seed: u64, n: usize) -> Vec<RayDraw> {
    let mut rng = Rng::new(seed);
    (0..n * ALL_KINDS.len())
        .map(|_| {
            let kind = ALL_KINDS[rng.below(ALL_KINDS.len())];
            let u = [(); 8].map(|_| rng.range(0.001, 0.999));
            let fraction =
                if rng.chance(0.5) { rng.range(0.05, 0.95) } else { rng.range(1.05, 1.5) };
            (kind, u, fraction)
        })
        .collect()
}

/// Degenerate grids: one cell, one row or column, holes. Their batch hits and occlusion
/// answers are the naive tracer's and the brute force's, with both kernels.
#[test]
fn small_and_holed_fields_match_the_naive_tracer() {
    let holes = |w: usize, h: usize| -> Vec<bool> {
        (0..w * h)
            .map(|i| (i % w, i / w))
            .map(|(c, r)| (2..5).contains(&c) && (1..3).contains(&r) || (c * 5 + r * 3) % 7 == 0)
            .collect()
    };
    let fields = [
        ("1x1", field(1, 1, |_, _| 2.5)),
        ("2x2", field(2, 2, |c, r| [1.0, 4.0, 2.5, 0.5][c + 2 * r])),
        ("1x9", field(1, 9, bumpy)),
        ("9x1", field(9, 1, bumpy)),
        ("9x7 with holes", field(9, 7, bumpy).with_holes(holes(9, 7)).unwrap()),
        (
            "2x2 with a hole",
            field(2, 2, bumpy).with_holes(vec![false, false, true, false]).unwrap(),
        ),
    ];
    for (seed, (name, field)) in fields.into_iter().enumerate() {
        let field = Arc::new(field);
        let draws = seeded_batch(seed as u64, 40);
        let rays = rays_of(&field, &draws);
        for surface in Surface::ALL {
            let shadows =
                shadow_rays(&field, surface, &rays, draws.iter().map(|&(_, _, fraction)| fraction));
            check_batch_hits(&field, surface, &rays).unwrap_or_else(|e| panic!("{name}: {e}"));
            check_batch_occlusion(&field, surface, &shadows)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }
}

/// A ray that enters the terrain's box takes traversal steps, one that misses it takes
/// none, and a batch adds its steps to what the slice holds.
#[test]
fn steps_count_the_rays_that_enter_the_box() {
    let field = Arc::new(field(8, 8, bumpy));
    for surface in Surface::ALL {
        let b = field.world_bounds(surface);
        let (centre, size) = (b.center(), b.max - b.min);
        let rays = [
            // Straight down onto the middle, and slanting in from outside the footprint.
            Ray::new(DVec3::new(centre.x, centre.y, b.max.z + 5.0), -DVec3::Z),
            Ray::new(b.min - size, (centre - (b.min - size)).normalize()),
            // Away from the box, above it, and stopping short of it.
            Ray::new(b.max + size, DVec3::new(1.0, 0.5, 0.2).normalize()),
            Ray::new(DVec3::new(b.min.x - 1.0, centre.y, b.max.z + 1.0), DVec3::X),
            Ray::new(DVec3::new(centre.x, centre.y, b.max.z + 5.0), -DVec3::Z).with_range(0.0, 4.0),
        ];
        let enters = [true, true, false, false, false];
        for simd in KERNELS {
            let mipmap = MipmapTracer::new(field.clone(), surface).with_simd(simd);
            let (mut hits, mut steps) = (vec![None; rays.len()], vec![0; rays.len()]);
            mipmap.intersect_batch(&rays, &mut hits, &mut steps);
            for (k, &enter) in enters.iter().enumerate() {
                assert_eq!(steps[k] > 0, enter, "{surface} {simd} ray {k}: {} steps", steps[k]);
                assert_eq!(hits[k].is_some(), enter, "{surface} {simd} ray {k}: {:?}", hits[k]);
            }
            let first = steps.clone();
            mipmap.intersect_batch(&rays, &mut hits, &mut steps);
            assert_eq!(steps, first.iter().map(|s| 2 * s).collect::<Vec<_>>(), "{surface} {simd}");
            let mut occluded = vec![true; rays.len()];
            let mut shadow_steps = vec![0; rays.len()];
            mipmap.occluded_batch(&rays, &mut occluded, &mut shadow_steps);
            assert_eq!(occluded, enters, "{surface} {simd}");
            for (k, &enter) in enters.iter().enumerate() {
                assert_eq!(shadow_steps[k] > 0, enter, "{surface} {simd} shadow ray {k}");
            }
        }
    }
}

/// An empty batch leaves nothing to do and does not panic.
#[test]
fn an_empty_batch_works() {
    let mipmap = MipmapTracer::new(Arc::new(field(4, 4, bumpy)), Surface::Boxes);
    mipmap.intersect_batch(&[], &mut [], &mut []);
    mipmap.occluded_batch(&[], &mut [], &mut []);
}

/// `intersect_batch` refuses a hit slice shorter than the rays.
#[test]
#[should_panic(expected = "batch slices differ")]
fn intersect_batch_refuses_slices_of_different_lengths() {
    let mipmap = MipmapTracer::new(Arc::new(field(4, 4, bumpy)), Surface::Boxes);
    let ray = Ray::new(DVec3::new(0.0, 4.0, 10.0), -DVec3::Z);
    mipmap.intersect_batch(&[ray, ray], &mut [None], &mut [0, 0]);
}

/// `occluded_batch` refuses a step slice longer than the rays.
#[test]
#[should_panic(expected = "batch slices differ")]
fn occluded_batch_refuses_slices_of_different_lengths() {
    let mipmap = MipmapTracer::new(Arc::new(field(4, 4, bumpy)), Surface::Triangles);
    let ray = Ray::new(DVec3::new(0.0, 4.0, 10.0), -DVec3::Z);
    mipmap.occluded_batch(&[ray], &mut [false], &mut [0, 0]);
}

/// Asking for AVX2 runs what the processor's best choice is, and asking for the portable
/// kernel runs it.
#[test]
fn the_tracer_reports_the_kernel_that_runs() {
    let field = Arc::new(field(4, 4, bumpy));
    let tracer = |simd| MipmapTracer::new(field.clone(), Surface::Boxes).with_simd(simd);
    assert_eq!(tracer(Simd::Avx2).simd(), Simd::detect());
    assert_eq!(tracer(Simd::Portable).simd(), Simd::Portable);
}
