//! The rasterizer against brute force: per-pixel distances against a ray-triangle test of
//! every triangle, and the fill rule (every pixel of a triangulated layer covered exactly once).

use proptest::prelude::*;
use relief_core::{Camera, DVec3, Projection, Ray};
use relief_mesh::{IndexedMesh, RasterTarget, Rasterizer, ScanLanes};

/// Möller-Trumbore: the ray parameter and the smallest barycentric coordinate (negative
/// outside the triangle).
fn ray_triangle(ray: &Ray, [a, b, c]: [DVec3; 3]) -> Option<(f64, f64)> {
    let (e1, e2) = (b - a, c - a);
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = ray.origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = ray.dir.dot(q) / det;
    let t = e2.dot(q) / det;
    // Smallest barycentric, as a fraction of the triangle's size seen from the ray.
    Some((t, u.min(v).min(1.0 - u - v)))
}

enum Expect {
    Miss,
    Hit(f64),
    Unclear,
}

/// The nearest hit among triangles, or `Unclear` when a triangle near its edge could change
/// the answer.
fn brute_force(ray: &Ray, mesh: &IndexedMesh) -> Expect {
    let margin = 1e-6;
    let (mut best, mut unclear_t) = (f64::INFINITY, f64::INFINITY);
    for k in 0..mesh.triangle_count() {
        let corners = mesh.corners(k as u32).unwrap();
        if let Some((t, bary)) = ray_triangle(ray, corners) {
            if t <= 1e-6 {
                continue;
            }
            if bary > margin {
                best = best.min(t);
            } else if bary > -margin {
                unclear_t = unclear_t.min(t);
            }
        }
    }
    if unclear_t <= best * (1.0 + 1e-6) {
        Expect::Unclear
    } else if best.is_finite() {
        Expect::Hit(best)
    } else {
        Expect::Miss
    }
}

fn camera_strategy() -> impl Strategy<Value = Camera> {
    (
        (-3.0..3.0f64, -3.0..3.0f64, -1.0..4.0f64),
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..0.5f64),
        prop_oneof![(20.0..120.0f64).prop_map(Some), Just(None)],
        (8u32..40, 8u32..40),
    )
        .prop_filter_map("degenerate camera", |(eye, target, fov, (w, h))| {
            let (eye, target) = (DVec3::from(eye), DVec3::from(target));
            let projection = match fov {
                Some(fov_deg) => Projection::Perspective { fov_deg },
                None => Projection::Orthographic { height: 4.0 },
            };
            Camera::new(eye, target, DVec3::Z, projection, w, h).ok()
        })
}

