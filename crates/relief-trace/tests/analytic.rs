//! Analytic scenes: hit distances of every tracer equal the closed form.

use relief_core::{DVec2, DVec3, GridGeometry, HeightField, Ray, Surface};
use relief_trace::{build_tracer, TracerKind};
use std::sync::Arc;

fn field(
    w: usize,
    h: usize,
    geometry: GridGeometry,
    f: impl Fn(usize, usize) -> f32,
) -> Arc<HeightField> {
    let samples = (0..w * h).map(|i| f(i % w, i / w)).collect();
    Arc::new(HeightField::new(w, h, samples, geometry).unwrap())
}

fn assert_close(got: Option<f64>, want: f64, what: &str) {
    let got = got.unwrap_or_else(|| panic!("{what}: missed, expected {want}"));
    assert!((got - want).abs() <= 1e-9 * want.abs().max(1.0), "{what}: got {got}, expected {want}");
}

fn every_tracer(
    surfaces: &[Surface],
    f: Arc<HeightField>,
    mut check: impl FnMut(&dyn relief_trace::Tracer, &str),
) {
    for &surface in surfaces {
        for kind in TracerKind::ALL {
            let tracer = build_tracer(f.clone(), surface, kind);
            check(tracer.as_ref(), &format!("{surface}/{kind}"));
        }
    }
}

#[test]
fn flat_plane_is_hit_at_the_closed_form_distance() {
    let g = GridGeometry { dx: 2.0, dy: 3.0, z_scale: 0.5, origin: DVec2::new(-10.0, 5.0) };
    let f = field(40, 30, g, |_, _| 10.0); // world height 5
    let dir = DVec3::new(0.3, 0.2, -1.0).normalize();
    let ray = Ray::new(DVec3::new(20.0, 40.0, 25.0), dir);
    every_tracer(&Surface::ALL, f, |t, name| {
        let hit = t.intersect(&ray);
        assert_close(hit.map(|h| h.t), 20.0 / -dir.z, name);
        assert!((hit.unwrap().normal - DVec3::Z).length() < 1e-12, "{name}: normal");
    });
}

#[test]
fn tilted_plane_matches_the_triangles_surface_exactly() {
    // Samples of z = 0.25 x (world) lie on one plane: the triangles reproduce it.
    let g = GridGeometry { dx: 1.5, dy: 1.0, z_scale: 1.0, origin: DVec2::ZERO };
    let f = field(50, 20, g, |c, _| (0.25 * (c as f64 + 0.5) * 1.5) as f32);
    let o = DVec3::new(10.0, 10.0, 40.0);
    let dir = DVec3::new(0.6, 0.1, -0.8).normalize();
    // o.z + t d.z = 0.25 (o.x + t d.x)  =>  t = (0.25 o.x - o.z) / (d.z - 0.25 d.x)
    let want = (0.25 * o.x - o.z) / (dir.z - 0.25 * dir.x);
    every_tracer(&[Surface::Triangles], f, |t, name| {
        let hit = t.intersect(&Ray::new(o, dir)).unwrap();
        assert_close(Some(hit.t), want, name);
        let n = DVec3::new(-0.25, 0.0, 1.0).normalize();
        assert!((hit.normal - n).length() < 1e-9, "{name}: normal {}", hit.normal);
    });
}

#[test]
fn single_spike_blocks_a_horizontal_ray_at_its_wall() {
    let f = field(9, 9, GridGeometry::unit(), |c, r| if (c, r) == (4, 4) { 10.0 } else { 0.0 });
    let along_x = Ray::new(DVec3::new(-3.0, 4.5, 5.0), DVec3::X);
    let down = Ray::new(DVec3::new(4.5, 4.5, 30.0), -DVec3::Z);
    let beside = Ray::new(DVec3::new(-3.0, 3.5, 5.0), DVec3::X);
    every_tracer(&[Surface::Boxes], f.clone(), |t, name| {
        let hit = t.intersect(&along_x).unwrap();
        assert_close(Some(hit.t), 7.0, name);
        assert_eq!(hit.normal, -DVec3::X, "{name}");
        assert_close(t.intersect(&down).map(|h| h.t), 20.0, name);
        assert!(t.intersect(&beside).is_none(), "{name}: ray beside the spike");
    });
    // Triangles: the spike is a pyramid of four faces rising from the neighbouring samples.
    // Along row y = 4.5 (through the apex) the face rises by 10 per texel from x = 3.5.
    every_tracer(&[Surface::Triangles], f, |t, name| {
        assert_close(t.intersect(&along_x).map(|h| h.t), 3.0 + 3.5 + 0.5, name);
        assert_close(t.intersect(&down).map(|h| h.t), 20.0, name);
    });
}

