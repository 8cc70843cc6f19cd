//! The shadow sweep's decisions equal traced shadow rays: [`SunShadows`] answers every ray
//! as the tracers it wraps do, on random terrains (cliffs, holes, any geometry), both
//! surfaces, any sun, for shadow rays leaving surface points and for rays from anywhere.

mod common;

use common::scenes::{ray_for, terrain, ALL_KINDS};
use proptest::prelude::*;
use relief_core::{DVec3, GridGeometry, HeightField, Ray, Surface};
use relief_trace::{MipmapTracer, NaiveTracer, SunShadows, TraceError, Tracer};
use std::sync::Arc;

/// Unit vector towards a sun at compass `azimuth_deg` (clockwise from +y) and `elevation_deg`.
fn sun(azimuth_deg: f64, elevation_deg: f64) -> DVec3 {
    let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
    DVec3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin())
}

/// A sun azimuth: often along an axis or a diagonal, else anywhere.
fn azimuth() -> impl Strategy<Value = f64> {
    prop_oneof![
        prop::sample::select(vec![0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0]),
        0.0f64..360.0,
    ]
}

/// A sun elevation: low, steep, straight up, or anywhere between.
fn elevation() -> impl Strategy<Value = f64> {
    prop_oneof![0.2f64..3.0, 80.0f64..89.99, Just(90.0), 3.0f64..80.0]
}

/// The shadow rays relief-shade makes: from the hit of a camera ray, lifted along the normal
/// by `lift` (relative to the hit distance, as relief-shade's bias), towards `towards_sun`.
fn surface_shadow_ray(tracer: &dyn Tracer, camera_ray: &Ray, lift: f64, sun: DVec3) -> Option<Ray> {
    let hit = tracer.intersect(camera_ray)?;
    let eps = lift * hit.t.abs() + 1e-12 * hit.position.abs().max_element();
    Some(Ray::new(hit.position + hit.normal * eps, sun))
}

/// Checks every ray against the wrapped tracers, one at a time and as one batch.
fn check(
    field: &Arc<HeightField>,
    surface: Surface,
    towards_sun: DVec3,
    block: usize,
    rays: &[Ray],
) -> Result<usize, TestCaseError> {
    let mipmap = MipmapTracer::new(field.clone(), surface);
    let naive = NaiveTracer::new(field.clone(), surface);
    let shadows = SunShadows::with_block(&mipmap, field.clone(), towards_sun, block).unwrap();
    let naive_shadows = SunShadows::with_block(&naive, field.clone(), towards_sun, block).unwrap();
    let mut proven = 0;
    for ray in rays {
        let expected = mipmap.occluded(ray);
        let decided = shadows.decide(ray, &mut 0);
        let lit = shadows.proves_lit(ray, &mut 0);
        prop_assert_eq!(lit, decided == Some(false));
        proven += lit as usize;
        prop_assert!(
            !(lit && expected),
            "{surface} block {block}: proven lit but mipmap occluded: {ray:?}"
        );
        prop_assert!(
            !(lit && naive.occluded(ray)),
            "{surface} block {block}: proven lit but naive occluded: {ray:?}"
        );
        if decided == Some(true) {
            prop_assert!(expected, "{surface} block {block}: proven occluded but lit: {ray:?}");
            prop_assert!(
                naive.occluded(ray),
                "{surface} block {block}: proven occluded, naive lit"
            );
        }
        prop_assert_eq!(shadows.occluded(ray), expected, "{} {:?}", surface, ray);
        prop_assert_eq!(naive_shadows.occluded(ray), naive.occluded(ray), "{} {:?}", surface, ray);
    }
    let mut batch = vec![true; rays.len()];
    let mut steps = vec![0; rays.len()];
    shadows.occluded_batch(rays, &mut batch, &mut steps);
    let mut plain = vec![true; rays.len()];
    mipmap.occluded_batch(rays, &mut plain, &mut vec![0; rays.len()]);
    prop_assert_eq!(&batch, &plain, "{} batch", surface);
    let mut decided = vec![None; rays.len()];
    shadows.decide_batch(rays, &mut decided, &mut vec![0; rays.len()]);
    for (ray, decision) in rays.iter().zip(decided) {
        prop_assert_eq!(decision, shadows.decide(ray, &mut 0), "{} decide_batch", surface);
    }
    // Short walks: most undecided rays are traced from where their walk stopped.
    for cells in [1, 2, 3] {
        let short = SunShadows::with_block(&mipmap, field.clone(), towards_sun, block)
            .unwrap()
            .with_walk_cells(cells);
        let naive_short = SunShadows::with_block(&naive, field.clone(), towards_sun, block)
            .unwrap()
            .with_walk_cells(cells);
        let mut batch = vec![true; rays.len()];
        short.occluded_batch(rays, &mut batch, &mut vec![0; rays.len()]);
        prop_assert_eq!(&batch, &plain, "{} walks of {} cells, batch", surface, cells);
        for ray in rays {
            prop_assert_eq!(short.occluded(ray), mipmap.occluded(ray), "{} {:?}", surface, ray);
            prop_assert_eq!(
                naive_short.occluded(ray),
                naive.occluded(ray),
                "{} {:?}",
                surface,
                ray
            );
        }
    }
    Ok(proven)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    #[test]
    fn sweep_decisions_equal_traced_shadow_rays(
        field in terrain(),
        azimuth in azimuth(),
        elevation in elevation(),
        block in 1usize..=4,
        numbers in prop::collection::vec(prop::array::uniform8(0.001f64..0.999), 48),
        lifts in prop::collection::vec(prop_oneof![Just(0.0), Just(1e-5), 1e-9f64..1e-2], 48),
    ) {
        let field = Arc::new(field);
        let towards_sun = sun(azimuth, elevation);
        for surface in Surface::ALL {
            let mipmap = MipmapTracer::new(field.clone(), surface);
            let mut rays = Vec::new();
            for (i, (u, lift)) in numbers.iter().zip(&lifts).enumerate() {
                // From surface points, as relief-shade makes them.
                let camera = ray_for(&field, ALL_KINDS[0], *u);
                rays.extend(surface_shadow_ray(&mipmap, &camera, *lift, towards_sun));
                // From anywhere: above, inside, below the surface, outside the grid.
                let other = ray_for(&field, ALL_KINDS[i % ALL_KINDS.len()], *u);
                rays.push(Ray { dir: towards_sun, ..other });
                // And some rays in other directions, which must just be traced.
                if i % 8 == 0 {
                    rays.push(other);
                }
            }
            check(&field, surface, towards_sun, block, &rays)?;
        }
    }
}

