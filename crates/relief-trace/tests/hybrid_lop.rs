//! The hybrid renderer's ray casting in proxy boxes (linear then binary search): with many
//! steps it converges to the exact tracer's hit on smooth terrain; with few it misses thin
//! crests, as the paper says; holes are no surface and their walls are met from the side.

use relief_core::{Camera, DVec2, DVec3, GridGeometry, HeightField, Ray, Surface};
use relief_trace::hybrid::{box_entry, lop_cast, HybridCells, LopSteps};
use relief_trace::{Hit, MipmapTracer, NaiveTracer, Tracer};
use std::sync::Arc;

/// The nearest of the hits in every cell's box, as the renderer's depth test keeps it.
fn nearest_lop_hit(
    field: &HeightField,
    cells: &HybridCells,
    ray: &Ray,
    steps: LopSteps,
) -> Option<Hit> {
    (0..cells.len())
        .filter_map(|k| lop_cast(field, cells, k, ray, steps))
        .min_by(|a, b| a.t.total_cmp(&b.t))
}

fn smooth_field() -> HeightField {
    let (w, h) = (41, 37);
    let samples = (0..w * h)
        .map(|k| {
            let (x, y) = ((k % w) as f64, (k / w) as f64);
            (6.0 + 3.0 * (x / 6.0).sin() * (y / 8.0).cos() + 0.05 * x) as f32
        })
        .collect();
    let geometry = GridGeometry { dx: 1.5, dy: 1.25, z_scale: 0.8, origin: DVec2::new(-20.0, 7.0) };
    HeightField::new(w, h, samples, geometry).unwrap()
}

#[test]
fn many_steps_converge_to_the_exact_hit_on_smooth_terrain() {
    let field = Arc::new(smooth_field());
    let b = field.world_bounds(Surface::Boxes);
    let centre = b.center();
    // Looking down at 50 degrees onto the middle: every pixel sees terrain.
    let eye = centre + DVec3::new(-25.0, -20.0, 35.0);
    let camera =
        Camera::look_at(eye, DVec3::new(centre.x, centre.y, b.min.z), DVec3::Z, 30.0, 32, 24)
            .unwrap();
    let fine = LopSteps { linear: 3000, binary: 52 };
    for surface in Surface::ALL {
        let exact = MipmapTracer::new(field.clone(), surface);
        for n in [9, 16] {
            let cells = HybridCells::new(&field, surface, n).unwrap();
            let (mut same_normal, mut hits) = (0, 0);
            for j in 0..camera.height() {
                for i in 0..camera.width() {
                    let ray = camera.ray(i, j);
                    let (e, l) = match (
                        exact.intersect(&ray),
                        nearest_lop_hit(&field, &cells, &ray, fine),
                    ) {
                        (Some(e), Some(l)) => (e, l),
                        (None, None) => continue,
                        (e, l) => panic!("{surface} n {n} ({i}, {j}): {l:?} vs exact {e:?}"),
                    };
                    hits += 1;
                    assert!(
                        (l.t - e.t).abs() <= 1e-7 * e.t,
                        "{surface} n {n} ({i}, {j}): {l:?} vs {e:?}"
                    );
                    same_normal += ((l.normal - e.normal).length() < 1e-6) as usize;
                    // The exact hit lies in a box the ray enters no later than it.
                    let entries =
                        (0..cells.len()).filter_map(|k| box_entry(&cells, &field, k, &ray));
                    assert!(entries.map(|(t0, _)| t0).fold(f64::INFINITY, f64::min) <= e.t);
                }
            }
            // Only hits on a triangle's edge may take the other triangle's normal.
            let pixels = (camera.width() * camera.height()) as usize;
            assert!(
                hits * 10 >= pixels * 9,
                "{surface} n {n}: {hits} of {pixels} pixels see terrain"
            );
            assert!(
                same_normal * 100 >= hits * 98,
                "{surface} n {n}: {same_normal} of {hits} normals"
            );
        }
    }
}

/// 17 x 5 samples, flat at 0 but for a ridge of height 10 in column 8.
fn ridge() -> HeightField {
    let samples = (0..17 * 5).map(|k| if k % 17 == 8 { 10.0 } else { 0.0 }).collect();
    HeightField::new(17, 5, samples, GridGeometry::unit()).unwrap()
}