fn soup_strategy() -> impl Strategy<Value = IndexedMesh> {
    prop::collection::vec(((-2.0..2.0f64), (-2.0..2.0f64), (-1.0..2.0f64)), 3..30).prop_flat_map(
        |points| {
            let n = points.len() as u32;
            let positions: Vec<DVec3> = points.into_iter().map(DVec3::from).collect();
            prop::collection::vec([0..n, 0..n, 0..n], 1..20)
                .prop_map(move |triangles| IndexedMesh::new(positions.clone(), triangles).unwrap())
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Every pixel holds the nearest triangle's exact ray-plane distance, or nothing where no
    /// triangle is hit, including triangles reaching behind the eye.
    #[test]
    fn distances_equal_brute_force_on_triangle_soups(mesh in soup_strategy(), camera in camera_strategy()) {
        let mut target = RasterTarget::for_camera(&camera);
        Rasterizer::with_tile_size(8).unwrap().draw(&camera, &mesh, 7, &mut target).unwrap();
        for j in 0..camera.height() {
            for i in 0..camera.width() {
                let ray = camera.ray(i, j);
                let got = target.get(i as usize, j as usize);
                match (brute_force(&ray, &mesh), got) {
                    (Expect::Unclear, _) | (Expect::Miss, None) => {}
                    (Expect::Hit(t), Some((d, id))) => {
                        prop_assert!(((d as f64) - t).abs() <= 1e-6 * t, "pixel ({i}, {j}): {d} vs {t}");
                        prop_assert!(id >= 7 && id < 7 + mesh.triangle_count() as u32);
                        // The G-buffer's hit of that triangle gives the same distance.
                        let hit = mesh.hit(id - 7, &ray).unwrap();
                        prop_assert!((hit.t - d as f64).abs() <= 1e-6 * t);
                    }
                    (expect, got) => prop_assert!(false, "pixel ({i}, {j}): expected {} got {got:?}",
                        match expect { Expect::Hit(t) => format!("hit at {t}"), _ => "miss".into() }),
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Every way of scanning draws the same target, bit for bit: distances, triangles and
    /// barycentrics, two meshes drawn one after the other into the same target (the second
    /// tested against the first's distances), perspective and orthographic cameras,
    /// triangles reaching behind the eye.
    #[test]
    fn every_scan_draws_the_same_bits(
        first in soup_strategy(),
        second in soup_strategy(),
        camera in camera_strategy(),
        tile in prop_oneof![Just(8u32), Just(16), Just(64)],
    ) {
        let draw = |lanes: ScanLanes| {
            let rasterizer = Rasterizer::with_tile_size(tile).unwrap().with_lanes(lanes).unwrap();
            let mut target = RasterTarget::with_barycentrics(
                camera.width() as usize,
                camera.height() as usize,
            );
            rasterizer.draw(&camera, &first, 0, &mut target).unwrap();
            let offset = first.triangle_count() as u32;
            rasterizer.draw(&camera, &second, offset, &mut target).unwrap();
            target
        };
        let rows = draw(ScanLanes::Rows);
        for lanes in ScanLanes::ALL.into_iter().filter(|l| l.is_available()) {
            let other = draw(lanes);
            prop_assert_eq!(&other.triangle, &rows.triangle, "{:?}", lanes);
            let bits = |v: &[f32]| v.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&other.distance), bits(&rows.distance), "{:?}", lanes);
            for (a, b) in other.barycentrics.iter().zip(&rows.barycentrics) {
                prop_assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{:?}", lanes);
            }
        }
    }
}

#[test]
fn this_processor_runs_the_scans_the_tests_compare() {
    // Where AVX-512 is missing the proptest above compares the rows with themselves only:
    // say so, so that a run on such a machine is not read as a check of the blocks.
    let missing: Vec<_> = ScanLanes::ALL.into_iter().filter(|l| !l.is_available()).collect();
    if !missing.is_empty() {
        println!("not checked on this processor: {missing:?}");
    }
    assert!(ScanLanes::Rows.is_available());
    assert!(Rasterizer::new().with_lanes(ScanLanes::fastest()).is_ok());
}

/// A planar `n x n` grid of quads over `[0, size]^2` at height `z`, interior vertices jittered
/// by `jitter` (at most a fifth of a step, so no triangle folds over), boundary vertices slid along the boundary, each quad split along a random
/// diagonal, each triangle with a random winding.
fn jittered_grid(n: usize, size: f64, z: f64, jitter: &[f64], choices: &[bool]) -> IndexedMesh {
    let mut positions = Vec::new();
    let step = size / n as f64;
    for r in 0..=n {
        for c in 0..=n {
            let k = r * (n + 1) + c;
            let (mut x, mut y) = (c as f64 * step, r as f64 * step);
            let (jx, jy) = (jitter[2 * k % jitter.len()], jitter[(2 * k + 1) % jitter.len()]);
            let corner = (c == 0 || c == n) && (r == 0 || r == n);
            if !corner {
                if c > 0 && c < n {
                    x += jx * step * 0.2;
                }
                if r > 0 && r < n {
                    y += jy * step * 0.2;
                }
            }
            positions.push(DVec3::new(x, y, z));
        }
    }
    let mut triangles = Vec::new();
    for r in 0..n {
        for c in 0..n {
            let v = |dc: usize, dr: usize| ((r + dr) * (n + 1) + c + dc) as u32;
            let q = r * n + c;
            let pick = |k: usize| choices[k % choices.len()];
            let (a, b) = if pick(3 * q) {
                ([v(0, 0), v(1, 0), v(1, 1)], [v(0, 0), v(1, 1), v(0, 1)])
            } else {
                ([v(0, 0), v(1, 0), v(0, 1)], [v(1, 0), v(1, 1), v(0, 1)])
            };
            let flip = |t: [u32; 3], f: bool| if f { [t[0], t[2], t[1]] } else { t };
            triangles.push(flip(a, pick(3 * q + 1)));
            triangles.push(flip(b, pick(3 * q + 2)));
        }
    }
    IndexedMesh::new(positions, triangles).unwrap()
}

/// Checks that every pixel whose ray meets the plane `z = z0` inside `[0, size]^2` (by a
/// margin) is covered exactly once and every pixel clearly outside not at all.
fn check_once(
    camera: &Camera,
    mesh: &IndexedMesh,
    size: f64,
    z0: f64,
) -> Result<usize, TestCaseError> {
    let counts = Rasterizer::with_tile_size(16).unwrap().coverage_counts(camera, mesh);
    let mut inside_pixels = 0;
    for j in 0..camera.height() {
        for i in 0..camera.width() {
            let ray = camera.ray(i, j);
            let count = counts[(i + j * camera.width()) as usize];
            let t = (z0 - ray.origin.z) / ray.dir.z;
            let inside = if t > 1e-9 && t.is_finite() {
                let p = ray.at(t);
                let margin = 1e-7 * size;
                let d = p.x.min(p.y).min(size - p.x).min(size - p.y);
                if d.abs() <= margin {
                    continue;
                }
                d > 0.0
            } else {
                false
            };
            inside_pixels += inside as usize;
            prop_assert_eq!(count, inside as u32, "pixel ({}, {})", i, j);
        }
    }
    Ok(inside_pixels)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(150))]

    /// No pixel drawn twice by one layer's shared edges, none missing: jittered grids seen by
    /// random cameras, some of them low enough that the plane reaches behind the eye.
    #[test]
    fn a_triangulated_plane_covers_every_pixel_once(
        n in 1usize..7,
        jitter in prop::collection::vec(-1.0..1.0f64, 8..64),
        choices in prop::collection::vec(any::<bool>(), 8..64),
        camera in camera_strategy(),
    ) {
        let mesh = jittered_grid(n, 2.0, 0.25, &jitter, &choices);
        check_once(&camera, &mesh, 2.0, 0.25)?;
    }

    /// Edges through pixel centres exactly: an orthographic camera looking straight down on a
    /// grid whose vertices sit on pixel centres and corners, every tie decided by the
    /// top-left rule, once.
    #[test]
    fn pixel_centres_on_edges_are_covered_once(
        n in 1usize..9,
        choices in prop::collection::vec(any::<bool>(), 8..64),
        half in any::<bool>(),
    ) {
        // 16 x 16 pixels over [-4, 4]^2: pixel size 0.5, centres at odd multiples of 0.25.
        let projection = Projection::Orthographic { height: 8.0 };
        let camera = Camera::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y, projection, 16, 16).unwrap();
        let size = if half { 2.0 } else { 2.25 };
        let mesh = jittered_grid(n, size, 0.0, &[0.0], &choices);
        let counts = Rasterizer::new().coverage_counts(&camera, &mesh);
        for j in 0..16u32 {
            for i in 0..16u32 {
                let p = camera.ray(i, j).origin;
                let inside = p.x > 0.0 && p.y > 0.0 && p.x < size && p.y < size;
                let on_boundary = p.x == 0.0 || p.y == 0.0 || p.x == size || p.y == size;
                if !on_boundary {
                    prop_assert_eq!(counts[(i + 16 * j) as usize], inside as u32, "pixel ({}, {})", i, j);
                }
            }
        }
    }
}

#[test]
fn refuses_mismatched_targets_and_overflowing_ids() {
    let camera =
        Camera::look_at(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y, 30.0, 8, 8).unwrap();
    let mesh = jittered_grid(2, 1.0, 0.0, &[0.0], &[true]);
    let mut small = RasterTarget::new(4, 8);
    assert!(Rasterizer::new().draw(&camera, &mesh, 0, &mut small).is_err());
    let mut target = RasterTarget::for_camera(&camera);
    assert!(Rasterizer::new().draw(&camera, &mesh, u32::MAX - 4, &mut target).is_err());
    assert!(Rasterizer::with_tile_size(4).is_err() && Rasterizer::with_tile_size(512).is_err());
    assert!(Rasterizer::with_tile_size(48).is_err());
}

#[test]
fn the_result_does_not_depend_on_tiles_or_threads() {
    let camera = Camera::look_at(
        DVec3::new(0.2, -0.3, 0.3),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::Z,
        70.0,
        97,
        61,
    )
    .unwrap();
    let mesh = jittered_grid(12, 2.0, 0.0, &[0.3, -0.7, 0.1, 0.9, -0.2], &[true, false, false]);
    let draw = |tile: u32, threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let mut target = RasterTarget::for_camera(&camera);
        pool.install(|| {
            Rasterizer::with_tile_size(tile).unwrap().draw(&camera, &mesh, 0, &mut target).unwrap()
        });
        target
    };
    let reference = draw(64, 1);
    let drawn = reference.triangle.iter().filter(|&&t| t != RasterTarget::NO_TRIANGLE).count();
    assert!(drawn > 1000, "{drawn} pixels drawn");
    assert_eq!(draw(8, 2), reference);
    assert_eq!(draw(256, 3), reference);
}