/// Smooth rolling hills with a geometry of its own.
fn hills(size: usize) -> Arc<HeightField> {
    let samples = (0..size * size)
        .map(|i| {
            let (x, y) = ((i % size) as f64, (i / size) as f64);
            (20.0 * (x / 9.0).sin() * (y / 13.0).cos() + 8.0 * ((x + 2.0 * y) / 17.0).sin()) as f32
        })
        .collect();
    let geometry = GridGeometry { dx: 2.0, dy: 2.0, ..GridGeometry::unit() };
    Arc::new(HeightField::new(size, size, samples, geometry).unwrap())
}

/// Shadow rays from the points a camera above the hills sees, towards `towards_sun`.
fn camera_shadow_rays(field: &HeightField, tracer: &dyn Tracer, towards_sun: DVec3) -> Vec<Ray> {
    let b = field.world_bounds(Surface::Triangles);
    let eye = DVec3::new(b.min.x - 10.0, b.min.y - 10.0, b.max.z + 60.0);
    let mut rays = Vec::new();
    for j in 0..40 {
        for i in 0..40 {
            let target = DVec3::new(
                b.min.x + (b.max.x - b.min.x) * (i as f64 + 0.5) / 40.0,
                b.min.y + (b.max.y - b.min.y) * (j as f64 + 0.5) / 40.0,
                b.min.z,
            );
            let camera = Ray::new(eye, (target - eye).normalize());
            rays.extend(surface_shadow_ray(tracer, &camera, 1e-5, towards_sun));
        }
    }
    rays
}

/// The sweep is worth its cost: on smooth hills it decides most lit shadow rays without
/// tracing (a sweep that decided nothing would still be exact, and fail here).
#[test]
fn sweep_decides_most_lit_rays_on_smooth_terrain() {
    let field = hills(128);
    for surface in Surface::ALL {
        for (azimuth, elevation) in [(315.0, 35.0), (90.0, 20.0), (200.0, 60.0)] {
            let towards_sun = sun(azimuth, elevation);
            let mipmap = MipmapTracer::new(field.clone(), surface);
            let rays = camera_shadow_rays(&field, &mipmap, towards_sun);
            for block in [1, 2, 4] {
                let shadows =
                    SunShadows::with_block(&mipmap, field.clone(), towards_sun, block).unwrap();
                let lit = rays.iter().filter(|r| !mipmap.occluded(r)).count();
                let mut steps = 0;
                let proven = rays.iter().filter(|r| shadows.proves_lit(r, &mut steps)).count();
                for ray in &rays {
                    let expected = mipmap.occluded(ray);
                    assert_eq!(shadows.occluded(ray), expected, "{ray:?}");
                    if let Some(decided) = shadows.decide(ray, &mut 0) {
                        assert_eq!(decided, expected, "{ray:?}");
                    }
                }
                let mut batch = vec![false; rays.len()];
                shadows.occluded_batch(&rays, &mut batch, &mut vec![0; rays.len()]);
                let plain: Vec<bool> = rays.iter().map(|r| mipmap.occluded(r)).collect();
                assert_eq!(batch, plain);
                let share = proven as f64 / lit as f64;
                assert!(
                    rays.len() > 1000 && share > 0.75,
                    "{surface} sun {azimuth}/{elevation} block {block}: {proven} of {lit} lit rays \
                     of {} proven ({steps} cells walked)",
                    rays.len()
                );
            }
        }
    }
}

#[test]
fn refuses_suns_below_the_horizon_and_empty_blocks() {
    let field = hills(8);
    let tracer = MipmapTracer::new(field.clone(), Surface::Boxes);
    for towards_sun in [DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, 0.0, -0.1), DVec3::NAN] {
        let refused = SunShadows::new(&tracer, field.clone(), towards_sun);
        assert!(matches!(refused, Err(TraceError::Options(_))), "{towards_sun}");
    }
    let refused = SunShadows::with_block(&tracer, field.clone(), DVec3::Z, 0);
    assert!(matches!(refused, Err(TraceError::Options(_))));
}

/// A single-row triangles surface has no cells: nothing to sweep, every ray traced.
#[test]
fn grids_without_cells_trace_everything() {
    let field = Arc::new(HeightField::new(5, 1, vec![1.0; 5], GridGeometry::unit()).unwrap());
    let tracer = MipmapTracer::new(field.clone(), Surface::Triangles);
    let shadows = SunShadows::new(&tracer, field, DVec3::new(0.5, 0.5, 0.7)).unwrap();
    let ray = Ray::new(DVec3::new(2.0, 0.5, 0.5), DVec3::new(0.5, 0.5, 0.7));
    assert!(!shadows.proves_lit(&ray, &mut 0));
    assert_eq!(shadows.occluded(&ray), tracer.occluded(&ray));
}