#[test]
fn few_steps_miss_a_thin_crest_that_many_steps_find() {
    let field = Arc::new(ridge());
    // Level with z = 9 along the middle row: the ridge is 0.2 wide there for triangles.
    let ray = Ray::new(DVec3::new(-3.0, 2.5, 9.0), DVec3::X);
    for (surface, x_hit, normal) in
        [(Surface::Triangles, 8.4, None), (Surface::Boxes, 8.0, Some(-DVec3::X))]
    {
        let exact = NaiveTracer::new(field.clone(), surface).intersect(&ray).unwrap();
        assert!((exact.position.x - x_hit).abs() < 1e-12, "{surface}: {exact:?}");
        let cells = HybridCells::new(&field, surface, 17).unwrap();
        assert_eq!(cells.len(), 1);
        let coarse = lop_cast(&field, &cells, 0, &ray, LopSteps { linear: 3, binary: 5 });
        assert!(coarse.is_none(), "{surface}: 3 steps jump over the ridge, got {coarse:?}");
        let fine = lop_cast(&field, &cells, 0, &ray, LopSteps { linear: 64, binary: 40 }).unwrap();
        assert!((fine.t - exact.t).abs() < 1e-9, "{surface}: {fine:?} vs {exact:?}");
        assert!((fine.normal - exact.normal).length() < 1e-9, "{surface}: {fine:?} vs {exact:?}");
        if let Some(n) = normal {
            assert_eq!(fine.normal, n);
        }
        // Two steps happen to land on the ridge: found, then refined by the binary search.
        let two = lop_cast(&field, &cells, 0, &ray, LopSteps { linear: 2, binary: 40 }).unwrap();
        assert!((two.t - exact.t).abs() < 1e-9, "{surface}: {two:?} vs {exact:?}");
    }
}

#[test]
fn holes_are_no_surface_and_their_walls_are_met_from_the_side() {
    // 5 x 5 at height 3 (one sample at 0 sets the floor), the texel (2, 2) a hole.
    let mut samples = vec![3.0f32; 25];
    samples[0] = 0.0;
    let mut holes = vec![false; 25];
    holes[2 + 2 * 5] = true;
    let field = HeightField::new(5, 5, samples, GridGeometry::unit()).unwrap();
    let field = Arc::new(field.with_holes(holes).unwrap());
    let cells = HybridCells::new(&field, Surface::Boxes, 5).unwrap();
    let exact = NaiveTracer::new(field.clone(), Surface::Boxes);
    let steps = LopSteps { linear: 200, binary: 40 };
    // Straight down through the hole: nothing.
    let down = Ray::new(DVec3::new(2.5, 2.5, 10.0), -DVec3::Z);
    assert!(exact.intersect(&down).is_none());
    assert!(lop_cast(&field, &cells, 0, &down, steps).is_none());
    // Into the hole and against the wall of texel (3, 2).
    let slanted = Ray::new(DVec3::new(2.1, 2.5, 3.5), DVec3::new(1.0, 0.0, -1.0).normalize());
    let e = exact.intersect(&slanted).unwrap();
    let l = lop_cast(&field, &cells, 0, &slanted, steps).unwrap();
    assert_eq!(e.normal, -DVec3::X);
    assert!((l.t - e.t).abs() < 1e-9 && l.normal == e.normal, "{l:?} vs {e:?}");
    // Next to the hole, the top.
    let beside = Ray::new(DVec3::new(1.5, 2.5, 10.0), -DVec3::Z);
    let l = lop_cast(&field, &cells, 0, &beside, LopSteps { linear: 4, binary: 0 }).unwrap();
    assert_eq!((l.t, l.normal), (7.0, DVec3::Z));
}

#[test]
fn from_below_the_floor_the_bottom_is_hit_in_boxes_reaching_it() {
    let field = Arc::new(smooth_field());
    let floor = field.min_sample() as f64 * field.geometry().z_scale;
    let ray = Ray::new(DVec3::new(10.0, 30.0, floor - 5.0), DVec3::new(0.1, 0.2, 1.0).normalize());
    for surface in Surface::ALL {
        let exact = NaiveTracer::new(field.clone(), surface).intersect(&ray).unwrap();
        assert_eq!(exact.normal, -DVec3::Z);
        let mut cells = HybridCells::new(&field, surface, 8).unwrap();
        let steps = LopSteps { linear: 8, binary: 5 };
        cells.set_floor_everywhere(true);
        let l = nearest_lop_hit(&field, &cells, &ray, steps).unwrap();
        assert!(
            (l.t - exact.t).abs() < 1e-9 && l.normal == -DVec3::Z,
            "{surface}: {l:?} vs {exact:?}"
        );
        // Tight boxes do not reach down there: the ray meets the solid only inside it.
        cells.set_floor_everywhere(false);
        let inner = nearest_lop_hit(&field, &cells, &ray, steps).unwrap();
        assert!(inner.t > exact.t + 1.0, "{surface}: {inner:?}");
    }
}