#[test]
fn kept_barycentrics_are_those_of_the_rays_hit() {
    let mesh = jittered_grid(8, 2.0, 0.0, &[0.3, -0.7, 0.1, 0.9, -0.2], &[true, false, false]);
    let cameras = [
        Camera::look_at(
            DVec3::new(0.2, -0.3, 0.3),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::Z,
            70.0,
            97,
            61,
        ),
        Camera::new(
            DVec3::new(1.0, 1.0, 5.0),
            DVec3::new(1.1, 0.9, 0.0),
            DVec3::Y,
            Projection::Orthographic { height: 3.0 },
            64,
            48,
        ),
    ];
    for camera in cameras.map(Result::unwrap) {
        let mut target =
            RasterTarget::with_barycentrics(camera.width() as usize, camera.height() as usize);
        let mut plain = RasterTarget::for_camera(&camera);
        Rasterizer::new().draw(&camera, &mesh, 0, &mut target).unwrap();
        Rasterizer::new().draw(&camera, &mesh, 0, &mut plain).unwrap();
        assert_eq!((&target.distance, &target.triangle), (&plain.distance, &plain.triangle));
        let mut checked = 0;
        for (k, &id) in target.triangle.iter().enumerate() {
            if id == RasterTarget::NO_TRIANGLE {
                continue;
            }
            let (i, j) = ((k % target.width) as u32, (k / target.width) as u32);
            let hit = mesh.hit(id, &camera.ray(i, j)).unwrap();
            let [b1, b2] = target.barycentrics[k];
            assert!(
                (0.0..=1.0).contains(&b1) && (0.0..=1.0).contains(&b2) && b1 + b2 <= 1.0 + 1e-6
            );
            let off = (b1 as f64 - hit.barycentrics[1])
                .abs()
                .max((b2 as f64 - hit.barycentrics[2]).abs());
            assert!(off < 1e-5, "pixel ({i}, {j}): {:?} against {:?}", [b1, b2], hit.barycentrics);
            checked += 1;
        }
        assert!(checked > 1000, "{checked} pixels checked");
    }
}