#[test]
fn pyramid_face_is_hit_at_the_closed_form_distance() {
    // h = 40 - 4 * max(|x - 10|, |y - 10|) in grid units around sample (10, 10)'s centre.
    let g = GridGeometry::unit();
    let f = field(21, 21, g, |c, r| {
        let (x, y) = (c as f32 - 10.0, r as f32 - 10.0);
        40.0 - 4.0 * x.abs().max(y.abs())
    });
    // Above the east face (x - 10 > |y - 10| + 1), where the surface is the plane 40 - 4 (x - 10).
    let (x, y) = (10.5 + 6.3, 10.5 + 1.2);
    let down = Ray::new(DVec3::new(x, y, 100.0), -DVec3::Z);
    let want = 100.0 - (40.0 - 4.0 * (x - 10.5));
    every_tracer(&[Surface::Triangles], f.clone(), |t, name| {
        assert_close(t.intersect(&down).map(|h| h.t), want, name);
    });
    // Boxes: the texel under the ray is a flat column at its own sample.
    every_tracer(&[Surface::Boxes], f, |t, name| {
        assert_close(t.intersect(&down).map(|h| h.t), 100.0 - (40.0 - 4.0 * 6.0), name);
    });
}

#[test]
fn rays_pass_through_holes_and_hit_their_walls() {
    // A 9 x 9 plateau at height 4 (one corner sample at 0, so walls reach down to 0) with a
    // 3 x 3 hole in the middle (texels 3..6).
    let f = field(9, 9, GridGeometry::unit(), |c, r| if c + r == 0 { 0.0 } else { 4.0 });
    let holes = (0..81).map(|k| (3..6).contains(&(k % 9)) && (3..6).contains(&(k / 9))).collect();
    let f = Arc::new(Arc::try_unwrap(f).unwrap().with_holes(holes).unwrap());
    let down_the_hole = Ray::new(DVec3::new(4.5, 4.5, 10.0), -DVec3::Z);
    let into_the_wall = Ray::new(DVec3::new(4.5, 4.5, 3.0), DVec3::X);
    let across_the_hole =
        Ray::new(DVec3::new(4.5, 4.5, 5.0), DVec3::new(1.0, 0.0, -1.0).normalize());
    every_tracer(&[Surface::Boxes], f.clone(), |t, name| {
        assert!(t.intersect(&down_the_hole).is_none(), "{name}: the hole has no floor");
        let wall = t.intersect(&into_the_wall).unwrap();
        assert_close(Some(wall.t), 1.5, name);
        assert_eq!(wall.normal, -DVec3::X, "{name}");
        // Sinks into the hole and meets its east wall at x = 6, z = 3.5.
        let hit = t.intersect(&across_the_hole).unwrap();
        assert_close(Some(hit.t), 1.5 * 2f64.sqrt(), name);
        assert_eq!(hit.normal, -DVec3::X, "{name}");
    });
    // Triangles: squares touching a hole sample are empty too; the hole spans 2.5..6.5.
    every_tracer(&[Surface::Triangles], f, |t, name| {
        assert!(t.intersect(&down_the_hole).is_none(), "{name}: the hole has no floor");
        let wall = t.intersect(&into_the_wall).unwrap();
        assert_close(Some(wall.t), 2.0, name);
        assert_eq!(wall.normal, -DVec3::X, "{name}");
    });
}

#[test]
fn a_flat_floor_at_the_lowest_height_is_never_missed() {
    // Flat at 0 (the minimum, so the floor lies on the bounding box's bottom face) with one
    // hill; rays from above land on a dense lattice that includes exact cell boundaries.
    let g = GridGeometry { dx: 0.7, dy: 1.3, z_scale: 1.1, origin: DVec2::new(-3.0, 2.0) };
    let f = field(16, 12, g, |c, r| if c > 12 && r > 8 { 5.0 } else { 0.0 });
    let t_bounds = |s: Surface| f.world_bounds(s);
    every_tracer(&Surface::ALL, f.clone(), |t, name| {
        for i in 0..=40 {
            for j in 0..=40 {
                let target = DVec3::new(
                    -3.0 + 0.7 * (0.5 + i as f64 * 0.25),
                    2.0 + 1.3 * (0.5 + j as f64 * 0.2),
                    0.0,
                );
                for dir in [DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.3, -0.2, -1.0).normalize()] {
                    let origin = target - dir * 20.0;
                    if let Some(hit) = t.intersect(&Ray::new(origin, dir)) {
                        assert!(hit.t <= 20.0 + 1e-9, "{name}: hit beyond the floor at {target}");
                    } else {
                        // Only the footprint's own edge is a tie (the silhouette of its wall).
                        let b = t_bounds(t.surface());
                        let inside = target.x > b.min.x + 1e-9
                            && target.x < b.max.x - 1e-9
                            && target.y > b.min.y + 1e-9
                            && target.y < b.max.y - 1e-9;
                        assert!(!inside, "{name}: missed the floor at {target} along {dir}");
                    }
                }
            }
        }
    });
}
